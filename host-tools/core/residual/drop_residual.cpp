#include "host-tools/core/residual/drop_residual.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <fftw3.h>
#include <stdexcept>

#include "host-tools/core/fit/drop_fit.hpp"
#include "host-tools/core/residual/steady_data.hpp"
#include "model/amb/amb_force.hpp"
#include "model/drop/sensor_orbit.hpp"

namespace amb::host::residual {
namespace {

using Readings = std::vector<std::array<double, 4>>;

std::string fmt(const char* f, double a, double b = 0, double c = 0, double d = 0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, f, a, b, c, d);
  return buf;
}

std::array<double, 2> rig_centre(const model::PlantParams& rig, int k) {
  const auto& a = rig.aux[static_cast<size_t>(k)];
  return {a.centre_offset_x_m, a.centre_offset_y_m};
}

std::vector<std::array<double, 2>> aux_points(const Readings& s, const model::drop::SensorOrbit& view, int k) {
  std::vector<std::array<double, 2>> p;
  p.reserve(s.size());
  for (const auto& r : s) p.push_back(view.at_aux_plane(r, k));
  return p;
}

// One-sided Welch PSD (Hann, 50 % overlap) averaged on 1/3-octave bands from f_lo to 0.4 fs.
std::vector<double> band_psd(const std::vector<double>& x, double fs, size_t seg, double f_lo) {
  std::vector<double> out;
  if (x.size() < seg || seg < 16) return out;
  std::vector<double> win(seg), buf(seg), psd(seg / 2 + 1, 0.0);
  double wss = 0.0;
  for (size_t i = 0; i < seg; ++i) {
    win[i] = 0.5 - 0.5 * std::cos(2.0 * M_PI * static_cast<double>(i) / static_cast<double>(seg));
    wss += win[i] * win[i];
  }
  std::vector<fftw_complex> spec(seg / 2 + 1);
  fftw_plan plan = fftw_plan_dft_r2c_1d(static_cast<int>(seg), buf.data(), spec.data(), FFTW_ESTIMATE);
  int count = 0;
  for (size_t start = 0; start + seg <= x.size(); start += seg / 2) {
    double mean = 0.0;
    for (size_t i = 0; i < seg; ++i) mean += x[start + i];
    mean /= static_cast<double>(seg);
    for (size_t i = 0; i < seg; ++i) buf[i] = (x[start + i] - mean) * win[i];
    fftw_execute(plan);
    for (size_t k = 0; k < psd.size(); ++k) psd[k] += 2.0 * (spec[k][0] * spec[k][0] + spec[k][1] * spec[k][1]) / (fs * wss);
    ++count;
  }
  fftw_destroy_plan(plan);
  const double df = fs / static_cast<double>(seg);
  for (double f = f_lo; f * std::pow(2.0, 1.0 / 6.0) < 0.4 * fs; f *= std::pow(2.0, 1.0 / 3.0)) {
    const auto a = static_cast<size_t>(std::ceil(f * std::pow(2.0, -1.0 / 6.0) / df));
    const auto e = static_cast<size_t>(std::floor(f * std::pow(2.0, 1.0 / 6.0) / df));
    double s = 0.0;
    int n = 0;
    for (size_t k = std::max<size_t>(a, 1); k <= e && k < psd.size(); ++k, ++n) s += psd[k];
    if (n > 0) out.push_back(s / (n * count) + 1e-300);
  }
  return out;
}

double pearson(const std::vector<double>& a, const std::vector<double>& b) {
  const size_t n = std::min(a.size(), b.size());
  if (n < 3) return 0.0;
  double ma = 0, mb = 0;
  for (size_t i = 0; i < n; ++i) ma += a[i], mb += b[i];
  ma /= static_cast<double>(n);
  mb /= static_cast<double>(n);
  double sab = 0, saa = 0, sbb = 0;
  for (size_t i = 0; i < n; ++i) {
    sab += (a[i] - ma) * (b[i] - mb);
    saa += (a[i] - ma) * (a[i] - ma);
    sbb += (b[i] - mb) * (b[i] - mb);
  }
  return saa > 0 && sbb > 0 ? sab / std::sqrt(saa * sbb) : 0.0;
}

DropErrors evaluate(const fit::DropMeasurement& m, const fit::DropFitResult& f, const model::PlantParams& rig,
                    const DropResidualOptions& o) {
  DropErrors e;
  e.cost = f.cost.total;
  e.friction_coefficient = f.friction_coefficient;
  const auto first = static_cast<size_t>(m.trigger_index);
  const size_t n = std::min(m.sensor_m.size() - first, f.trace.samples.size());
  Readings meas(m.sensor_m.begin() + static_cast<long>(first), m.sensor_m.begin() + static_cast<long>(first + n));
  Readings sim;
  sim.reserve(n);
  for (size_t i = 0; i < n; ++i) sim.push_back(f.trace.samples[i].sensor_m);
  const double c0 = rig.aux[0].clearance_m;
  const model::drop::SensorOrbit view(rig);
  // Orbit distance at the sensor planes over the first impacts.
  const size_t w = std::min(n, static_cast<size_t>(std::lround(o.orbit_error_window_s * m.sample_rate_hz)));
  double s2 = 0.0;
  for (size_t i = 0; i < w; ++i)
    for (int p = 0; p < 2; ++p) {
      const auto a = view.at_sensor_plane(meas[i], p), b = view.at_sensor_plane(sim[i], p);
      s2 += (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]);
    }
  e.error.rms = w > 0 ? std::sqrt(s2 / (2.0 * static_cast<double>(w))) / c0 : 0.0;
  // Spectra of the four sensors after the trigger.
  const auto seg = static_cast<size_t>(std::lround(0.05 * m.sample_rate_hz));
  double db2 = 0.0, pear = 0.0;
  int bands = 0, chans = 0;
  for (int c = 0; c < 4; ++c) {
    std::vector<double> xm(n), xs(n);
    for (size_t i = 0; i < n; ++i) xm[i] = meas[i][static_cast<size_t>(c)], xs[i] = sim[i][static_cast<size_t>(c)];
    const auto pm = band_psd(xm, m.sample_rate_hz, seg, 20.0), ps = band_psd(xs, m.sample_rate_hz, seg, 20.0);
    if (pm.empty() || pm.size() != ps.size()) continue;
    std::vector<double> lm, ls;
    for (size_t k = 0; k < pm.size(); ++k) {
      const double d = 10.0 * std::log10(pm[k] / ps[k]);
      db2 += d * d;
      ++bands;
      lm.push_back(std::log10(pm[k]));
      ls.push_back(std::log10(ps[k]));
    }
    pear += pearson(lm, ls);
    ++chans;
  }
  e.error.spectral = bands > 0 ? std::sqrt(db2 / bands) : 0.0;
  e.error.pearson = chans > 0 ? pear / chans : 0.0;
  // Contact geometry: measured contact points about the model's centres, corrected by the
  // estimator's bias seen on the simulation.
  e.measured_circle = estimate_contact_circles(meas, rig, m.sample_rate_hz, o);
  e.simulated_circle = estimate_contact_circles(sim, rig, m.sample_rate_hz, o);
  std::array<std::array<double, 2>, 2> ref{};
  for (int k = 0; k < 2; ++k) {
    e.model_centre_m[static_cast<size_t>(k)] = rig_centre(rig, k);
    ref[static_cast<size_t>(k)] = e.simulated_circle[static_cast<size_t>(k)].valid
                                      ? e.simulated_circle[static_cast<size_t>(k)].centre_m
                                      : e.model_centre_m[static_cast<size_t>(k)];
  }
  const auto mis = contact_misfit(meas, rig, ref, o);
  double st2 = 0.0;
  for (int k = 0; k < 2; ++k) {
    const auto& [rms, cnt] = mis[static_cast<size_t>(k)];
    const double r = rms / rig.aux[static_cast<size_t>(k)].clearance_m;
    st2 += r * r;
    e.misfit_ssr_m2 += rms * rms * cnt;
    e.misfit_points += cnt;
  }
  e.error.statics = std::sqrt(st2 / 2.0);
  return e;
}

