#include "host-tools/core/residual/steady_fit.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "model/signal/pearson.hpp"
#include "model/amb/amb_force.hpp"
#include "model/effects/effect_loop_model.hpp"

namespace amb::host::residual {
namespace {

using cd = std::complex<double>;
using model::effects::EffectKind;
constexpr double k_two_pi = 2.0 * M_PI;
constexpr double k_line_floor = 0.03;

std::array<double, 2> unbalance_planes(const board::BoardConfig& b) {
  std::vector<model::RigidDisk> disks = b.plant.rotor.disks;
  std::sort(disks.begin(), disks.end(), [](const auto& x, const auto& y) { return x.mass_kg > y.mass_kg; });
  double length = 0.0;
  for (const auto& e : b.plant.rotor.elements) length += e.length_m;
  std::array<double, 2> z{length / 3.0, 2.0 * length / 3.0};
  if (disks.size() >= 2) z = {std::min(disks[0].axial_m, disks[1].axial_m), std::max(disks[0].axial_m, disks[1].axial_m)};
  return z;
}

using model::signal::pearson;  // one definition: model/signal/pearson.hpp

}  // namespace

int element_parameters(EffectKind k) {
  switch (k) {
    case EffectKind::pedestal_resonance: return 3;
    case EffectKind::sensor_runout: return 4 * model::effects::k_runout_orders;
    case EffectKind::aux_bearing_offset: return 4;
    case EffectKind::amplifier_lag: return 1;
    case EffectKind::rotor_mode: return 1;
    case EffectKind::magnetic_saturation: return 1;
    case EffectKind::sensor_mass: return 1;
    case EffectKind::aux_support_compliance: return 1;
    case EffectKind::sensor_gain: return 2;  // the two planes' probe gain ratios (drop part)
  }
  return 0;
}

SteadyEvaluation evaluate_steady(const SteadyData& d, const board::BoardConfig& b, const model::effects::EffectSet& fx,
                                 const model::effects::SensorRunout* known_runout,
                                 const std::shared_ptr<const model::RigModel>& rig_in) {
  SteadyEvaluation ev;
  ev.effects = fx;
  const std::shared_ptr<const model::RigModel> rig = rig_in ? rig_in : model::RigModel::make(b.plant);
  const model::effects::EffectLoopModel m(rig, b.plant, b.controller, b.rate_hz, d.spin_hz, fx);
  const double t = d.window_s;

  // ---- PSD: two white noise sources, sensor noise (variance sigma_s^2 per sample at every
  // sensor) and a force disturbance (variance sigma_f^2 per sample on every actuator axis);
  // P = sigma_s^2 g + sigma_f^2 h. For a ratio rho_f = sigma_f^2 / sigma_s^2 the Whittle optimum of
  // sigma_s^2 is closed-form; rho_f is found by a golden-section search on log10 rho_f (and rho_f = 0).
  const size_t nb = d.bands.size();
  std::vector<std::array<double, k_channels>> g(nb), gf(nb);
  for (size_t i = 0; i < nb; ++i) {
    const auto r = m.at(d.bands[i].f_hz);
    for (int c = 0; c < k_channels; ++c) {
      double s = 0.0, sf = 0.0;
      for (int k = 0; k < 4; ++k) {
        s += std::norm(r.noise(c, k));
        sf += std::norm(r.injection(c, k) / m.ki_eff(k));
      }
      g[i][static_cast<size_t>(c)] = std::max(s * 2.0 / d.fs_hz, 1e-300);
      gf[i][static_cast<size_t>(c)] = sf * 2.0 / d.fs_hz;
    }
  }
  auto whittle = [&](double rho_f, double* sigma2_out) {
    double num = 0.0, den = 0.0;
    for (size_t i = 0; i < nb; ++i)
      for (int c = 0; c < k_channels; ++c) {
        num += d.bands[i].averages * d.bands[i].psd[static_cast<size_t>(c)] / (g[i][static_cast<size_t>(c)] + rho_f * gf[i][static_cast<size_t>(c)]);
        den += d.bands[i].averages;
      }
    const double s2 = den > 0 ? num / den : 0.0;
    double v = 0.0;
    for (size_t i = 0; i < nb; ++i)
      for (int c = 0; c < k_channels; ++c) {
        const double p = std::max(s2 * (g[i][static_cast<size_t>(c)] + rho_f * gf[i][static_cast<size_t>(c)]), 1e-300);
        v += d.bands[i].averages * (std::log(p) + d.bands[i].psd[static_cast<size_t>(c)] / p);
      }
    if (sigma2_out != nullptr) *sigma2_out = s2;
    return v;
  };
  double rho_f = 0.0;
  {
    double best = whittle(0.0, nullptr);
    double lo = 4.0, hi = 22.0;  // log10 (m/N)^2
    const double gr = 0.5 * (std::sqrt(5.0) - 1.0);
    double a = hi - gr * (hi - lo), bb = lo + gr * (hi - lo);
    double fa = whittle(std::pow(10.0, a), nullptr), fb = whittle(std::pow(10.0, bb), nullptr);
    for (int it = 0; it < 40; ++it) {
      if (fa < fb) {
        hi = bb; bb = a; fb = fa; a = hi - gr * (hi - lo); fa = whittle(std::pow(10.0, a), nullptr);
      } else {
        lo = a; a = bb; fa = fb; bb = lo + gr * (hi - lo); fb = whittle(std::pow(10.0, bb), nullptr);
      }
    }
    const double x = fa < fb ? a : bb;
    if (std::min(fa, fb) < best) rho_f = std::pow(10.0, x);
  }
  double sigma2 = 0.0;
  double nll = whittle(rho_f, &sigma2);
  ev.noise_rms_m = std::sqrt(sigma2);
  ev.force_noise_rms_n = std::sqrt(sigma2 * rho_f);
  ev.psd_pred.resize(nb);
  int data = 0;
  for (size_t i = 0; i < nb; ++i)
    for (int c = 0; c < k_channels; ++c) {
      ev.psd_pred[i][static_cast<size_t>(c)] = sigma2 * (g[i][static_cast<size_t>(c)] + rho_f * gf[i][static_cast<size_t>(c)]);
      ++data;
    }
  // Model PSD at an arbitrary frequency (for line and static variances).
  auto psd_at = [&](double f_hz) {
    std::array<double, k_channels> out{};
    const auto r = m.at(std::max(f_hz, 0.5));
    for (int c = 0; c < k_channels; ++c) {
      double s = 0.0;
      for (int k = 0; k < 4; ++k) s += std::norm(r.noise(c, k)) + rho_f * std::norm(r.injection(c, k) / m.ki_eff(k));
      out[static_cast<size_t>(c)] = sigma2 * s * 2.0 / d.fs_hz;
    }
    return out;
  };

  // ---- speed-order lines: weighted complex least squares per order ----
  ev.unbalance_axial_m = unbalance_planes(b);
  model::effects::SensorRunout runout{};
  for (int h = 1; h <= k_orders && d.spin_hz > 0.0; ++h) {
    const double f = h * d.spin_hz;
    const auto p = psd_at(f);
    std::vector<Eigen::VectorXcd> basis;
    if (h == 1)
      for (double z : ev.unbalance_axial_m) basis.push_back(m.forward_force(f, z));
    if (fx.runout && h <= model::effects::k_runout_orders)
      for (int plane = 0; plane < 2; ++plane) basis.push_back(m.forward_runout(f, plane));
    Eigen::VectorXcd y(k_channels), w(k_channels);
    for (int c = 0; c < k_channels; ++c) {
      y(c) = d.order[static_cast<size_t>(c)][static_cast<size_t>(h - 1)];
      const double v = 2.0 * p[static_cast<size_t>(c)] / t + std::pow(k_line_floor * std::abs(y(c)), 2) + 1e-300;
      w(c) = 1.0 / std::sqrt(v);
    }
    // A runout known from elsewhere (a drop's contact geometry): its response is part of the
    // prediction, not fitted.
    Eigen::VectorXcd known = Eigen::VectorXcd::Zero(k_channels);
    if (known_runout != nullptr && !fx.runout && h <= model::effects::k_runout_orders)
      for (int plane = 0; plane < 2; ++plane)
        known += m.forward_runout(f, plane) * known_runout->r_m[static_cast<size_t>(plane)][static_cast<size_t>(h - 1)];
    const Eigen::VectorXcd y_meas = y;
    y -= known;
    Eigen::VectorXcd pred = known;
    if (!basis.empty()) {
      Eigen::MatrixXcd a(k_channels, static_cast<Eigen::Index>(basis.size()));
      for (size_t j = 0; j < basis.size(); ++j) a.col(static_cast<Eigen::Index>(j)) = basis[j];
      const Eigen::MatrixXcd aw = w.asDiagonal() * a;
      const Eigen::VectorXcd coef = aw.colPivHouseholderQr().solve(w.asDiagonal() * y);
      pred += a * coef;
      size_t j = 0;
      if (h == 1) {
        ev.unbalance_force_n = {coef(0), coef(1)};
        j = 2;
      }
      if (fx.runout)
        for (int plane = 0; plane < 2; ++plane)
          runout.r_m[static_cast<size_t>(plane)][static_cast<size_t>(h - 1)] = coef(static_cast<Eigen::Index>(j++));
    }
    for (int c = 0; c < k_channels; ++c) {
      ev.order_pred[static_cast<size_t>(c)][static_cast<size_t>(h - 1)] = pred(c);
      const double v = 1.0 / std::norm(w(c));
      nll += std::norm(y_meas(c) - pred(c)) / v + std::log(v);
      data += 2;
    }
  }
  if (fx.runout) ev.effects.runout = runout;

  // ---- statics: levitated ----
  const auto st = m.static_levitated();
  ev.ki_ratio = st.ki_ratio;
  {
    const auto p0 = psd_at(d.bands.empty() ? 1.0 : d.bands.front().f_hz);
    double lim = 1e9;
    for (const auto& a : b.plant.amb) lim = std::min(lim, a.coil_current_limit_a);
    for (int c = 0; c < k_channels; ++c) {
      const double pred = c < 4 ? st.sensor_m[static_cast<size_t>(c)] : st.current_a[static_cast<size_t>(c - 4)];
      const double floor = c < 4 ? 0.2e-6 : 5e-4 * lim;
      const double v = p0[static_cast<size_t>(c)] / t + std::pow(0.02 * std::abs(pred) + floor, 2);
      ev.static_pred[static_cast<size_t>(c)] = pred;
      nll += 0.5 * (std::pow(d.mean[static_cast<size_t>(c)] - pred, 2) / v + std::log(v));
      ++data;
    }
  }

  // ---- rest on the aux bearings: linear in the aux-bearing offsets ----
  if (d.has_rest) {
    std::array<double, 4> base = m.rest_sensors_m();
    std::array<double, 4> v{};
    for (int k = 0; k < 4; ++k)
      v[static_cast<size_t>(k)] = std::pow(d.rest_std_m[static_cast<size_t>(k)], 2) / std::max<size_t>(d.rest_len / 10, 1) + std::pow(0.5e-6, 2);
    if (fx.aux_offset) {
      // Columns: sensitivity of the rest readings to each offset (exactly linear).
      model::effects::EffectSet zero = fx;
      zero.aux_offset = model::effects::AuxBearingOffset{};
      const model::effects::EffectLoopModel m0(rig, b.plant, b.controller, b.rate_hz, d.spin_hz, zero);
      base = m0.rest_sensors_m();
      Eigen::Matrix4d a;
      for (int j = 0; j < 4; ++j) {
        model::effects::EffectSet one = zero;
        if (j < 2) one.aux_offset->x_m[static_cast<size_t>(j)] = 1e-4;
        else one.aux_offset->y_m[static_cast<size_t>(j - 2)] = 1e-4;
        const model::effects::EffectLoopModel m1(rig, b.plant, b.controller, b.rate_hz, d.spin_hz, one);
        const auto r1 = m1.rest_sensors_m();
        for (int k = 0; k < 4; ++k) a(k, j) = (r1[static_cast<size_t>(k)] - base[static_cast<size_t>(k)]) / 1e-4;
      }
      Eigen::Vector4d y;
      for (int k = 0; k < 4; ++k) y(k) = d.rest_mean_m[static_cast<size_t>(k)] - base[static_cast<size_t>(k)];
      const Eigen::Vector4d off = a.fullPivLu().solve(y);
      model::effects::AuxBearingOffset o;
      o.x_m = {off(0), off(1)};
      o.y_m = {off(2), off(3)};
      ev.effects.aux_offset = o;
      const Eigen::Vector4d fit = a * off;
      for (int k = 0; k < 4; ++k) base[static_cast<size_t>(k)] += fit(k);
    }
    ev.rest_pred_m = base;
    for (int k = 0; k < 4; ++k) {
      nll += 0.5 * (std::pow(d.rest_mean_m[static_cast<size_t>(k)] - base[static_cast<size_t>(k)], 2) / v[static_cast<size_t>(k)] +
                    std::log(v[static_cast<size_t>(k)]));
      ++data;
    }
  }

  ev.nll = nll;
  ev.parameters = k_base_parameters;
  for (int k = 0; k < model::effects::k_effect_kinds; ++k)
    if (fx.has(static_cast<EffectKind>(k))) ev.parameters += element_parameters(static_cast<EffectKind>(k));
  ev.data_points = data;
  ev.bic = 2.0 * nll + ev.parameters * std::log(static_cast<double>(data));
  ev.aic = 2.0 * nll + 2.0 * ev.parameters;

  // ---- error figures ----
  double rho = 0.0;
  for (int c = 0; c < k_channels; ++c) {
    const auto& y = d.window[static_cast<size_t>(c)];
    double rr = 0.0, yy = 0.0;
    for (size_t i = 0; i < y.size(); ++i) {
      const double tt = static_cast<double>(i) / d.fs_hz;
      double model_v = ev.static_pred[static_cast<size_t>(c)];
      for (int h = 1; h <= k_orders; ++h)
        model_v += (ev.order_pred[static_cast<size_t>(c)][static_cast<size_t>(h - 1)] *
                    std::exp(cd(0.0, k_two_pi * h * d.spin_hz * tt))).real();
      rr += (y[i] - model_v) * (y[i] - model_v);
      yy += y[i] * y[i];
    }
    if (c < 4 && d.has_rest) {
      const double n = static_cast<double>(d.rest_len);
      const double e = d.rest_mean_m[static_cast<size_t>(c)] - ev.rest_pred_m[static_cast<size_t>(c)];
      const double s = d.rest_std_m[static_cast<size_t>(c)];
      rr += n * (e * e + s * s);
      yy += n * (std::pow(d.rest_mean_m[static_cast<size_t>(c)], 2) + s * s);
    }
    rho += yy > 0 ? rr / yy : 0.0;
  }
  ev.error.rms = std::sqrt(rho / k_channels);
  if (d.has_rest) {
    double q = 0.0;
    for (int k = 0; k < 4; ++k)
      q += std::pow((d.rest_mean_m[static_cast<size_t>(k)] - ev.rest_pred_m[static_cast<size_t>(k)]) / b.plant.aux[static_cast<size_t>(k / 2)].clearance_m, 2);
    ev.error.statics = std::sqrt(q / 4.0);
  }
  double s2 = 0.0, pr = 0.0;
  for (int c = 0; c < k_channels; ++c) {
    std::vector<double> a(nb), p(nb);
    for (size_t i = 0; i < nb; ++i) {
      a[i] = std::log10(std::max(d.bands[i].psd[static_cast<size_t>(c)], 1e-300));
      p[i] = std::log10(ev.psd_pred[i][static_cast<size_t>(c)]);
      s2 += 100.0 * (a[i] - p[i]) * (a[i] - p[i]);
    }
    pr += pearson(a, p);
  }
  ev.error.spectral = nb ? std::sqrt(s2 / static_cast<double>(nb * k_channels)) : 0.0;
  ev.error.pearson = pr / k_channels;
  return ev;
}

}  // namespace amb::host::residual
