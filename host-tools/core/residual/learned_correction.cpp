#include "host-tools/core/io/number_text.hpp"
#include "host-tools/core/residual/learned_correction.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include <Eigen/Cholesky>
#include <Eigen/Dense>

namespace amb::host::residual {

bool LearnedCorrectionOptions::valid(std::string* why) const {
  auto fail = [&](const char* m) {
    if (why) *why = m;
    return false;
  };
  if (!(knot_spacing_octaves > 0.0) || knot_spacing_octaves > 10.0) return fail("knot_spacing_octaves in (0, 10]");
  if (gain_bands < 1 || gain_bands > 32) return fail("gain_bands in [1, 32]");
  if (!(local_halfwidth_octaves > 0.0) || local_halfwidth_octaves > 5.0) return fail("local_halfwidth_octaves in (0, 5]");
  if (lambdas.empty()) return fail("at least one ridge penalty");
  for (double l : lambdas)
    if (!(l > 0.0) || !std::isfinite(l)) return fail("ridge penalties must be finite and > 0");
  if (!(min_half_s > 0.0)) return fail("min_half_s > 0");
  if (!(gcv_gamma >= 1.0) || gcv_gamma > 5.0) return fail("gcv_gamma in [1, 5]");
  return true;
}

namespace {



// Digamma and trigamma for x > 0 (recurrence to x >= 6, then the asymptotic series): the
// mean and the variance of ln of a Gamma(K, 1/K) variable, i.e. of a log Welch estimate
// with K averages, are psi(K) - ln K and psi'(K).
double digamma(double x) {
  double r = 0.0;
  while (x < 6.0) {
    r -= 1.0 / x;
    x += 1.0;
  }
  const double f = 1.0 / (x * x);
  return r + std::log(x) - 0.5 / x - f * (1.0 / 12 - f * (1.0 / 120 - f * (1.0 / 252 - f * (1.0 / 240 - f / 132))));
}
double trigamma(double x) {
  double r = 0.0;
  while (x < 6.0) {
    r += 1.0 / (x * x);
    x += 1.0;
  }
  const double f = 1.0 / (x * x);
  return r + 1.0 / x + f / 2.0 + (1.0 / (6 * x * x * x)) * (1.0 - f * (1.0 / 5 - f * (1.0 / 7 - f / 5)));
}

// Hat functions over u = log2 f with `count` knots from u0, `step` apart (partition of unity;
// points outside the knot range take the end knot): the first knot and its weight.
struct Hat {
  int knot = 0;
  double w = 1.0;
};
Hat hat(double u, double u0, double step, int count) {
  if (count <= 1) return {0, 1.0};
  const double pos = std::clamp((u - u0) / step, 0.0, static_cast<double>(count - 1));
  const int t = std::min(static_cast<int>(std::floor(pos)), count - 2);
  return {t, 1.0 - (pos - t)};
}

// The map's basis over the training part's frequency range.
struct Basis {
  double u0 = 0.0, u1 = 0.0;
  int transfer = 2;   // transfer-path hats
  double t_step = 1.0;
  int gain = 1;       // prominence-gain hats
  double g_step = 1.0;
  int size() const { return transfer + gain; }
};

Basis make_basis(double f_lo, double f_hi, const LearnedCorrectionOptions& o) {
  Basis b;
  b.u0 = std::log2(f_lo);
  b.u1 = std::log2(f_hi);
  const double span = std::max(b.u1 - b.u0, 1e-6);
  b.transfer = std::max(2, static_cast<int>(std::ceil(span / o.knot_spacing_octaves - 1e-9)) + 1);
  b.t_step = span / (b.transfer - 1);
  b.gain = o.gain_bands;
  b.g_step = o.gain_bands > 1 ? span / (o.gain_bands - 1) : 1.0;
  return b;
}

// The model's prominence: its log level minus its mean over +-h octaves (that channel's grid).
std::vector<double> prominence(const CorrectionSpectrum& s, double h_oct) {
  const size_t n = s.f_hz.size();
  std::vector<double> p(n, 0.0);
  for (size_t i = 0; i < n; ++i) {
    const double ui = std::log2(s.f_hz[i]);
    double m = 0.0;
    int k = 0;
    for (size_t j = 0; j < n; ++j)
      if (std::abs(std::log2(s.f_hz[j]) - ui) <= h_oct) {
        m += s.model_ln[j];
        ++k;
      }
    p[i] = s.model_ln[i] - m / k;
  }
  return p;
}

// Design rows of one group in one part, and the targets r = measured - model.
struct GroupRows {
  Eigen::MatrixXd x;
  Eigen::VectorXd r;
  Eigen::VectorXd noise_var;
};

GroupRows rows(const CorrectionPart& part, int g, const Basis& b, const LearnedCorrectionOptions& o) {
  size_t n = 0;
  for (const auto& s : part.spectra)
    if (s.group == g) n += s.f_hz.size();
  GroupRows out;
  out.x = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(n), b.size());
  out.r.resize(static_cast<Eigen::Index>(n));
  out.noise_var.resize(static_cast<Eigen::Index>(n));
  Eigen::Index i = 0;
  for (const auto& s : part.spectra) {
    if (s.group != g) continue;
    const auto p = prominence(s, o.local_halfwidth_octaves);
    for (size_t k = 0; k < s.f_hz.size(); ++k, ++i) {
      const double u = std::log2(s.f_hz[k]);
      const Hat th = hat(u, b.u0, b.t_step, b.transfer);
      out.x(i, th.knot) += th.w;
      if (b.transfer > 1) out.x(i, th.knot + 1) += 1.0 - th.w;
      const Hat gh = hat(u, b.u0, b.g_step, b.gain);
      out.x(i, b.transfer + gh.knot) += gh.w * p[k];
      if (b.gain > 1) out.x(i, b.transfer + gh.knot + 1) += (1.0 - gh.w) * p[k];
      out.r(i) = s.measured_ln[k] - s.model_ln[k];
      out.noise_var(i) = k < s.noise_var_ln.size() ? s.noise_var_ln[k] : 0.0;
    }
  }
  return out;
}

struct GroupFit {
  Eigen::VectorXd theta;  // in original column units
  double lambda = 0.0, edf = 0.0;
};

// Weighted ridge on unit-mean-square columns, penalty lambda x n, lambda chosen by GCV on
// these rows. Weights: the inverse of each point's estimator variance (relative to their mean),
// so that a band with few averages (a heavy-tailed log estimate) cannot pull the map; unit
// weights when the variances are unknown.
GroupFit fit_group(const GroupRows& tr, const LearnedCorrectionOptions& o) {
  const Eigen::Index n = tr.x.rows(), m = tr.x.cols();
  GroupFit best;
  best.theta = Eigen::VectorXd::Zero(m);
  if (n == 0) return best;
  Eigen::VectorXd sw = Eigen::VectorXd::Ones(n);
  if ((tr.noise_var.array() > 0.0).all()) {
    sw = tr.noise_var.cwiseInverse();
    sw /= sw.mean();
    sw = sw.cwiseSqrt();
  }
  const Eigen::MatrixXd xw = sw.asDiagonal() * tr.x;
  const Eigen::VectorXd rw = sw.asDiagonal() * tr.r;
  Eigen::VectorXd scale(m);
  for (Eigen::Index j = 0; j < m; ++j) {
    const double ms = xw.col(j).squaredNorm() / static_cast<double>(n);
    scale(j) = ms > 1e-24 ? 1.0 / std::sqrt(ms) : 0.0;  // an empty column stays at 0
  }
  const Eigen::MatrixXd xs = xw * scale.asDiagonal();
  const Eigen::MatrixXd a = xs.transpose() * xs;
  const Eigen::VectorXd xr = xs.transpose() * rw;
  double best_gcv = std::numeric_limits<double>::infinity();
  for (double lam : o.lambdas) {
    Eigen::MatrixXd reg = a;
    reg.diagonal().array() += lam * static_cast<double>(n);
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(reg);
    const Eigen::VectorXd th = ldlt.solve(xr);
    if (!th.allFinite()) continue;
    const double edf = ldlt.solve(a).trace();
    const double rss = (rw - xs * th).squaredNorm();
    const double dof = static_cast<double>(n) - o.gcv_gamma * edf;
    if (!(dof > 0.5)) continue;
    const double gcv = static_cast<double>(n) * rss / (dof * dof);
    if (gcv < best_gcv) {
      best_gcv = gcv;
      best.theta = scale.asDiagonal() * th;
      best.lambda = lam;
      best.edf = edf;
    }
  }
  return best;
}

struct Accum {
  double s_before = 0.0, s_after = 0.0, s_noise = 0.0;
  int n = 0;
  void add(const GroupRows& g, const Eigen::VectorXd& theta) {
    const Eigen::VectorXd after = g.r - g.x * theta;
    s_before += g.r.squaredNorm();
    s_after += after.squaredNorm();
    s_noise += g.noise_var.sum();
    n += static_cast<int>(g.r.size());
  }
  CorrectionScore score(double db_per_ln) const {
    CorrectionScore c;
    c.points = n;
    if (n == 0) return c;
    const double mb = s_before / n, ma = s_after / n, mf = s_noise / n;
    c.before_db = db_per_ln * std::sqrt(mb);
    c.after_db = db_per_ln * std::sqrt(ma);
    c.noise_floor_db = db_per_ln * std::sqrt(mf);
    c.absorbed_fraction = mb > 0.0 ? 1.0 - ma / mb : 0.0;
    c.absorbed_fraction_of_excess = mb > 1.1 * mf ? (mb - ma) / (mb - mf) : std::numeric_limits<double>::quiet_NaN();
    return c;
  }
};

void set_noise_floor(CorrectionScore& c, double floor_ms_ln, double db_per_ln) {
  const double mb = std::pow(c.before_db / db_per_ln, 2), ma = std::pow(c.after_db / db_per_ln, 2);
  c.noise_floor_db = db_per_ln * std::sqrt(floor_ms_ln);
  c.absorbed_fraction_of_excess = mb > 1.1 * floor_ms_ln ? (mb - ma) / (mb - floor_ms_ln) : std::numeric_limits<double>::quiet_NaN();
}

void check_part(const CorrectionPart& p, const char* which, int groups) {
  for (const auto& s : p.spectra) {
    const size_t n = s.f_hz.size();
    if (s.measured_ln.size() != n || s.model_ln.size() != n || (!s.noise_var_ln.empty() && s.noise_var_ln.size() != n))
      throw std::invalid_argument(std::string("learned correction: ") + which + " spectrum " + s.channel + ": lengths differ");
    for (size_t k = 0; k < n; ++k)
      if (!(s.f_hz[k] > 0.0) || !std::isfinite(s.measured_ln[k]) || !std::isfinite(s.model_ln[k]))
        throw std::invalid_argument(std::string("learned correction: ") + which + " spectrum " + s.channel +
                                    ": non-positive frequency or non-finite level");
    if (s.group < 0 || s.group >= groups)
      throw std::invalid_argument("learned correction: " + std::string(which) + " spectrum " + s.channel + ": group out of range");
  }
}

const char* k_steady_channel[k_channels] = {"sensor A1", "sensor A2", "sensor B1", "sensor B2",
                                            "current A1", "current A2", "current B1", "current B2"};

}  // namespace