// BIC decrease of the aux-bearing offset (4 parameters) from the contact scatter before and
// after, with `points` contact samples decorrelated over o.decorrelation_s.
double offset_delta_bic(double ssr_before, double ssr_after, int points, double fs, const DropResidualOptions& o) {
  const double n_eff = std::max(1.0, points * std::min(1.0, 1.0 / (fs * o.decorrelation_s)));
  return ssr_before > 0 && ssr_after > 0 ? n_eff * std::log(ssr_before / ssr_after) - 4.0 * std::log(n_eff) : 0.0;
}

ErrorFigures combine(const ErrorFigures& a, const ErrorFigures& b) {
  auto q = [](double x, double y) { return std::sqrt(0.5 * (x * x + y * y)); };
  return {q(a.rms, b.rms), q(a.spectral, b.spectral), 0.5 * (a.pearson + b.pearson), q(a.statics, b.statics)};
}

}  // namespace

std::array<ContactCircle, 2> estimate_contact_circles(const Readings& sensor_m, const model::PlantParams& rig,
                                                      double fs_hz, const DropResidualOptions& o) {
  std::array<ContactCircle, 2> out{};
  const model::drop::SensorOrbit view(rig);
  const double per_point = std::min(1.0, 1.0 / (fs_hz * o.decorrelation_s));  // independent points per sample
  for (int k = 0; k < 2; ++k) {
    const double R = rig.aux[static_cast<size_t>(k)].clearance_m;
    const auto pts = aux_points(sensor_m, view, k);
    // Unknowns: centre (x, y) and the effective contact radius (clearance plus the mean
    // contact deflection and the sensor view's bias), a nuisance parameter.
    Eigen::Vector3d c(rig_centre(rig, k)[0], rig_centre(rig, k)[1], R);
    ContactCircle& cc = out[static_cast<size_t>(k)];
    Eigen::Matrix3d jtj = Eigen::Matrix3d::Zero();
    double ss = 0.0;
    int used = 0;
    for (int it = 0; it < 40; ++it) {
      jtj.setZero();
      Eigen::Vector3d jtr = Eigen::Vector3d::Zero();
      ss = 0.0;
      used = 0;
      for (const auto& p : pts) {
        const Eigen::Vector2d d(p[0] - c[0], p[1] - c[1]);
        const double rho = d.norm();
        if (rho < o.contact_band * R || rho <= 0) continue;
        const Eigen::Vector3d j(-d[0] / rho, -d[1] / rho, -1.0);  // d(rho - R_eff)/d(cx, cy, R_eff)
        const double r = rho - c[2];
        jtj += j * j.transpose();
        jtr += j * r;
        ss += r * r;
        ++used;
      }
      if (static_cast<double>(used) * per_point < 20.0) break;
      // A short arc leaves the radius and the centre along the arc's normal confounded.
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(jtj);
      if (es.eigenvalues()[0] < 1e-3 * es.eigenvalues()[2]) break;
      const Eigen::Vector3d dc = -jtj.ldlt().solve(jtr);
      c += dc;
      if (dc.norm() < 1e-10) {
        cc.valid = true;
        break;
      }
    }
    if (!cc.valid || used < 3) {
      cc.valid = false;
      continue;
    }
    cc.centre_m = {c[0], c[1]};
    cc.radius_m = c[2];
    cc.points = used;
    cc.misfit_rms_m = std::sqrt(ss / used);
    // Covariance with decorrelated points: s^2 (J^T J)^-1 / per_point.
    const Eigen::Matrix3d cov = (ss / used) * jtj.inverse() / per_point;
    cc.sigma_m = std::sqrt(std::max(cov(0, 0), cov(1, 1)));
  }
  return out;
}

