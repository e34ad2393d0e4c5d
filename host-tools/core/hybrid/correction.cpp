#include "host-tools/core/hybrid/correction.hpp"

#include "host-tools/core/hybrid/hat_basis.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>

#include <Eigen/Cholesky>
#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include "host-tools/core/hybrid/spectra.hpp"

namespace amb::host::hybrid {

const char* correction_feature_name(int j) {
  static const char* names[k_correction_features] = {"base_lines", "base_level", "fixed_lines", "sim_lines", "sim_level"};
  return j >= 0 && j < k_correction_features ? names[j] : "?";
}

bool CorrectionOptions::valid(std::string* why) const {
  auto fail = [&](const char* m) {
    if (why) *why = m;
    return false;
  };
  if (features >= (1u << k_correction_features)) return fail("unknown correction feature bit");
  if (bands < 1 || bands > 64) return fail("correction bands in [1, 64]");
  if (offset_spacing_bins < 0 || offset_spacing_bins > 1000) return fail("correction offset spacing in [0, 1000]");
  if (local_halfwidth_bins < 1 || local_halfwidth_bins > 100) return fail("correction local half-width in [1, 100]");
  if (!(lambda > 0) || !std::isfinite(lambda)) return fail("correction lambda must be > 0");
  return true;
}

std::string CorrectionOptions::describe() const {
  if (features == 0 && offset_spacing_bins == 0) return "none (the interpolated transport)";
  std::string s;
  for (int j = 0; j < k_correction_features; ++j)
    if (features & (1u << j)) s += (s.empty() ? "" : "+") + std::string(correction_feature_name(j));
  if (s.empty()) s = "offset only";
  char b[128];
  std::snprintf(b, sizeof b, ", %d band(s), offset %s, lambda %g", bands,
                offset_spacing_bins > 0 ? std::to_string(offset_spacing_bins).c_str() : "none", lambda);
  return s + b;
}

namespace {


double mean_abs(const std::vector<double>& y) {
  double s = 0.0;
  for (double v : y) s += std::abs(v);
  return y.empty() || s <= 0 ? 1.0 : s / static_cast<double>(y.size());
}

std::vector<double> mean_of(const std::vector<std::vector<double>>& v) {
  std::vector<double> m(v.front().size(), 0.0);
  for (const auto& s : v)
    for (size_t k = 0; k < m.size(); ++k) m[k] += s[k] / static_cast<double>(v.size());
  return m;
}

}  // namespace

size_t Correction::offset_hats() const {
  if (o_.offset_spacing_bins <= 0 || bins_ < 2) return 0;
  const auto sp = static_cast<size_t>(o_.offset_spacing_bins);
  return std::max<size_t>(2, (bins_ - 1 + sp - 1) / sp + 1);
}

size_t Correction::unknowns() const {
  size_t used = 0;
  for (int j = 0; j < k_correction_features; ++j)
    if (o_.features & (1u << j)) ++used;
  return used * static_cast<size_t>(o_.bands) + offset_hats();
}

// Raw (unscaled) features of the used set at every bin: f[k][u], u over used features.
void Correction::features(const CorrectionCase& c, std::vector<std::vector<double>>& f) const {
  if (c.base.size() != bins_ || c.fixed.size() != bins_ || c.sim.size() != bins_)
    throw std::invalid_argument("correction: an input spectrum has the wrong number of bins");
  const int h = o_.local_halfwidth_bins;
  const auto lb = local_mean(c.base, h), lf = local_mean(c.fixed, h), ls = local_mean(c.sim, h);
  f.assign(bins_, {});
  for (size_t k = 0; k < bins_; ++k) {
    const double all[k_correction_features] = {c.base[k] - lb[k], lb[k], c.fixed[k] - lf[k], c.sim[k] - ls[k], ls[k]};
    for (int j = 0; j < k_correction_features; ++j)
      if (o_.features & (1u << j)) f[k].push_back(all[j]);
  }
}

void Correction::train(const std::vector<CorrectionCase>& cases, const CorrectionOptions& o,
                       const std::vector<double>* weights) {
  std::string why;
  if (!o.valid(&why)) throw std::invalid_argument("correction: " + why);
  if (cases.empty() || cases.front().base.empty()) throw std::invalid_argument("correction: no training case");
  o_ = o;
  bins_ = cases.front().base.size();
  size_t rows = 0;
  for (const auto& c : cases) {
    if (c.segments.empty()) throw std::invalid_argument("correction: a case has no measured segment");
    for (const auto& s : c.segments)
      if (s.size() != bins_) throw std::invalid_argument("correction: a measured segment has the wrong number of bins");
    rows += c.segments.size();
  }
  if (weights != nullptr && weights->size() != rows) throw std::invalid_argument("correction: one weight per segment");
  change_max_ = 0.0;
  for (const auto& c : cases) {
    if (!(c.speed_change > 0) || !std::isfinite(c.speed_change))
      throw std::invalid_argument("correction: a training case has no speed change (its source is its own operating point)");
    change_max_ = std::max(change_max_, c.speed_change);
  }
  // Features per case; their rms over the training rows standardises them.
  std::vector<std::vector<std::vector<double>>> feat(cases.size());
  size_t used = 0;
  for (int j = 0; j < k_correction_features; ++j)
    if (o_.features & (1u << j)) ++used;
  std::vector<double> ss(used, 0.0);
  double wsum = 0.0;
  {
    size_t r = 0;
    for (size_t c = 0; c < cases.size(); ++c) {
      features(cases[c], feat[c]);
      const double d = cases[c].speed_change / change_max_;
      for (auto& fk : feat[c])
        for (double& v : fk) v *= d;
      double wc = 0.0;
      for (size_t s = 0; s < cases[c].segments.size(); ++s, ++r) wc += weights ? (*weights)[r] : 1.0;
      for (size_t k = 0; k < bins_; ++k)
        for (size_t u = 0; u < used; ++u) ss[u] += wc * feat[c][k][u] * feat[c][k][u];
      wsum += wc;
    }
  }
  scale_.assign(used, 1.0);
  for (size_t u = 0; u < used; ++u) {
    const double rms = std::sqrt(ss[u] / std::max(1e-300, wsum * static_cast<double>(bins_)));
    scale_[u] = rms > 1e-12 ? rms : 0.0;
  }
  const size_t nb = static_cast<size_t>(o_.bands), nh = offset_hats(), dim = unknowns();
  w_.assign(dim, 0.0);
  if (dim == 0) return;
  Eigen::MatrixXd ata = Eigen::MatrixXd::Zero(static_cast<long>(dim), static_cast<long>(dim));
  Eigen::VectorXd aty = Eigen::VectorXd::Zero(static_cast<long>(dim));
  std::vector<long> idx;
  std::vector<double> val;
  size_t r = 0;
  for (size_t c = 0; c < cases.size(); ++c) {
    // Every segment of a case has the same inputs: accumulate the row once with the summed
    // weight and the weighted mean target.
    double wc = 0.0;
    std::vector<double> ybar(bins_, 0.0);
    for (const auto& s : cases[c].segments) {
      const double w = weights ? (*weights)[r] : 1.0;
      ++r;
      wc += w;
      for (size_t k = 0; k < bins_; ++k) ybar[k] += w * s[k];
    }
    if (wc <= 0) continue;
    for (size_t k = 0; k < bins_; ++k) {
      const double resid = ybar[k] / wc - cases[c].base[k];
      idx.clear();
      val.clear();
      const Hat hb = hat(k, bins_, nb);
      for (size_t u = 0; u < used; ++u) {
        if (scale_[u] == 0.0) continue;
        const double x = feat[c][k][u] / scale_[u];
        idx.push_back(static_cast<long>(hb.knot * used + u));
        val.push_back(hb.w * x);
        if (nb > 1 && hb.w < 1.0) {
          idx.push_back(static_cast<long>((hb.knot + 1) * used + u));
          val.push_back((1.0 - hb.w) * x);
        }
      }
      if (nh > 0) {
        const double d = cases[c].speed_change / change_max_;
        const Hat ht = hat(k, bins_, nh);
        idx.push_back(static_cast<long>(nb * used + ht.knot));
        val.push_back(d * ht.w);
        if (ht.w < 1.0) {
          idx.push_back(static_cast<long>(nb * used + ht.knot + 1));
          val.push_back(d * (1.0 - ht.w));
        }
      }
      for (size_t a = 0; a < idx.size(); ++a) {
        aty(idx[a]) += wc * val[a] * resid;
        for (size_t b = 0; b < idx.size(); ++b) ata(idx[a], idx[b]) += wc * val[a] * val[b];
      }
    }
  }
  const double n = std::max(1e-300, wsum * static_cast<double>(bins_));
  ata /= n;
  aty /= n;
  for (size_t i = 0; i < dim; ++i) ata(static_cast<long>(i), static_cast<long>(i)) += o_.lambda;
  const Eigen::VectorXd theta = ata.ldlt().solve(aty);
  for (size_t i = 0; i < dim; ++i) w_[i] = theta(static_cast<long>(i));
}

std::vector<double> Correction::predict(const CorrectionCase& in) const {
  if (!trained()) throw std::logic_error("correction: not trained");
  std::vector<std::vector<double>> f;
  features(in, f);
  const size_t used = scale_.size(), nb = static_cast<size_t>(o_.bands), nh = offset_hats();
  std::vector<double> y = in.base;
  if (!(in.speed_change >= 0) || !std::isfinite(in.speed_change))
    throw std::invalid_argument("correction: the speed change must be finite and >= 0");
  const double d = change_max_ > 0 ? std::min(in.speed_change, change_max_) / change_max_ : 0.0;
  if (d == 0.0) return y;
  for (size_t k = 0; k < bins_; ++k) {
    double corr = 0.0;
    const Hat hb = hat(k, bins_, nb);
    for (size_t u = 0; u < used; ++u) {
      if (scale_[u] == 0.0) continue;
      const double x = f[k][u] / scale_[u];
      double g = hb.w * w_[hb.knot * used + u];
      if (nb > 1 && hb.w < 1.0) g += (1.0 - hb.w) * w_[(hb.knot + 1) * used + u];
      corr += g * x;
    }
    if (nh > 0) {
      const Hat ht = hat(k, bins_, nh);
      corr += ht.w * w_[nb * used + ht.knot] + (ht.w < 1.0 ? (1.0 - ht.w) * w_[nb * used + ht.knot + 1] : 0.0);
    }
    y[k] += d * corr;
  }
  return y;
}

nlohmann::json Correction::to_json() const {
  return {{"features", o_.features},
          {"bands", o_.bands},
          {"offset_spacing_bins", o_.offset_spacing_bins},
          {"local_halfwidth_bins", o_.local_halfwidth_bins},
          {"lambda", o_.lambda},
          {"bins", bins_},
          {"speed_change_max", change_max_},
          {"scale", scale_},
          {"w", w_}};
}

Correction Correction::from_json(const nlohmann::json& j) {
  Correction c;
  c.o_.features = j.at("features").get<unsigned>();
  c.o_.bands = j.at("bands");
  c.o_.offset_spacing_bins = j.at("offset_spacing_bins");
  c.o_.local_halfwidth_bins = j.at("local_halfwidth_bins");
  c.o_.lambda = j.at("lambda");
  std::string why;
  if (!c.o_.valid(&why)) throw std::invalid_argument("correction: " + why);
  c.bins_ = j.at("bins");
  c.change_max_ = j.at("speed_change_max");
  if (!(c.change_max_ > 0) || !std::isfinite(c.change_max_)) throw std::invalid_argument("correction: speed_change_max must be > 0");
  c.scale_ = j.at("scale").get<std::vector<double>>();
  c.w_ = j.at("w").get<std::vector<double>>();
  size_t used = 0;
  for (int f = 0; f < k_correction_features; ++f)
    if (c.o_.features & (1u << f)) ++used;
  if (c.bins_ < 2 || c.scale_.size() != used || c.w_.size() != c.unknowns())
    throw std::invalid_argument("correction: weights do not match its options");
  for (double v : c.w_)
    if (!std::isfinite(v)) throw std::invalid_argument("correction: a weight is not finite");
  return c;
}

CvResult select_correction(const std::vector<CorrectionCase>& cases, const std::vector<CorrectionOptions>& candidates) {
  std::vector<int> groups;
  for (const auto& c : cases)
    if (std::find(groups.begin(), groups.end(), c.group) == groups.end()) groups.push_back(c.group);
  if (groups.size() < 2) throw std::invalid_argument("correction: inner cross-validation needs two operating points");
  CvResult res;
  // The baseline's own held-out score.
  double base_sum = 0.0;
  size_t n = 0;
  for (const auto& c : cases) {
    base_sum += pearson(c.base, mean_of(c.segments));
    ++n;
  }
  res.baseline_pearson = base_sum / static_cast<double>(n);
  res.chosen_pearson = res.baseline_pearson;
  res.chosen = CorrectionOptions{};
  res.chosen.features = 0;
  res.chosen.offset_spacing_bins = 0;
  for (const auto& cand : candidates) {
    double sum = 0.0;
    for (int g : groups) {
      std::vector<CorrectionCase> tr;
      for (const auto& c : cases)
        if (c.group != g) tr.push_back(c);
      Correction m;
      m.train(tr, cand);
      for (const auto& c : cases)
        if (c.group == g) sum += pearson(m.predict(c), mean_of(c.segments));
    }
    const double mean = sum / static_cast<double>(n);
    res.rows.push_back({cand, mean});
    ++res.candidates;
    if (mean > res.chosen_pearson) {  // strictly better; ties keep the earlier (simpler) one
      res.chosen = cand;
      res.chosen_pearson = mean;
    }
  }
  return res;
}

std::vector<CorrectionOptions> correction_candidates(int local_halfwidth_bins, int offset_spacing_bins, bool with_sim) {
  // Feature subsets: the base's own lines and level, then the fixed-frequency lines, then the
  // physics; every subset with the base terms (the correction is of the moved spectrum).
  const unsigned sets[] = {0b00011, 0b00111, 0b11011, 0b11111, 0b01011, 0b01111};
  const int bands[] = {1, 4, 8};
  const double lambdas[] = {0.001, 0.01, 0.1, 1.0};
  std::vector<CorrectionOptions> out;
  for (unsigned s : sets) {
    if (!with_sim && (s & 0b11000u) != 0) continue;
    for (int b : bands)
      for (int off : {0, offset_spacing_bins})
        for (double l : lambdas) {
          CorrectionOptions o;
          o.features = s;
          o.bands = b;
          o.offset_spacing_bins = off;
          o.local_halfwidth_bins = local_halfwidth_bins;
          o.lambda = l;
          out.push_back(o);
        }
  }
  return out;
}

void CorrectionEnsemble::train(const std::vector<CorrectionCase>& cases, const std::vector<CorrectionOptions>& candidates,
                               int n_members, uint64_t seed) {
  cv = select_correction(cases, candidates);
  members.clear();
  CorrectionOptions o = cv.chosen;
  if (o.features == 0 && o.offset_spacing_bins == 0) {
    // The baseline won the inner cross-validation: a correction with no weight.
    o.offset_spacing_bins = 0;
  }
  main.train(cases, o);
  // Members trained with one operating point left out (the inner folds of the chosen
  // correction); their held-out residuals give the predictive part of the band.
  std::vector<int> groups;
  for (const auto& c : cases)
    if (std::find(groups.begin(), groups.end(), c.group) == groups.end()) groups.push_back(c.group);
  const size_t bins = cases.front().base.size();
  const size_t nb = static_cast<size_t>(k_residual_bands);
  std::vector<std::vector<double>> resid(nb);
  for (int g : groups) {
    std::vector<CorrectionCase> tr;
    for (const auto& c : cases)
      if (c.group != g) tr.push_back(c);
    Correction f;
    f.train(tr, o);
    for (const auto& c : cases) {
      if (c.group != g) continue;
      const auto y = f.predict(c);
      const auto t = mean_of(c.segments);
      const double unit = relative_residuals ? mean_abs(y) : 1.0;
      for (size_t k = 0; k < bins; ++k) resid[std::min(nb - 1, k * nb / bins)].push_back((t[k] - y[k]) / unit);
    }
    members.push_back(std::move(f));
  }
  resid_lo.assign(nb, 0.0);
  resid_hi.assign(nb, 0.0);
  for (size_t b = 0; b < nb; ++b) {
    auto& r = resid[b];
    if (r.empty()) continue;
    std::sort(r.begin(), r.end());
    auto q = [&](double p) { return r[std::min(r.size() - 1, static_cast<size_t>(std::floor(p * static_cast<double>(r.size() - 1) + 0.5)))]; };
    resid_lo[b] = q(0.5 * (1.0 - k_band_coverage));
    resid_hi[b] = q(0.5 * (1.0 + k_band_coverage));
  }
  std::mt19937_64 rng(seed);
  size_t rows = 0;
  for (const auto& c : cases) rows += c.segments.size();
  for (int m = 0; m < n_members; ++m) {
    // Bootstrap within each case: draw its segments with replacement (multiplicities).
    std::vector<double> w(rows, 0.0);
    size_t r0 = 0;
    for (const auto& c : cases) {
      const size_t ns = c.segments.size();
      for (size_t d = 0; d < ns; ++d) w[r0 + static_cast<size_t>(rng() % ns)] += 1.0;
      r0 += ns;
    }
    Correction mm;
    mm.train(cases, o, &w);
    members.push_back(std::move(mm));
  }
}

void CorrectionEnsemble::predict(const std::vector<CorrectionCase>& in, const std::vector<double>& weights,
                                 std::vector<double>& y, std::vector<double>& lo, std::vector<double>& hi) const {
  if (in.empty() || in.size() != weights.size()) throw std::invalid_argument("correction: one weight per input");
  auto mixed = [&](const Correction& c) {
    std::vector<double> out;
    for (size_t i = 0; i < in.size(); ++i) {
      const auto yi = c.predict(in[i]);
      if (out.empty()) out.assign(yi.size(), 0.0);
      for (size_t k = 0; k < yi.size(); ++k) out[k] += weights[i] * yi[k];
    }
    return out;
  };
  y = mixed(main);
  lo = y;
  hi = y;
  for (const auto& m : members) {
    const auto ym = mixed(m);
    for (size_t k = 0; k < y.size(); ++k) {
      lo[k] = std::min(lo[k], ym[k]);
      hi[k] = std::max(hi[k], ym[k]);
    }
  }
  const size_t nb = resid_lo.size();
  const double unit = relative_residuals ? mean_abs(y) : 1.0;
  for (size_t k = 0; k < y.size() && nb > 0; ++k) {
    const size_t b = std::min(nb - 1, k * nb / y.size());
    lo[k] += unit * std::min(0.0, resid_lo[b]);
    hi[k] += unit * std::max(0.0, resid_hi[b]);
  }
}

nlohmann::json CorrectionEnsemble::to_json() const {
  nlohmann::json mem = nlohmann::json::array();
  for (const auto& m : members) mem.push_back(m.to_json());
  return {{"main", main.to_json()},
          {"members", mem},
          {"residual_lo", resid_lo},
          {"residual_relative", relative_residuals},
          {"residual_hi", resid_hi},
          {"cv", {{"chosen", cv.chosen.describe()},
                  {"chosen_pearson", cv.chosen_pearson},
                  {"baseline_pearson", cv.baseline_pearson},
                  {"candidates", cv.candidates}}}};
}

CorrectionEnsemble CorrectionEnsemble::from_json(const nlohmann::json& j) {
  CorrectionEnsemble e;
  e.main = Correction::from_json(j.at("main"));
  for (const auto& m : j.at("members")) {
    e.members.push_back(Correction::from_json(m));
    if (e.members.back().options().features != e.main.options().features)
      throw std::invalid_argument("correction: an ensemble member differs from the main correction");
  }
  e.resid_lo = j.at("residual_lo").get<std::vector<double>>();
  e.relative_residuals = j.at("residual_relative");
  e.resid_hi = j.at("residual_hi").get<std::vector<double>>();
  if (e.resid_lo.size() != e.resid_hi.size()) throw std::invalid_argument("correction: residual quantiles differ in length");
  e.cv.chosen = e.main.options();
  e.cv.chosen_pearson = j.at("cv").at("chosen_pearson");
  e.cv.baseline_pearson = j.at("cv").at("baseline_pearson");
  e.cv.candidates = j.at("cv").at("candidates");
  return e;
}

}  // namespace amb::host::hybrid