LearnedCorrectionSummary learned_correction(const CorrectionPart& train, const CorrectionPart& test,
                                            const std::vector<std::string>& group_names, const LearnedCorrectionOptions& o) {
  std::string why;
  if (!o.valid(&why)) throw std::invalid_argument("learned correction options: " + why);
  check_part(train, "training", static_cast<int>(group_names.size()));
  check_part(test, "scored", static_cast<int>(group_names.size()));
  LearnedCorrectionSummary s;
  s.trained_on = train.name;
  s.scored_on = test.name;
  s.knot_spacing_octaves = o.knot_spacing_octaves;
  s.gain_bands = o.gain_bands;
  s.note = "learned correction: a regularised map fitted to what the named elements leave; not a physical "
           "explanation, not part of the verdict";
  double f_lo = std::numeric_limits<double>::infinity(), f_hi = 0.0;
  for (const auto& sp : train.spectra)
    for (double f : sp.f_hz) {
      f_lo = std::min(f_lo, f);
      f_hi = std::max(f_hi, f);
    }
  if (!(f_hi > f_lo)) {
    s.skipped_why = "the training part has no frequency range";
    return s;
  }
  const Basis b = make_basis(f_lo, f_hi, o);
  Accum held, trained;
  for (int g = 0; g < static_cast<int>(group_names.size()); ++g) {
    const GroupRows tr = rows(train, g, b, o);
    const GroupRows te = rows(test, g, b, o);
    if (tr.r.size() == 0 && te.r.size() == 0) continue;
    const GroupFit fit = fit_group(tr, o);
    GroupScore gs;
    gs.name = group_names[static_cast<size_t>(g)];
    gs.lambda = fit.lambda;
    gs.effective_parameters = fit.edf;
    gs.weights = b.size();
    Accum one;
    one.add(te, fit.theta);
    gs.held_out = one.score(test.db_per_ln);
    held.add(te, fit.theta);
    trained.add(tr, fit.theta);
    s.weights += b.size();
    s.effective_parameters += fit.edf;
    s.training_points += static_cast<int>(tr.r.size());
    s.groups.push_back(gs);
  }
  if (held.n == 0 || s.training_points == 0) {
    s.skipped_why = "no channel group has points in both parts";
    return s;
  }
  s.held_out = held.score(test.db_per_ln);
  s.training = trained.score(train.db_per_ln);
  s.noise_floor_source = "the estimates' nominal variance";
  s.done = true;
  return s;
}