std::array<std::pair<double, int>, 2> contact_misfit(const Readings& sensor_m, const model::PlantParams& rig,
                                                     const std::array<std::array<double, 2>, 2>& centre_m,
                                                     const DropResidualOptions& o) {
  std::array<std::pair<double, int>, 2> out{};
  const model::drop::SensorOrbit view(rig);
  for (int k = 0; k < 2; ++k) {
    const double R = rig.aux[static_cast<size_t>(k)].clearance_m;
    // Radial scatter about `centre` (the effective radius is the mean radius: a nuisance).
    std::vector<double> rho;
    for (const auto& p : aux_points(sensor_m, view, k)) {
      const double r = std::hypot(p[0] - centre_m[static_cast<size_t>(k)][0], p[1] - centre_m[static_cast<size_t>(k)][1]);
      if (r >= o.contact_band * R) rho.push_back(r);
    }
    const int n = static_cast<int>(rho.size());
    double mean = 0.0, ss = 0.0;
    for (double r : rho) mean += r;
    mean /= std::max(n, 1);
    for (double r : rho) ss += (r - mean) * (r - mean);
    out[static_cast<size_t>(k)] = {n > 0 ? std::sqrt(ss / n) : 0.0, n};
  }
  return out;
}

bool is_drop_event(const LoadedEvent& r, const board::BoardConfig& b, std::string* why) {
  auto no = [&](const std::string& s) {
    if (why != nullptr) *why = s;
    return false;
  };
  const size_t n = r.samples();
  const double fs = r.sample_rate_hz;
  if (r.trigger_index == 0 || r.trigger_index >= n || static_cast<double>(n - r.trigger_index) < 0.05 * fs)
    return no("no trigger with at least 50 ms after it");
  const ChannelMap map = match_channels(r);
  const auto trig = static_cast<size_t>(r.trigger_index);
  double lim = 1e9;
  for (const auto& a : b.plant.amb) lim = std::min(lim, a.coil_current_limit_a);
  // Currents after the trigger (10 ms on, the amplifiers' decay): near zero at most samples.
  size_t quiet = 0, total = 0;
  for (size_t i = trig + static_cast<size_t>(0.01 * fs); i < n; ++i, ++total) {
    double m = 0.0;
    for (int j = 4; j < 8; ++j) m = std::max(m, std::abs(map[j][i]));
    if (m < 0.02 * lim) ++quiet;
  }
  if (total == 0 || static_cast<double>(quiet) < 0.9 * static_cast<double>(total))
    return no("the coil currents do not stay near zero after the trigger (not an amplifier cut-off)");
  Readings s(n - trig);
  for (size_t i = trig; i < n; ++i)
    for (int k = 0; k < 4; ++k) s[i - trig][static_cast<size_t>(k)] = map[k][i];
  const model::drop::SensorOrbit view(b.plant);
  double reach = 0.0;
  for (int k = 0; k < 2; ++k)
    for (const auto& p : aux_points(s, view, k))
      reach = std::max(reach, std::hypot(p[0] - rig_centre(b.plant, k)[0], p[1] - rig_centre(b.plant, k)[1]) /
                                  b.plant.aux[static_cast<size_t>(k)].clearance_m);
  if (reach < 0.8) return no("the orbit does not reach the auxiliary bearings after the trigger");
  return true;
}

