#include "host-tools/core/hybrid/spectral_map.hpp"

#include "host-tools/core/hybrid/hat_basis.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Cholesky>
#include <Eigen/Dense>
#include <nlohmann/json.hpp>

namespace amb::host::hybrid {

bool SpectralMapOptions::valid(std::string* why) const {
  auto fail = [&](const char* m) {
    if (why) *why = m;
    return false;
  };
  if (bands < 1 || bands > 64) return fail("bands in [1, 64]");
  if (transfer_spacing_bins < 1 || transfer_spacing_bins > 1000) return fail("transfer_spacing_bins in [1, 1000]");
  if (local_halfwidth_bins < 1 || local_halfwidth_bins > 100) return fail("local_halfwidth_bins in [1, 100]");
  if (physics_channels < 1 || physics_channels > 8) return fail("physics_channels in [1, 8]");
  if (!(lambda_transfer > 0) || !(lambda_physics > 0)) return fail("ridge penalties must be > 0");
  return true;
}

namespace {


size_t hat_count(size_t bins, int spacing) {
  return std::max<size_t>(2, (bins - 1 + static_cast<size_t>(spacing) - 1) / static_cast<size_t>(spacing) + 1);
}

}  // namespace

void SpectralMap::physics_features(const std::vector<std::vector<double>>& q,
                                   std::vector<std::vector<double>>& out) const {
  const size_t nf = features();
  out.assign(bins_, std::vector<double>(nf, 0.0));
  if (!o_.use_physics) return;
  if (q.size() != static_cast<size_t>(o_.physics_channels))
    throw std::invalid_argument("map: expected " + std::to_string(o_.physics_channels) + " physics spectra");
  const auto h = static_cast<long>(o_.local_halfwidth_bins);
  const auto n = static_cast<long>(bins_);
  for (size_t c = 0; c < q.size(); ++c) {
    if (q[c].size() != bins_) throw std::invalid_argument("physics spectrum has the wrong number of bins");
    for (long k = 0; k < n; ++k) {
      const long lo = std::max(0L, k - h), hi = std::min(n - 1, k + h);
      double m = 0.0;
      for (long j = lo; j <= hi; ++j) m += q[c][static_cast<size_t>(j)];
      m /= static_cast<double>(hi - lo + 1);
      if (o_.split_local) {
        out[static_cast<size_t>(k)][c * k_physics_features] = m;
        out[static_cast<size_t>(k)][c * k_physics_features + 1] = q[c][static_cast<size_t>(k)] - m;
      } else {
        out[static_cast<size_t>(k)][c] = q[c][static_cast<size_t>(k)];
      }
    }
  }
}

size_t SpectralMap::transfer_count() const { return 1 + k_condition_states + k_op_inputs; }

size_t SpectralMap::physics_count() const {
  if (!o_.use_physics) return 0;
  return features() * (1 + (o_.state_gain ? k_condition_states : 0) + (o_.op_gain ? k_op_inputs : 0));
}

size_t SpectralMap::unknowns() const {
  // + one unpenalised global gain per physics feature (the band gains are deviations from it)
  return hats_ * transfer_count() + static_cast<size_t>(o_.bands) * physics_count() + features();
}

void SpectralMap::row(const MapInput& in, const std::vector<double>& q_raw, size_t k,
                      std::vector<long>& idx, std::vector<double>& val) const {
  std::array<double, k_op_inputs> u{};
  for (int m = 0; m < k_op_inputs; ++m) u[m] = op_scale_[m] > 0 ? (in.op[m] - op_mean_[m]) / op_scale_[m] : 0.0;
  const size_t tc = transfer_count();
  const Hat th = hat(k, bins_, hats_);
  for (int side = 0; side < 2; ++side) {
    const double w = side == 0 ? th.w : 1.0 - th.w;
    if (w == 0.0) continue;
    const size_t base = (th.knot + static_cast<size_t>(side)) * tc;
    idx.push_back(static_cast<long>(base));
    val.push_back(w);
    idx.push_back(static_cast<long>(base + 1 + static_cast<size_t>(in.state)));
    val.push_back(w);
    for (int m = 0; m < k_op_inputs; ++m)
      if (u[m] != 0.0) {
        idx.push_back(static_cast<long>(base + 1 + k_condition_states + static_cast<size_t>(m)));
        val.push_back(w * u[m]);
      }
  }
  if (!o_.use_physics) return;
  const size_t nf = features();
  double q[8 * k_physics_features];
  for (size_t f = 0; f < nf; ++f) q[f] = q_scale_[f] > 0 ? (q_raw[f] - q_mean_[f]) / q_scale_[f] : 0.0;
  const size_t pc = physics_count();
  const size_t global = hats_ * tc + static_cast<size_t>(o_.bands) * pc;
  for (size_t f = 0; f < nf; ++f) {
    idx.push_back(static_cast<long>(global + f));
    val.push_back(q[f]);
  }
  const Hat bh = hat(k, bins_, static_cast<size_t>(o_.bands));
  for (int side = 0; side < 2; ++side) {
    const double w = side == 0 ? bh.w : 1.0 - bh.w;
    if (w == 0.0 || (o_.bands == 1 && side == 1)) continue;
    size_t c = hats_ * tc + (bh.knot + static_cast<size_t>(side)) * pc;
    for (size_t f = 0; f < nf; ++f) {
      idx.push_back(static_cast<long>(c++));
      val.push_back(w * q[f]);
      if (o_.state_gain) {
        idx.push_back(static_cast<long>(c + static_cast<size_t>(in.state)));
        val.push_back(w * q[f]);
        c += k_condition_states;
      }
      if (o_.op_gain)
        for (int m = 0; m < k_op_inputs; ++m, ++c)
          if (u[m] != 0.0) {
            idx.push_back(static_cast<long>(c));
            val.push_back(w * q[f] * u[m]);
          }
    }
  }
}

void SpectralMap::train(const std::vector<MapInput>& in, const std::vector<std::vector<double>>& y,
                        const std::vector<double>& grid_hz, const SpectralMapOptions& o) {
  std::string why;
  if (!o.valid(&why)) throw std::invalid_argument("map options: " + why);
  if (in.empty() || in.size() != y.size()) throw std::invalid_argument("map: inputs and targets differ in number");
  if (grid_hz.size() < 4) throw std::invalid_argument("map: grid too small");
  o_ = o;
  bins_ = grid_hz.size();
  grid_hz_ = grid_hz;
  hats_ = hat_count(bins_, o_.transfer_spacing_bins);
  for (const auto& r : y)
    if (r.size() != bins_) throw std::invalid_argument("map: target with the wrong number of bins");
  for (const auto& c : in)
    if (c.state < 0 || c.state >= k_condition_states) throw std::invalid_argument("map: state out of range");
  const size_t n = in.size();

  // Standardise the operating point and the physics features on the training set. An input
  // that does not vary in training (one speed, one load) gets scale 0: it cannot be learned
  // from these data and is ignored rather than extrapolated.
  for (int m = 0; m < k_op_inputs; ++m) {
    double s = 0, s2 = 0;
    for (const auto& c : in) s += c.op[m];
    op_mean_[m] = s / static_cast<double>(n);
    for (const auto& c : in) s2 += (c.op[m] - op_mean_[m]) * (c.op[m] - op_mean_[m]);
    const double sd = std::sqrt(s2 / static_cast<double>(n));
    op_scale_[m] = sd > 1e-9 * std::max(1.0, std::abs(op_mean_[m])) ? sd : 0.0;
  }
  std::vector<std::vector<std::vector<double>>> feats(n);
  q_mean_.assign(features(), 0.0);
  q_scale_.assign(features(), 0.0);
  for (size_t i = 0; i < n; ++i) physics_features(in[i].physics, feats[i]);
  if (o_.use_physics) {
    for (size_t f = 0; f < features(); ++f) {
      double s = 0, s2 = 0;
      for (const auto& fi : feats)
        for (const auto& v : fi) s += v[f];
      q_mean_[f] = s / static_cast<double>(n * bins_);
      for (const auto& fi : feats)
        for (const auto& v : fi) s2 += (v[f] - q_mean_[f]) * (v[f] - q_mean_[f]);
      const double sd = std::sqrt(s2 / static_cast<double>(n * bins_));
      q_scale_[f] = sd > 1e-12 ? sd : 0.0;
    }
  }

  // Normal equations accumulated from the sparse rows.
  const size_t dim = unknowns();
  Eigen::MatrixXd ata = Eigen::MatrixXd::Zero(static_cast<long>(dim), static_cast<long>(dim));
  Eigen::VectorXd aty = Eigen::VectorXd::Zero(static_cast<long>(dim));
  std::vector<long> idx;
  std::vector<double> val;
  for (size_t i = 0; i < n; ++i) {
    for (size_t k = 0; k < bins_; ++k) {
      idx.clear();
      val.clear();
      row(in[i], feats[i][k], k, idx, val);
      const double t = y[i][k];
      for (size_t a = 0; a < idx.size(); ++a) {
        aty[idx[a]] += val[a] * t;
        for (size_t b = 0; b < idx.size(); ++b) ata(idx[a], idx[b]) += val[a] * val[b];
      }
    }
  }
  // Penalties scaled by how many observations a weight sees (cases x bins under its hat), so
  // lambda means the same for any number of cases and bins. The transfer intercepts a_t get a
  // token penalty (numerical only): the mean spectrum is not shrunk.
  const double obs_t = static_cast<double>(n * bins_) / static_cast<double>(hats_);
  const double obs_b = static_cast<double>(n * bins_) / static_cast<double>(o_.bands);
  const size_t tc = transfer_count();
  for (size_t t = 0; t < hats_; ++t)
    for (size_t j = 0; j < tc; ++j) {
      const auto d = static_cast<long>(t * tc + j);
      ata(d, d) += (j == 0 ? 1e-9 : o_.lambda_transfer) * obs_t;
    }
  const size_t global = dim - features();
  for (size_t j = hats_ * tc; j < global; ++j) ata(static_cast<long>(j), static_cast<long>(j)) += o_.lambda_physics * obs_b;
  for (size_t j = global; j < dim; ++j) ata(static_cast<long>(j), static_cast<long>(j)) += 1e-9 * static_cast<double>(n * bins_);
  const Eigen::VectorXd theta = ata.ldlt().solve(aty);
  if (!theta.allFinite()) throw std::runtime_error("map: the ridge system could not be solved");
  w_.assign(theta.data(), theta.data() + dim);

  double ss = 0;
  for (size_t i = 0; i < n; ++i) {
    const auto p = predict(in[i]);
    for (size_t k = 0; k < bins_; ++k) ss += (p[k] - y[i][k]) * (p[k] - y[i][k]);
  }
  training_rms_ = std::sqrt(ss / static_cast<double>(n * bins_));
}

std::vector<double> SpectralMap::predict(const MapInput& in) const {
  if (!trained()) throw std::logic_error("map not trained");
  if (in.state < 0 || in.state >= k_condition_states) throw std::invalid_argument("map: state out of range");
  std::vector<std::vector<double>> q;
  physics_features(in.physics, q);
  std::vector<double> out(bins_);
  std::vector<long> idx;
  std::vector<double> val;
  for (size_t k = 0; k < bins_; ++k) {
    idx.clear();
    val.clear();
    row(in, q[k], k, idx, val);
    double v = 0.0;
    for (size_t a = 0; a < idx.size(); ++a) v += val[a] * w_[static_cast<size_t>(idx[a])];
    out[k] = v;
  }
  return out;
}

nlohmann::json SpectralMap::to_json() const {
  nlohmann::json j;
  j["options"] = {{"use_physics", o_.use_physics},
                  {"bands", o_.bands},
                  {"transfer_spacing_bins", o_.transfer_spacing_bins},
                  {"local_halfwidth_bins", o_.local_halfwidth_bins},
                  {"lambda_transfer", o_.lambda_transfer},
                  {"lambda_physics", o_.lambda_physics},
                  {"state_gain", o_.state_gain},
                  {"op_gain", o_.op_gain},
                  {"physics_channels", o_.physics_channels},
                  {"split_local", o_.split_local}};
  j["grid_hz"] = grid_hz_;
  j["op_mean"] = op_mean_;
  j["op_scale"] = op_scale_;
  j["q_mean"] = q_mean_;
  j["q_scale"] = q_scale_;
  j["weights"] = w_;
  j["training_rms"] = training_rms_;
  return j;
}

SpectralMap SpectralMap::from_json(const nlohmann::json& j) {
  SpectralMap m;
  const auto& o = j.at("options");
  m.o_.use_physics = o.at("use_physics").get<bool>();
  m.o_.bands = o.at("bands").get<int>();
  m.o_.transfer_spacing_bins = o.at("transfer_spacing_bins").get<int>();
  m.o_.local_halfwidth_bins = o.at("local_halfwidth_bins").get<int>();
  m.o_.lambda_transfer = o.at("lambda_transfer").get<double>();
  m.o_.lambda_physics = o.at("lambda_physics").get<double>();
  m.o_.state_gain = o.at("state_gain").get<bool>();
  m.o_.op_gain = o.at("op_gain").get<bool>();
  m.o_.physics_channels = o.at("physics_channels").get<int>();
  m.o_.split_local = o.at("split_local").get<bool>();
  std::string why;
  if (!m.o_.valid(&why)) throw std::invalid_argument("model file: map options: " + why);
  m.grid_hz_ = j.at("grid_hz").get<std::vector<double>>();
  m.bins_ = m.grid_hz_.size();
  if (m.bins_ < 4) throw std::invalid_argument("model file: map grid too small");
  m.hats_ = hat_count(m.bins_, m.o_.transfer_spacing_bins);
  m.op_mean_ = j.at("op_mean").get<std::array<double, k_op_inputs>>();
  m.op_scale_ = j.at("op_scale").get<std::array<double, k_op_inputs>>();
  m.q_mean_ = j.at("q_mean").get<std::vector<double>>();
  m.q_scale_ = j.at("q_scale").get<std::vector<double>>();
  if (m.q_mean_.size() != m.features() || m.q_scale_.size() != m.features())
    throw std::invalid_argument("model file: map physics scaling does not match its options");
  m.w_ = j.at("weights").get<std::vector<double>>();
  m.training_rms_ = j.value("training_rms", 0.0);
  if (m.w_.size() != m.unknowns())
    throw std::invalid_argument("model file: map weights do not match its grid and options");
  for (double v : m.w_)
    if (!std::isfinite(v)) throw std::invalid_argument("model file: map weight not finite");
  return m;
}

}  // namespace amb::host::hybrid