CorrectionPart steady_half_part(const SteadyData& d, const SteadyEvaluation& model, int half, const SteadyOptions& so) {
  if (half != 0 && half != 1) throw std::invalid_argument("steady_half_part: half must be 0 or 1");
  const size_t len = d.window_len / 2;
  const auto seg = static_cast<size_t>(so.segment_s * d.fs_hz);
  if (len < 3 * seg || d.window[0].size() < 2 * len)
    throw std::runtime_error(io::printf_text("a half of the steady window (%.2f s) is shorter than 3 Welch segments of %.2f s (5 with 50 %% overlap)",
                                 static_cast<double>(len) / d.fs_hz, so.segment_s));
  const std::vector<Band> h = remainder_bands(d, half == 0 ? 0 : len, len, so);
  if (h.size() != d.bands.size() || model.psd_pred.size() != d.bands.size())
    throw std::runtime_error("the half's bands differ from the record's (steady options differ from the loop's)");
  CorrectionPart p;
  p.name = io::printf_text(half == 0 ? "first half of the steady window (%.2f s)" : "second half of the steady window (%.2f s)",
               static_cast<double>(len) / d.fs_hz);
  p.db_per_ln = 10.0 / std::log(10.0);
  for (int c = 0; c < k_channels; ++c) {
    CorrectionSpectrum s;
    s.group = c / 2;
    s.channel = k_steady_channel[c];
    for (size_t i = 0; i < h.size(); ++i) {
      const double pm = h[i].psd[static_cast<size_t>(c)];
      const double pp = model.psd_pred[i][static_cast<size_t>(c)];
      if (!(pm > 0.0) || !(pp > 0.0) || !std::isfinite(pp)) continue;
      const double k = h[i].averages;
      s.f_hz.push_back(d.bands[i].f_hz);
      s.measured_ln.push_back(std::log(pm));
      // The model as a K-average log estimate sees it: ln P + psi(K) - ln K.
      s.model_ln.push_back(std::log(pp) + digamma(k) - std::log(k));
      s.noise_var_ln.push_back(trigamma(k));
    }
    p.spectra.push_back(std::move(s));
  }
  return p;
}