fit::DropMeasurement drop_measurement_of(const LoadedEvent& r, const board::BoardConfig& b, const DropResidualOptions& o) {
  (void)b;
  const ChannelMap map = match_channels(r);
  fit::DropMeasurement m;
  m.source = r.source;
  m.rig = r.rig;
  m.sample_rate_hz = r.sample_rate_hz;
  const size_t trig = r.trigger_index;
  const size_t first = trig - std::min(trig, static_cast<size_t>(0.02 * r.sample_rate_hz));
  const size_t end = std::min(r.samples(), trig + static_cast<size_t>(std::lround(o.window_s * r.sample_rate_hz)));
  m.trigger_index = static_cast<int>(trig - first);
  for (size_t i = first; i < end; ++i) {
    std::array<double, 4> s{};
    for (int k = 0; k < 4; ++k) s[static_cast<size_t>(k)] = map[k][i];
    m.sensor_m.push_back(s);
    if (map.speed_hz != nullptr) m.speed_rad_s.push_back(2.0 * M_PI * (*map.speed_hz)[i]);
  }
  m.speed_at_trigger_hz = map.speed_hz != nullptr ? (*map.speed_hz)[trig] : r.speed_at_trigger_hz.value_or(0.0);
  m.amplifiers_off = true;
  return m;
}