namespace {

// Trained on a, scored on b; and the reverse fold (trained on b, scored on a) as a check.
LearnedCorrectionSummary both_ways(const CorrectionPart& a, const CorrectionPart& b, const std::vector<std::string>& groups,
                                   const LearnedCorrectionOptions& o) {
  LearnedCorrectionSummary fwd = learned_correction(a, b, groups, o);
  const LearnedCorrectionSummary rev = learned_correction(b, a, groups, o);
  if (rev.done) {
    fwd.has_reverse = true;
    fwd.reverse_trained_on = rev.trained_on;
    fwd.reverse_scored_on = rev.scored_on;
    fwd.reverse_held_out = rev.held_out;
  }
  return fwd;
}

}  // namespace

LearnedCorrectionSummary learned_correction_steady(const SteadyData& d, const SteadyEvaluation& model,
                                                   const LearnedCorrectionOptions& o, const SteadyOptions& so) {
  LearnedCorrectionSummary s;
  s.domain = "log PSD per channel (4 sensors, 4 coil currents), 1/" + std::to_string(so.bands_per_octave) +
             "-octave bands, mean and speed orders 1..3 removed";
  const double half_s = static_cast<double>(d.window_len / 2) / d.fs_hz;
  if (half_s < o.min_half_s || half_s < 3.0 * so.segment_s) {
    s.skipped_why = io::printf_text("steady window %.2f s: a half is shorter than %.2f s, too short to train on one half and score on the other",
                        d.window_s, std::max(o.min_half_s, 3.0 * so.segment_s));
    return s;
  }
  CorrectionPart first, second;
  try {
    first = steady_half_part(d, model, 0, so);
    second = steady_half_part(d, model, 1, so);
  } catch (const std::runtime_error& e) {
    s.skipped_why = e.what();
    return s;
  }
  const std::vector<std::string> groups = {"sensors A", "sensors B", "currents AMB A", "currents AMB B"};
  LearnedCorrectionSummary fwd = both_ways(first, second, groups, o);
  fwd.domain = s.domain;
  // The noise floor from the data, not from the estimator's nominal variance: the two halves
  // estimate the same spectrum (a steady record), so half the mean square of their log
  // difference is one half's estimation variance (the nominal 1/averages overstates it here).
  // Anything that differs between the halves beyond noise counts as noise too: the floor is
  // an upper bound, and the share of the excess absorbed is then, if anything, overstated.
  std::vector<double> ss(groups.size(), 0.0);
  std::vector<int> nn(groups.size(), 0);
  double s_all = 0.0;
  int n_all = 0;
  for (size_t c = 0; c < first.spectra.size() && c < second.spectra.size(); ++c) {
    const auto& a = first.spectra[c];
    const auto& b = second.spectra[c];
    for (size_t i = 0, j = 0; i < a.f_hz.size() && j < b.f_hz.size();) {
      if (a.f_hz[i] < b.f_hz[j]) { ++i; continue; }
      if (b.f_hz[j] < a.f_hz[i]) { ++j; continue; }
      const double v = 0.5 * std::pow((a.measured_ln[i] - a.model_ln[i]) - (b.measured_ln[j] - b.model_ln[j]), 2);
      ss[static_cast<size_t>(a.group)] += v;
      ++nn[static_cast<size_t>(a.group)];
      s_all += v;
      ++n_all;
      ++i;
      ++j;
    }
  }
  if (n_all > 0) {
    const double db = first.db_per_ln;
    set_noise_floor(fwd.held_out, s_all / n_all, db);
    set_noise_floor(fwd.training, s_all / n_all, db);
    if (fwd.has_reverse) set_noise_floor(fwd.reverse_held_out, s_all / n_all, db);
    for (auto& g : fwd.groups)
      for (size_t k = 0; k < groups.size(); ++k)
        if (g.name == groups[k] && nn[k] > 0) set_noise_floor(g.held_out, ss[k] / nn[k], db);
    fwd.noise_floor_source = "split-half: half the mean square of the two halves' log difference";
  }
  return fwd;
}

LearnedCorrectionSummary learned_correction_sweep(const SweepOutcome& so, const LearnedCorrectionOptions& o) {
  LearnedCorrectionSummary s;
  s.domain = "log |H| per accelerometer over the compared bins (coherence >= the loop's threshold)";
  const auto& d = so.data;
  const auto& hm = so.after.h_model;
  CorrectionPart odd, even;
  odd.name = "odd accelerometers (1, 3, ...)";
  even.name = "even accelerometers (2, 4, ...)";
  odd.db_per_ln = even.db_per_ln = 20.0 / std::log(10.0);
  for (size_t c = 0; c < d.h.size() && c < hm.size(); ++c) {
    CorrectionSpectrum sp;
    sp.group = 0;
    sp.channel = "accel " + std::to_string(c + 1);
    for (size_t i = 0; i < d.f_hz.size(); ++i) {
      if (!(d.w[c][i] > 0.0) || !(std::abs(hm[c][i]) > 0.0) || !(std::abs(d.h[c][i]) > 0.0)) continue;
      sp.f_hz.push_back(d.f_hz[i]);
      sp.measured_ln.push_back(std::log(std::abs(d.h[c][i])));
      sp.model_ln.push_back(std::log(std::abs(hm[c][i])));
      // Weight w = n gamma^2 / (1 - gamma^2): var(ln |H1|) ~ (1 - gamma^2) / (2 n gamma^2) = 1 / (2 w).
      sp.noise_var_ln.push_back(0.5 / d.w[c][i]);
    }
    if (sp.f_hz.empty()) continue;
    (c % 2 == 0 ? odd : even).spectra.push_back(std::move(sp));
  }
  if (odd.spectra.empty() || even.spectra.empty()) {
    s.skipped_why = "fewer than two accelerometers with compared bins: no held-out channel to score on";
    return s;
  }
  const std::vector<std::string> groups = {"accelerometers"};
  LearnedCorrectionSummary fwd = both_ways(odd, even, groups, o);
  fwd.domain = s.domain;
  return fwd;
}

}  // namespace amb::host::residual