DropResidualOutcome run_drop_residual(const LoadedEvent& r, const board::BoardConfig& b, const DropResidualOptions& o) {
  std::string why;
  if (!is_drop_event(r, b, &why)) throw std::runtime_error("event " + r.source + " is not a drop event: " + why);
  DropResidualOutcome out;
  const double fs = r.sample_rate_hz;
  const auto trig = static_cast<size_t>(r.trigger_index);

  size_t runout_window_start = 0;
  double runout_spin_hz = 0.0;
  // Levitated part: the steady loop on the pre-trigger history.
  const double lev_s = static_cast<double>(trig) / fs;
  if (lev_s >= o.min_levitated_s) {
    LoadedEvent pre = slice_event(r, 0, trig);
    pre.trigger_index = 0;
    SteadyOptions so;
    so.window_s = std::min(so.window_s, lev_s - 0.05);
    try {
      const SteadyData d = extract_steady(pre, b, so);
      out.levitated = run_residual_loop(d, b, o.loop);
      out.levitated_analysed = true;
      runout_window_start = d.window_start;
      runout_spin_hz = d.spin_hz;
    } catch (const std::runtime_error& e) {
      out.levitated_note = std::string("levitated part not analysed: ") + e.what();
    }
  } else {
    out.levitated_note = fmt("levitated part not analysed: %.2f s of pre-trigger history < %.2f s", lev_s, o.min_levitated_s);
  }

  // Drop part: fit the drop model, then look at the contact geometry.
  fit::DropMeasurement m = drop_measurement_of(r, b, o);
  // Runout found in the levitated part is a measurement artefact: it stays in the readings
  // when the rotor falls. Subtract it, with the rotor angle carried on from the levitated
  // window through the recorded speed (scaled to the refined speed at the trigger).
  bool runout_found = false;
  for (const auto& e : out.levitated.effects_added) runout_found = runout_found || e.name == "sensor_runout";
  if (out.levitated_analysed && runout_found && out.levitated.after.effects.runout && runout_spin_hz > 0.0) {
    const auto& ro = *out.levitated.after.effects.runout;
    const size_t first = trig - static_cast<size_t>(m.trigger_index);
    const double f_trig = m.speed_rad_s.empty() ? 0.0 : m.speed_rad_s[static_cast<size_t>(m.trigger_index)] / (2.0 * M_PI);
    double theta = 2.0 * M_PI * runout_spin_hz * (static_cast<double>(first) - static_cast<double>(runout_window_start)) / fs;
    for (size_t i = 0; i < m.sensor_m.size(); ++i) {
      for (int k = 0; k < 4; ++k) {
        const auto dir = model::magnet::axis_direction(b.plant.sensor[static_cast<size_t>(k)].angle_deg);
        double v = 0.0;
        for (int h = 1; h <= model::effects::k_runout_orders; ++h)
          v += (ro.r_m[static_cast<size_t>(k / 2)][static_cast<size_t>(h - 1)] * std::complex<double>(dir[0], -dir[1]) *
                std::exp(std::complex<double>(0.0, h * theta))).real();
        m.sensor_m[i][static_cast<size_t>(k)] -= v;
      }
      const bool after_trigger = i >= static_cast<size_t>(m.trigger_index) && f_trig > 0.0 && !m.speed_rad_s.empty();
      const double f_now = after_trigger ? runout_spin_hz * m.speed_rad_s[i] / (2.0 * M_PI) / f_trig : runout_spin_hz;
      theta += 2.0 * M_PI * f_now / fs;
    }
    out.drop_notes.push_back(fmt("runout of the levitated part subtracted from the drop readings (plane A 1x %.1f um, plane B 1x %.1f um)",
                                 std::abs(ro.r_m[0][0]) * 1e6, std::abs(ro.r_m[1][0]) * 1e6));
  }
  if (const auto err = m.check(); !err.empty()) throw std::runtime_error("event " + r.source + ": drop part: " + err);
  fit::DropFitOptions fo;
  fo.max_window_s = o.window_s;
  // Model updating of the drop part: the contact law is an uncertain part of the drop model
  // (a real touchdown contact is compliant; the board states one law). The drop model is
  // fitted with each law (board's first) and the one with the lowest Phase C cost is kept.
  board::BoardConfig bu = b;
  fit::DropFitResult base = fit::fit_drop(m, bu, fo);
  const char* law_name[3] = {"rigid", "hertz", "linear"};
  if (o.update_contact_law) {
    const model::AuxContactLaw board_law = b.plant.aux[0].contact_law;
    for (model::AuxContactLaw law : {model::AuxContactLaw::rigid, model::AuxContactLaw::hertz, model::AuxContactLaw::linear}) {
      if (law == board_law) continue;
      board::BoardConfig bl = b;
      for (auto& a : bl.plant.aux) a.contact_law = law;
      try {
        fit::DropFitResult f = fit::fit_drop(m, bl, fo);
        out.drop_notes.push_back(std::string("contact law ") + law_name[static_cast<int>(law)] +
                                 fmt(": friction %.3f, Phase C cost %.4g", f.friction_coefficient, f.cost.total));
        if (f.cost.total < base.cost.total) {
          base = std::move(f);
          bu = bl;
        }
      } catch (const std::exception& e) {
        out.drop_notes.push_back(std::string("contact law ") + law_name[static_cast<int>(law)] + " not fitted: " + e.what());
      }
    }
  }
  out.contact_law = law_name[static_cast<int>(bu.plant.aux[0].contact_law)];
  out.drop_before = evaluate(m, base, bu.plant, o);
  out.drop_after = out.drop_before;
  out.drop_notes.push_back(fmt("drop model fitted: friction coefficient %.3f, Phase C cost %.4g", base.friction_coefficient,
                               base.cost.total) + ", contact law " + out.contact_law);
  CandidateScore cand;
  cand.name = "aux_bearing_offset";
  std::array<std::array<double, 2>, 2> delta{};
  bool significant = false, testable = true;
  for (int k = 0; k < 2; ++k) {
    const auto& mc = out.drop_before.measured_circle[static_cast<size_t>(k)];
    const auto& sc = out.drop_before.simulated_circle[static_cast<size_t>(k)];
    const double R = b.plant.aux[static_cast<size_t>(k)].clearance_m;
    if (!mc.valid || !sc.valid) {
      testable = false;
      out.drop_notes.push_back(fmt("aux bearing %.0f: too few contact points for the circle fit", k));
      continue;
    }
    delta[static_cast<size_t>(k)] = {mc.centre_m[0] - sc.centre_m[0], mc.centre_m[1] - sc.centre_m[1]};
    const double dn = std::hypot(delta[static_cast<size_t>(k)][0], delta[static_cast<size_t>(k)][1]);
    const double sig = std::hypot(mc.sigma_m, sc.sigma_m);
    // The bias correction is the fitted drop model's: when that model does not match the
    // contact (rigid vs compliant, other friction), its bias can itself be the difference. An
    // offset is claimed only when the raw measured centre is also off the model's centre.
    const auto& mcen = out.drop_before.model_centre_m[static_cast<size_t>(k)];
    const double raw = std::hypot(mc.centre_m[0] - mcen[0], mc.centre_m[1] - mcen[1]);
    const bool sig_k = dn > std::max(4.0 * sig, o.min_offset_fraction * R) && raw > std::max(4.0 * mc.sigma_m, o.min_offset_fraction * R);
    significant = significant || sig_k;
    out.drop_notes.push_back(fmt("aux bearing %.0f: contact circle centre %+.1f / %+.1f um from the model's (sigma %.1f um)", k,
                                 delta[static_cast<size_t>(k)][0] * 1e6, delta[static_cast<size_t>(k)][1] * 1e6, sig * 1e6) +
                             (sig_k ? " -- significant" : ""));
  }
  cand.testable = testable;
  if (testable) {
    // Candidate score without refit: the scatter about the measured circles' centres
    // (= the bias-corrected model centres moved by delta).
    const size_t first = static_cast<size_t>(m.trigger_index);
    const Readings meas(m.sensor_m.begin() + static_cast<long>(first), m.sensor_m.end());
    const auto mis = contact_misfit(meas, b.plant,
                                    {out.drop_before.measured_circle[0].centre_m, out.drop_before.measured_circle[1].centre_m}, o);
    double ssr = 0.0;
    for (const auto& [rms, cnt] : mis) ssr += rms * rms * cnt;
    cand.delta_bic = offset_delta_bic(out.drop_before.misfit_ssr_m2, ssr, out.drop_before.misfit_points, fs, o);
    const double n_eff = std::max(1.0, out.drop_before.misfit_points * std::min(1.0, 1.0 / (fs * o.decorrelation_s)));
    cand.evidence = fmt("contact circles off the model's centres by %.1f and %.1f um (%.0f decorrelated contact points)",
                        std::hypot(delta[0][0], delta[0][1]) * 1e6, std::hypot(delta[1][0], delta[1][1]) * 1e6, n_eff);
    cand.evidence += significant ? "" : "; within the estimator's uncertainty";
  } else {
    cand.evidence = "not testable: the rotor touched an aux bearing too briefly for a circle fit";
  }
  out.drop_ranking.push_back(cand);

  if (testable && significant && cand.delta_bic > o.loop.min_delta_bic) {
    board::BoardConfig b2 = bu;
    for (int k = 0; k < 2; ++k) {
      b2.plant.aux[static_cast<size_t>(k)].centre_offset_x_m += delta[static_cast<size_t>(k)][0];
      b2.plant.aux[static_cast<size_t>(k)].centre_offset_y_m += delta[static_cast<size_t>(k)][1];
    }
    const fit::DropFitResult refit = fit::fit_drop(m, b2, fo);
    const DropErrors after = evaluate(m, refit, b2.plant, o);
    const double dbic = offset_delta_bic(out.drop_before.misfit_ssr_m2, after.misfit_ssr_m2, out.drop_before.misfit_points, fs, o);
    const bool material = after.error.statics <= (1.0 - o.loop.min_relative_improvement) * out.drop_before.error.statics;
    out.drop_notes.push_back(fmt("refit with the offset: friction %.3f, contact misfit %.4g -> %.4g of the clearance, dBIC %.1f",
                                 refit.friction_coefficient, out.drop_before.error.statics, after.error.statics, dbic));
    // Kept only if every drop-part error falls (orbit rms, spectral, contact misfit; Pearson rises).
    const auto& e0 = out.drop_before.error;
    // (a change within 1 % counts as unchanged, as in the steady loop)
    const double tol = 0.01;
    const bool all_fall = after.error.rms <= e0.rms * (1.0 + tol) && after.error.spectral <= e0.spectral * (1.0 + tol) &&
                          after.error.pearson >= e0.pearson * (1.0 - tol) && after.error.statics <= e0.statics * (1.0 + tol);
    out.drop_notes.push_back(fmt("with the offset: orbit rms %.4f -> %.4f, spectral %.2f -> %.2f dB", e0.rms, after.error.rms,
                                 e0.spectral, after.error.spectral) +
                             fmt(", pearson %.3f -> %.3f", e0.pearson, after.error.pearson));
    if (dbic > o.loop.min_delta_bic && material && all_fall) {
      out.drop_after = after;
      EffectAdded e;
      e.name = "aux_bearing_offset";
      e.parameters = {{"x0_m", delta[0][0]}, {"y0_m", delta[0][1]}, {"x1_m", delta[1][0]}, {"y1_m", delta[1][1]},
                      {"friction_coefficient", refit.friction_coefficient}};
      e.evidence = cand.evidence;
      e.delta_bic = dbic;
      out.effects_added.push_back(e);
    } else {
      out.drop_notes.push_back(all_fall ? "aux_bearing_offset not kept: it does not earn its parameters"
                                        : "aux_bearing_offset not kept: a drop-part error rises with it");
    }
  }

  std::vector<EffectAdded> all = out.levitated_analysed ? out.levitated.effects_added : std::vector<EffectAdded>{};
  all.insert(all.end(), out.effects_added.begin(), out.effects_added.end());
  out.effects_added = all;
  if (out.levitated_analysed) {
    out.before = combine(out.levitated.before.error, out.drop_before.error);
    out.after = combine(out.levitated.after.error, out.drop_after.error);
  } else {
    out.before = out.drop_before.error;
    out.after = out.drop_after.error;
  }
  out.verdict.clear();
  for (const auto& e : out.effects_added) out.verdict += (out.verdict.empty() ? "" : "+") + e.name;
  if (out.verdict.empty()) out.verdict = "none";
  return out;
}

}  // namespace amb::host::residual
