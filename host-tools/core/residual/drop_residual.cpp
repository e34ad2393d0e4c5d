#include "host-tools/core/io/number_text.hpp"
#include "host-tools/core/residual/drop_residual.hpp"
#include "host-tools/core/residual/contact_view.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <fftw3.h>
#include <limits>
#include <optional>
#include <stdexcept>

#include "model/signal/pearson.hpp"
#include "host-tools/core/fit/drop_fit.hpp"
#include "host-tools/core/residual/candidate_report.hpp"
#include "host-tools/core/residual/engine/elements.hpp"
#include "host-tools/core/residual/steady_data.hpp"
#include "model/amb/amb_force.hpp"
#include "model/drop/sensor_orbit.hpp"

namespace amb::host::residual {
namespace {

using Readings = std::vector<std::array<double, 4>>;


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
std::vector<double> band_psd(const std::vector<double>& x, double fs, size_t seg, double f_lo,
                             std::vector<double>* centres = nullptr) {
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
    if (n > 0) {
      out.push_back(s / (n * count) + 1e-300);
      if (centres != nullptr) centres->push_back(f);
    }
  }
  return out;
}

using model::signal::pearson;  // one definition: model/signal/pearson.hpp

// `sag`: the board rotor's sag bias of the straight-line view (gravity_sag_view_shift_m),
// computed once per event (it does not depend on the aux-bearing offsets the refits move).
DropErrors evaluate(const fit::DropMeasurement& m, const fit::DropFitResult& f, const model::PlantParams& rig,
                    const DropResidualOptions& o, const SagViewShift& sag, const ContactView& contact_view) {
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
  (void)band_psd(std::vector<double>(n, 0.0), m.sample_rate_hz, seg, 20.0, &e.band_hz);
  for (int c = 0; c < 4; ++c) {
    std::vector<double> xm(n), xs(n);
    for (size_t i = 0; i < n; ++i) xm[i] = meas[i][static_cast<size_t>(c)], xs[i] = sim[i][static_cast<size_t>(c)];
    const auto pm = band_psd(xm, m.sample_rate_hz, seg, 20.0), ps = band_psd(xs, m.sample_rate_hz, seg, 20.0);
    if (pm.empty() || pm.size() != ps.size()) continue;
    std::vector<double> lm, ls;
    auto& plane_db = e.band_db[static_cast<size_t>(c / 2)];
    if (plane_db.size() < pm.size()) plane_db.resize(pm.size(), 0.0);
    for (size_t k = 0; k < pm.size(); ++k) {
      const double d = 10.0 * std::log10(pm[k] / ps[k]);
      plane_db[k] += 0.5 * d;
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
  // With a flexible board rotor both sides are read at the aux planes themselves: the
  // record through the rotor's bending (ContactView), the simulation from its own rotor
  // centre there (exact for a rigid or a flexible drop model).
  Readings meas_c = meas, sim_c = sim;
  if (contact_view.flexible()) {
    meas_c = contact_view.contact_readings(meas, m.sample_rate_hz);
    std::vector<std::array<double, 4>> aux(n);
    for (size_t i = 0; i < n; ++i) {
      const auto& sm = f.trace.samples[i];
      aux[i] = {sm.aux_x_m[0], sm.aux_y_m[0], sm.aux_x_m[1], sm.aux_y_m[1]};
    }
    sim_c = contact_view.from_aux_planes(aux);
  }
  e.measured_circle = estimate_contact_circles(meas_c, rig, m.sample_rate_hz, o);
  e.simulated_circle = estimate_contact_circles(sim_c, rig, m.sample_rate_hz, o);
  // A rigid drop model (chosen by the drop cost) has no shaft sag between the aux contacts,
  // which the straight-line sensor view of the board's flexible rotor reads as centres lower
  // by the static sag: that bias is added to the simulated circles (the main job's drop: the
  // offsets came out 11 um low without it; forcing the flexible drop model instead fitted the
  // drop far worse, cost 14 against 2.7).
  // In contact the shaft carries more than its weight: the inertia of a decelerated rotor is
  // distributed as its mass is, so the sag scales with the mean downward contact force over
  // the contact samples (from the fitted simulation) against the weight.
  if (!contact_view.flexible() && sag.weight_n > 0.0 && f.rotor_modes_per_plane == 2 && rig.rotor.modes_kept != 2) {
    double fy = 0.0, weight = 0.0;
    std::array<double, 2> fk{};
    std::array<int, 2> nk{};
    for (size_t i = 0; i < n; ++i) {
      const auto& sm = f.trace.samples[i];
      for (size_t k = 0; k < 2; ++k)
        if (sm.contact_fraction[k] > 0.5) {
          const double r = std::hypot(sm.aux_x_m[k] - rig.aux[k].centre_offset_x_m, sm.aux_y_m[k] - rig.aux[k].centre_offset_y_m);
          if (r > 0.0) fk[k] += -sm.normal_n[k] * (sm.aux_y_m[k] - rig.aux[k].centre_offset_y_m) / r;
          ++nk[k];
        }
    }
    for (size_t k = 0; k < 2; ++k) fy += nk[k] > 0 ? fk[k] / nk[k] : 0.0;
    weight = sag.weight_n;
    const double scale = weight > 0.0 && fy > weight ? fy / weight : 1.0;
    e.sag_scale = scale;
    for (size_t k = 0; k < 2; ++k)
      if (e.simulated_circle[k].valid) e.simulated_circle[k].centre_m[1] += scale * sag.shift_m[k];
  }
  std::array<std::array<double, 2>, 2> ref{};
  for (int k = 0; k < 2; ++k) {
    const auto& mc = e.measured_circle[static_cast<size_t>(k)];
    const auto& sc = e.simulated_circle[static_cast<size_t>(k)];
    e.radius_excess_m[static_cast<size_t>(k)] = mc.valid && sc.valid ? mc.radius_m - sc.radius_m : 0.0;
    e.model_centre_m[static_cast<size_t>(k)] = rig_centre(rig, k);
    ref[static_cast<size_t>(k)] = e.simulated_circle[static_cast<size_t>(k)].valid
                                      ? e.simulated_circle[static_cast<size_t>(k)].centre_m
                                      : e.model_centre_m[static_cast<size_t>(k)];
  }
  const auto mis = contact_misfit(meas_c, rig, ref, o);
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

// Samples from `first` on for which a recorded speed stream (Hz) is the rotor's spin: finite,
// above 5 % of `f_ref`, and changing no faster than `max_accel` (rad/s^2) allows. A stream
// that drops faster than any friction can brake the rotor (a lost tracker, a speed command
// set to zero at the fault) is not a spin record from there on.
size_t spin_record_length(const std::vector<double>& f_hz, size_t first, double f_ref, double fs, double max_accel) {
  const double max_step = max_accel / (2.0 * M_PI * fs) + 1e-3 * f_ref;
  double prev = f_ref;
  size_t n = 0;
  for (size_t i = first; i < f_hz.size(); ++i, ++n) {
    const double f = f_hz[i];
    if (!(std::isfinite(f) && f > 0.05 * f_ref && std::abs(f - prev) <= max_step)) break;
    prev = f;
  }
  return n;
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
    // Band samples inside the clearance are flight, not contact: after a first fit, samples
    // whose radial residual is beyond o.trim_sigma robust scales (1.4826 MAD) of its median are
    // left out and the circle refitted, twice (as the runout and gain estimators do).
    double lo = -1e9, hi = 1e9;
    for (int pass = 0; pass < 3; ++pass) {
      cc.valid = false;
      for (int it = 0; it < 40; ++it) {
        jtj.setZero();
        Eigen::Vector3d jtr = Eigen::Vector3d::Zero();
        ss = 0.0;
        used = 0;
        for (const auto& p : pts) {
          const Eigen::Vector2d d(p[0] - c[0], p[1] - c[1]);
          const double rho = d.norm();
          if (rho < o.contact_band * R || rho <= 0) continue;
          const double r = rho - c[2];
          if (r < lo || r > hi) continue;
          const Eigen::Vector3d j(-d[0] / rho, -d[1] / rho, -1.0);  // d(rho - R_eff)/d(cx, cy, R_eff)
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
      if (!cc.valid || pass == 2) break;
      std::vector<double> res;
      for (const auto& p : pts) {
        const double rho = std::hypot(p[0] - c[0], p[1] - c[1]);
        if (rho >= o.contact_band * R && rho > 0) res.push_back(rho - c[2]);
      }
      if (res.size() < 10) break;
      std::vector<double> v = res;
      std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
      const double med = v[v.size() / 2];
      for (auto& x : v) x = std::abs(x - med);
      std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
      const double scale = 1.4826 * v[v.size() / 2];
      if (!(scale > 0.0)) break;
      lo = med - o.contact_trim_sigma * scale;
      hi = med + o.contact_trim_sigma * scale;
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
  // The fit compares spin-down and speed: give it the speed stream only when it is the
  // rotor's spin through the whole window (else the spin is not measured after the trigger).
  if (!m.speed_rad_s.empty()) {
    std::vector<double> f_hz;
    for (double w : m.speed_rad_s) f_hz.push_back(w / (2.0 * M_PI));
    const size_t after = m.sensor_m.size() - static_cast<size_t>(m.trigger_index);
    if (spin_record_length(f_hz, static_cast<size_t>(m.trigger_index), m.speed_at_trigger_hz, m.sample_rate_hz,
                           o.max_spin_accel_rad_s2) < after)
      m.speed_rad_s.clear();
  }
  return m;
}

DropResidualOutcome run_drop_residual(const LoadedEvent& r, const board::BoardConfig& b, const DropResidualOptions& o) {
  std::string why;
  if (!is_drop_event(r, b, &why)) throw std::runtime_error("event " + r.source + " is not a drop event: " + why);
  DropResidualOutcome out;
  const double fs = r.sample_rate_hz;
  const auto trig = static_cast<size_t>(r.trigger_index);
  // The board's rig model, built once and shared by every model of this run (model/rig).
  const std::shared_ptr<const model::RigModel> rig_model = o.loop.rig_model ? o.loop.rig_model : model::RigModel::make(b.plant);
  LoopOptions loop = o.loop;
  loop.rig_model = rig_model;
  const auto say = [&o](const std::string& line) {
    if (o.progress) o.progress(line);
  };

  size_t lev_window_start = 0;
  std::optional<SteadyData> lev_data;
  std::optional<SteadyEvaluation> lev_with_runout;  // the levitated part with the drop's runout held
  double lev_spin_hz = 0.0;
  // Levitated part: the steady loop on the pre-trigger history.
  const double lev_s = static_cast<double>(trig) / fs;
  if (lev_s >= o.min_levitated_s) {
    LoadedEvent pre = slice_event(r, 0, trig);
    pre.trigger_index = 0;
    SteadyOptions so;
    so.window_s = std::min(so.window_s, lev_s - 0.05);
    try {
      const SteadyData d = extract_steady(pre, b, so);
      say("levitated part (" + std::to_string(static_cast<int>(lev_s * 1000.0)) + " ms): steady loop");
      out.levitated = run_residual_loop(d, b, loop);
      lev_data = d;
      out.levitated_analysed = true;
      lev_window_start = d.window_start;
      lev_spin_hz = d.spin_hz;
    } catch (const std::runtime_error& e) {
      out.levitated_note = std::string("levitated part not analysed: ") + e.what();
    }
  } else {
    out.levitated_note = io::printf_text("levitated part not analysed: %.2f s of pre-trigger history < %.2f s", lev_s, o.min_levitated_s);
  }

  // Drop part, the measurement as recorded.
  fit::DropMeasurement m = drop_measurement_of(r, b, o);
  if (const auto err = m.check(); !err.empty()) throw std::runtime_error("event " + r.source + ": drop part: " + err);
  const auto first = static_cast<size_t>(m.trigger_index);  // the trigger within m
  // Rotor angle over m, in the levitated window's reference (so that the levitated part's
  // runout phasors apply): the refined levitated speed before the trigger, the recorded
  // speed after it (scaled to the refined speed at the trigger) as long as it is a spin
  // record -- a stream that drops faster than any friction can brake the rotor (a lost
  // tracker, a speed command) is not, and from there on the angle is unknown.
  const SpinAngle angle = [&] {
    SpinAngle a;
    const ChannelMap map = match_channels(r);
    const size_t n = m.sensor_m.size(), rec_first = trig - first;
    std::vector<double> f_hz;
    if (map.speed_hz != nullptr) f_hz.assign(map.speed_hz->begin() + static_cast<long>(rec_first), map.speed_hz->begin() + static_cast<long>(rec_first + n));
    const double f_chan_trig = f_hz.size() > first ? f_hz[first] : 0.0;
    const double f_ref = lev_spin_hz > 0.0 ? lev_spin_hz : (f_chan_trig > 0.0 ? f_chan_trig : m.speed_at_trigger_hz);
    const double scale = f_chan_trig > 0.0 && f_ref > 0.0 ? f_ref / f_chan_trig : 1.0;
    const size_t valid = f_hz.empty() ? 0 : spin_record_length(f_hz, first, f_chan_trig, fs, o.max_spin_accel_rad_s2);
    double theta = out.levitated_analysed ? 2.0 * M_PI * lev_spin_hz * (static_cast<double>(rec_first) - static_cast<double>(lev_window_start)) / fs : 0.0;
    for (size_t i = 0; i < n; ++i) {
      const bool known = f_ref > 0.0 && (i < first || i < first + valid);
      a.theta_rad.push_back(theta);
      a.known.push_back(known ? 1 : 0);
      if (known) theta += 2.0 * M_PI * (i < first ? f_ref : f_hz[i] * scale) / fs;
    }
    out.angle_known_after_trigger_s = static_cast<double>(valid) / fs;
    return a;
  }();
  SpinAngle angle_after;
  angle_after.theta_rad.assign(angle.theta_rad.begin() + static_cast<long>(first), angle.theta_rad.end());
  angle_after.known.assign(angle.known.begin() + static_cast<long>(first), angle.known.end());

  fit::DropFitOptions fo;
  fo.rig_model = rig_model;
  fo.progress = o.progress;
  fo.max_window_s = o.window_s;
  fo.choose_rotor_structure = !o.board_rotor_structure;
  // Model updating of the drop part: the contact law is an uncertain part of the drop model
  // (a real touchdown contact is compliant; the board states one law). With the option the
  // drop model is fitted with each law (board's first) and the lowest Phase C cost is kept.
  board::BoardConfig bu = b;
  say("drop part: fitting the drop model (base)");
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
                                 io::printf_text(": friction %.3f, Phase C cost %.4g", f.friction_coefficient, f.cost.total));
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
  auto after_trigger = [&](const fit::DropMeasurement& mm) {
    return Readings(mm.sensor_m.begin() + static_cast<long>(first), mm.sensor_m.end());
  };
  // Which view of the contact points the record supports: a flexible rotor's contact points
  // lie on circles only when read through its bending, a rigid rotor's only on the straight
  // line. The record chooses: the view with the smaller radial scatter of the contact points
  // about their own fitted circles.
  const ContactView bent(b.plant, *rig_model), straight(b.plant, *rig_model, false);
  auto contact_scatter = [&](const ContactView& v) {
    const Readings rd = v.contact_readings(after_trigger(m), fs);
    const auto circ = estimate_contact_circles(rd, b.plant, fs, o);
    std::array<std::array<double, 2>, 2> centres{};
    for (size_t k = 0; k < 2; ++k) centres[k] = circ[k].valid ? circ[k].centre_m : rig_centre(b.plant, static_cast<int>(k));
    double ssr = 0.0;
    int count = 0;
    for (const auto& [rms, cnt] : contact_misfit(rd, b.plant, centres, o)) {
      ssr += rms * rms * cnt;
      count += cnt;
    }
    return count > 0 ? std::sqrt(ssr / count) : std::numeric_limits<double>::infinity();
  };
  bool use_bending = false;
  if (bent.flexible()) {
    const double s_bent = contact_scatter(bent), s_straight = contact_scatter(straight);
    use_bending = s_bent < s_straight;
    out.drop_notes.push_back(io::printf_text("contact points about their own circles: %.2f um rms read through the board rotor's "
                                             "first bending mode (%.0f Hz free-free), %.2f um on the straight line through the "
                                             "sensor planes: ", s_bent * 1e6, bent.bending_hz(), s_straight * 1e6) +
                             (use_bending ? "the contact geometry is read at the aux planes through the bending"
                                          : "the straight line is kept (the rotor behaves as a rigid one: no sag bias added)"));
  }
  const ContactView& view = use_bending ? bent : straight;
  // The static sag bias of the straight view is a flexible rotor's: added to a rigid
  // simulation's circles only when the board's rotor is flexible and its bending cannot be
  // read (no invertible bending mode). Where it can and the record chose the straight line,
  // the rotor behaves as a rigid one (on rigid-rotor records the sag put the centres 5 um high).
  const SagViewShift sag = bent.flexible() ? SagViewShift{} : gravity_sag_view_shift_m(b.plant, *rig_model);
  out.drop_before = evaluate(m, base, bu.plant, o, sag, view);
  out.drop_after = out.drop_before;
  out.drop_notes.push_back(io::printf_text("drop model fitted: friction coefficient %.3f, Phase C cost %.4g", base.friction_coefficient,
                               base.cost.total) + ", contact law " + out.contact_law +
                           io::printf_text(", rotor %.0f modes per plane (2: rigid)", static_cast<double>(base.rotor_modes_per_plane)));
  if (out.drop_before.sag_scale > 0.0) {
    out.drop_notes.push_back(io::printf_text("rigid drop model: the board's flexible rotor's sag bias added to its contact circles, "
                                 "%.1f / %.1f um (static) x %.2f (mean contact force / weight)",
                                 sag.shift_m[0] * 1e6, sag.shift_m[1] * 1e6, out.drop_before.sag_scale));
  }
  out.drop_notes.push_back(out.angle_known_after_trigger_s > 0.0
                               ? io::printf_text("rotor angle known for %.3f s after the trigger (speed record)", out.angle_known_after_trigger_s)
                               : std::string("rotor angle unknown after the trigger (no spin-speed record there)"));
  const engine::Criterion& crit = o.loop.criterion;
  // The drop trajectory after the first impacts is chaotic: two drops that differ by a few
  // micrometres diverge, so the orbit distance and the band spectra of the post-impact motion
  // cannot judge a correction. They are reported beside every candidate as information,
  // never as a veto; the decision reads the contact geometry (engine/criterion.hpp).
  auto information = [](const DropErrors& e0, const DropErrors& e1) {
    std::vector<engine::Feature> v{{"orbit rms over the first impacts", "clearance", e0.error.rms, e1.error.rms},
                                   {"drop spectral error", "dB", e0.error.spectral, e1.error.spectral},
                                   {"drop spectra Pearson", "1", e0.error.pearson, e1.error.pearson, true},
                                   {"friction coefficient", "1", e0.friction_coefficient, e1.friction_coefficient},
                                   {"Phase C cost", "1", e0.cost, e1.cost}};
    return v;
  };
  auto errs = [](const ErrorFigures& e) {
    return io::printf_text("orbit rms %.4f, spectral %.2f dB, pearson %.3f", e.rms, e.spectral, e.pearson) + io::printf_text(", contact misfit %.4f", e.statics);
  };
  std::vector<EffectAdded> drop_added;
  ContactGeometryOptions geo;
  geo.contact_band = o.contact_band;
  geo.decorrelation_s = o.decorrelation_s;

  // ---- Candidate: sensor_runout (drop part) ----
  // The fitted unbalance's own signature in contact (shaft bending between the contacts,
  // contact-deflection modulation): a 1x contact residual below it is not called runout.
  {
    std::array<double, 2> fu{}, zu{};
    if (out.levitated_analysed) {
      for (size_t j = 0; j < 2; ++j) {
        fu[j] = std::abs(out.levitated.after.unbalance_force_n[j]);
        zu[j] = out.levitated.after.unbalance_axial_m[j];
      }
    } else {
      // No levitated fit: the board's two largest disk unbalances at the trigger speed.
      auto disks = b.plant.rotor.disks;
      std::sort(disks.begin(), disks.end(), [](const auto& x, const auto& y) { return x.unbalance_kg_m > y.unbalance_kg_m; });
      const double w = 2.0 * M_PI * m.speed_at_trigger_hz;
      for (size_t j = 0; j < std::min<size_t>(2, disks.size()); ++j) {
        fu[j] = disks[j].unbalance_kg_m * w * w;
        zu[j] = disks[j].axial_m;
      }
    }
    const double spin = lev_spin_hz > 0.0 ? lev_spin_hz : m.speed_at_trigger_hz;
    try {
      const auto sig = unbalance_contact_signature_m(bu.plant, *rig_model, fu, zu, spin);
      for (size_t p = 0; p < 2; ++p) out.runout_floor_m[p] = o.spin_locked_factor * sig[p];
    } catch (const std::exception& e) {
      out.drop_notes.push_back(std::string("unbalance contact signature not computed: ") + e.what());
    }
  }
  const Readings raw_after = after_trigger(m);
  out.drop_runout = estimate_contact_runout(raw_after, angle_after, bu.plant, fs, geo);
  bool lev_runout = false;
  for (const auto& e : out.levitated.effects_added) lev_runout = lev_runout || e.name == "sensor_runout";
  const auto& lev_ro = out.levitated.after.effects.runout;
  CandidateScore rc;
  rc.name = "sensor_runout";
  ContactRunout sel;  // the phasors that pass, refitted alone
  bool runout_sig = false;
  RunoutMask mask{};
  if (!out.drop_runout.testable) {
    rc.testable = false;
    rc.evidence = "not testable in the drop part: " + out.drop_runout.why_not;
  } else {
    // A phasor belongs to the element when it exceeds min_effect_sigma standard errors and,
    // at 1x, the fitted unbalance's contact signature (the predicted change of the readings
    // must be beyond the noise and beyond what the base model's own unknowns make).
    std::string list;
    bool any = false;
    for (size_t p = 0; p < 2; ++p)
      for (size_t h = 0; h < static_cast<size_t>(model::effects::k_runout_orders); ++h) {
        const double amp = std::abs(out.drop_runout.runout.r_m[p][h]), sg = out.drop_runout.sigma_m[p][h];
        const double z = sg > 0.0 ? amp / sg : 0.0;
        mask[p][h] = z >= crit.min_effect_sigma && (h > 0 || amp > out.runout_floor_m[p]);
        any = any || mask[p][h];
        list += std::string(list.empty() ? "" : ", ") + (p == 0 ? "A " : "B ") +
                io::printf_text("%.0fx %.2f um", static_cast<double>(h + 1), amp * 1e6) + io::printf_text(" (%.1f sigma)", z);
      }
    if (any) {
      sel = estimate_contact_runout(raw_after, angle_after, bu.plant, fs, geo, mask);
      runout_sig = sel.testable;
    }
    rc.delta_bic = any && sel.testable ? sel.delta_bic : out.drop_runout.delta_bic;
    rc.evidence = "spin-locked departure of the contact points from the clearance circles: " + list +
                  io::printf_text("; 1x floor (fitted unbalance bending the shaft between the contacts, x%.2f): A %.2f um, ", o.spin_locked_factor,
                      out.runout_floor_m[0] * 1e6) +
                  io::printf_text("B %.2f um; %.0f decorrelated contact points", out.runout_floor_m[1] * 1e6, out.drop_runout.n_eff) +
                  io::printf_text("; BIC decrease %.1f", rc.delta_bic);
    if (!any) rc.evidence += " (no phasor beyond the noise and the unbalance's signature)";
  }
  // What is subtracted from the drop readings: the drop part's estimate decides the 1x (the
  // levitated part cannot split a 1x runout from unbalance at one speed) when it is testable;
  // the levitated part's 2x is taken where the drop part has none; without a testable drop
  // estimate the levitated runout as found.
  model::effects::SensorRunout apply;
  bool have_apply = false;
  if (runout_sig) {
    apply = sel.runout;
    have_apply = true;
    out.runout_source = "drop";
    if (lev_runout && lev_ro)
      for (size_t p = 0; p < 2; ++p)
        if (!mask[p][1] && std::abs(lev_ro->r_m[p][1]) > 0.0) {
          apply.r_m[p][1] = lev_ro->r_m[p][1];
          out.runout_source = "levitated 2x + drop";
        }
  } else if (lev_runout && lev_ro) {
    apply = *lev_ro;
    have_apply = true;
    out.runout_source = "levitated";
    if (out.drop_runout.testable) {
      for (size_t p = 0; p < 2; ++p) apply.r_m[p][0] = 0.0;  // the contact geometry has no 1x runout beyond the noise
      out.runout_source = "levitated 2x (1x not confirmed by the contact geometry)";
    }
  }
  const bool angle_through = out.angle_known_after_trigger_s >= 0.9 * static_cast<double>(m.sensor_m.size() - first) / fs;
  if (runout_sig && !angle_through) {
    rc.testable = false;
    rc.evidence += "; not decided: the rotor angle is not known through the drop (no spin-speed record)";
  }
  if (have_apply && angle_through) {
    fit::DropMeasurement mc = m;
    mc.sensor_m = remove_runout(m.sensor_m, angle, apply, bu.plant);
    const DropErrors e1 = evaluate(mc, base, bu.plant, o, sag, view);  // runout is a reading artefact: the drop model's motion is unchanged
    out.drop_notes.push_back("runout (" + out.runout_source + ") subtracted from the drop readings: " + errs(out.drop_before.error) +
                             " -> " + errs(e1.error));
    bool keep = !runout_sig || lev_runout;  // a runout the levitated part named is applied as found there
    if (runout_sig) {
      // The engine decides on what the runout explains: the spin-locked departure of the
      // contact points from the circles (each selected phasor, in its standard errors, before
      // and after the correction) and the contact misfit.
      const ContactRunout post = estimate_contact_runout(after_trigger(mc), angle_after, bu.plant, fs, geo, mask);
      engine::CandidateEvidence ce;
      ce.element = "sensor_runout";
      ce.evidence = rc.evidence;
      ce.delta_ic = sel.delta_bic;
      ce.ic_basis = "BIC of the contact points' radial residual (circles alone against circles + spin-locked phasors), "
                    "Gaussian with the record's own scatter, decorrelated points";
      for (size_t p = 0; p < 2; ++p)
        for (size_t h = 0; h < static_cast<size_t>(model::effects::k_runout_orders); ++h) {
          if (!mask[p][h]) continue;
          const double sg = out.drop_runout.sigma_m[p][h];
          const double z0 = sg > 0.0 ? std::abs(out.drop_runout.runout.r_m[p][h]) / sg : 0.0;
          const double z1 = post.testable && sg > 0.0 ? std::abs(post.runout.r_m[p][h]) / sg : z0;
          ce.effect_sigma = std::max(ce.effect_sigma, z0);
          ce.decision.push_back({std::string(p == 0 ? "plane A " : "plane B ") + (h == 0 ? "1x" : "2x") + " spin-locked contact residual",
                                 "sigma", z0, z1, false, crit.min_effect_sigma});
          if (std::abs(sel.runout.r_m[p][h]) > 200e-6) {
            ce.identified = false;
            ce.not_identified = "a runout phasor beyond 200 um (the element's bound)";
          }
        }
      ce.decision.push_back({"contact misfit", "clearance", out.drop_before.error.statics, e1.error.statics});
      // A runout is a reading artefact of the whole record: held in the levitated part's
      // speed-order lines, it must not make them worse (a clean generated drop once showed a
      // 2x contact residual at 8.5 sigma whose runout raised the levitated rms 0.12 -> 6.2).
      if (lev_data && !out.levitated.after.effects.runout) {
        try {
          lev_with_runout = evaluate_steady(*lev_data, b, out.levitated.after.effects, &apply, rig_model);
          ce.decision.push_back({"levitated part: rms error with the runout held", "1", out.levitated.after.error.rms,
                                 lev_with_runout->error.rms});
        } catch (const std::exception& e) {
          out.drop_notes.push_back(std::string("levitated part not evaluated with the drop's runout: ") + e.what());
        }
      }
      ce.information = information(out.drop_before, e1);
      const engine::Decision dec = engine::decide(ce, crit);
      rc = scored(ce, dec);
      if (!lev_runout) keep = dec.kept;
      if (!dec.kept) out.drop_notes.push_back("sensor_runout (drop part) not kept: " + dec.reason);
    }
    if (keep) {
      out.runout_applied = apply;
      m = mc;
      out.drop_after = e1;
      if (runout_sig && !lev_runout) {
        EffectAdded e;
        e.name = "sensor_runout";
        model::effects::EffectSet es;
        es.runout = apply;
        e.parameters = effect_parameters(es, model::effects::EffectKind::sensor_runout);
        e.evidence = rc.evidence;
        e.delta_bic = rc.delta_bic;
        drop_added.push_back(e);
      }
    }
  } else if (have_apply) {
    out.drop_notes.push_back("runout (" + out.runout_source +
                             ") not subtracted from the drop readings: the rotor angle is not known through the drop (no spin-speed record)");
  }
  out.drop_ranking.push_back(rc);

  // ---- Candidate: sensor_gain ----
  // A probe's sensitivity off by a factor reads the clearance circle as an ellipse along its
  // axis: per sensor plane, the gain ratio of its two probes from the contact geometry.
  {
    CandidateScore gc;
    gc.name = "sensor_gain";
    const ContactGain g0 = estimate_contact_gain(after_trigger(m), bu.plant, fs, geo);
    if (!g0.testable) {
      gc.testable = false;
      gc.evidence = "not testable: " + g0.why_not;
      out.drop_ranking.push_back(gc);
    } else {
      std::array<bool, 2> fr{};
      std::string list;
      for (size_t p = 0; p < 2; ++p) {
        const double z = g0.sigma[p] > 0.0 ? std::abs(g0.log_ratio[p]) / g0.sigma[p] : 0.0;
        fr[p] = z >= crit.min_effect_sigma && std::abs(g0.log_ratio[p]) >= o.min_gain_log_ratio;
        list += std::string(list.empty() ? "" : ", ") + (p == 0 ? "A1/A2 " : "B1/B2 ") + io::printf_text("%.4f", std::exp(g0.log_ratio[p])) +
                io::printf_text(" (%.1f sigma)", z);
      }
      gc.evidence = "contact points on ellipses along the probe axes: gain ratios " + list +
                    io::printf_text("; smallest ratio claimed %.1f %%", 100.0 * o.min_gain_log_ratio) +
                    io::printf_text("; %.0f decorrelated contact points", g0.n_eff);
      gc.delta_bic = g0.delta_bic;
      if (!fr[0] && !fr[1]) {
        gc.evidence += " (no ratio beyond the noise and the smallest claimed)";
        out.drop_ranking.push_back(gc);
      } else {
        const ContactGain g1 = estimate_contact_gain(after_trigger(m), bu.plant, fs, geo, fr);
        fit::DropMeasurement mc = m;
        mc.sensor_m = remove_gain_ratio(m.sensor_m, g1.log_ratio);
        const DropErrors e1 = evaluate(mc, base, bu.plant, o, sag, view);  // a reading artefact: the drop model's motion is unchanged
        const ContactGain post = estimate_contact_gain(after_trigger(mc), bu.plant, fs, geo, fr);
        engine::CandidateEvidence ce;
        ce.element = "sensor_gain";
        ce.evidence = gc.evidence;
        ce.testable = g1.testable;
        ce.delta_ic = g1.delta_bic;
        ce.ic_basis = "BIC of the contact points' radial residual (circles against ellipses along the probe axes), "
                      "Gaussian with the record's own scatter, decorrelated points";
        for (size_t p = 0; p < 2; ++p) {
          if (!fr[p]) continue;
          const double z0 = g0.sigma[p] > 0.0 ? std::abs(g0.log_ratio[p]) / g0.sigma[p] : 0.0;
          const double z1 = post.testable && g0.sigma[p] > 0.0 ? std::abs(post.log_ratio[p]) / g0.sigma[p] : z0;
          ce.effect_sigma = std::max(ce.effect_sigma, z0);
          ce.decision.push_back({std::string(p == 0 ? "plane A" : "plane B") + " probe gain ratio off 1", "sigma", z0, z1, false,
                                 crit.min_effect_sigma});
          const double ratio = std::exp(g1.log_ratio[p]);
          if (!(ratio >= 0.5 && ratio <= 2.0)) {
            ce.identified = false;
            ce.not_identified = "a gain ratio beyond [0.5, 2] (the element's bound)";
          }
        }
        // A probe's gain is a property of one probe: the same ellipse at both sensor planes
        // (equal ratios within their errors) is the rotor's own orbit shape in contact (seen
        // on a clean generated drop: 0.970 and 0.967 at 7-8 sigma), not a probe.
        if (fr[0] && fr[1] &&
            std::abs(g1.log_ratio[0] - g1.log_ratio[1]) < 2.0 * std::hypot(g1.sigma[0], g1.sigma[1])) {
          ce.identified = false;
          ce.not_identified = "the same ellipse at both sensor planes (a shape of the orbit, not of one probe)";
        }
        ce.decision.push_back({"contact misfit", "clearance", out.drop_after.error.statics, e1.error.statics});
        ce.information = information(out.drop_after, e1);
        const engine::Decision dec = engine::decide(ce, crit);
        out.drop_ranking.push_back(scored(ce, dec));
        if (dec.kept) {
          out.gain_log_ratio_applied = g1.log_ratio;
          m = mc;
          out.drop_after = e1;
          EffectAdded e;
          e.name = "sensor_gain";
          e.parameters = {{"gain_a1_over_a2", std::exp(g1.log_ratio[0])}, {"gain_b1_over_b2", std::exp(g1.log_ratio[1])},
                          {"gain_a1_over_a2_sigma", g1.sigma[0] * std::exp(g1.log_ratio[0])},
                          {"gain_b1_over_b2_sigma", g1.sigma[1] * std::exp(g1.log_ratio[1])}};
          e.evidence = gc.evidence;
          e.delta_bic = g1.delta_bic;
          drop_added.push_back(e);
        } else {
          out.drop_notes.push_back("sensor_gain not kept: " + dec.reason);
        }
      }
    }
  }

  // ---- Candidate: aux_bearing_offset ----
  const DropErrors& cur = out.drop_after;
  CandidateScore cand;
  cand.name = "aux_bearing_offset";
  std::array<std::array<double, 2>, 2> delta{};
  bool significant = false, testable = true;
  for (int k = 0; k < 2; ++k) {
    const auto& mc = cur.measured_circle[static_cast<size_t>(k)];
    const auto& sc = cur.simulated_circle[static_cast<size_t>(k)];
    const double R = b.plant.aux[static_cast<size_t>(k)].clearance_m;
    if (!mc.valid || !sc.valid) {
      testable = false;
      out.drop_notes.push_back(io::printf_text("aux bearing %.0f: too few contact points for the circle fit", static_cast<double>(k)));
      continue;
    }
    delta[static_cast<size_t>(k)] = {mc.centre_m[0] - sc.centre_m[0], mc.centre_m[1] - sc.centre_m[1]};
    const double dn = std::hypot(delta[static_cast<size_t>(k)][0], delta[static_cast<size_t>(k)][1]);
    const double sig = std::hypot(mc.sigma_m, sc.sigma_m);
    // The bias correction is the fitted drop model's: when that model does not match the
    // contact (rigid vs compliant, other friction), its bias can itself be the difference. An
    // offset is claimed only when the raw measured centre is also off the model's centre.
    const auto& mcen = cur.model_centre_m[static_cast<size_t>(k)];
    const double raw = std::hypot(mc.centre_m[0] - mcen[0], mc.centre_m[1] - mcen[1]);
    const bool sig_k = dn > std::max(4.0 * sig, o.min_offset_fraction * R) && raw > std::max(4.0 * mc.sigma_m, o.min_offset_fraction * R);
    significant = significant || sig_k;
    out.drop_notes.push_back(io::printf_text("aux bearing %.0f: contact circle centre %+.1f / %+.1f um from the model's (sigma %.1f um)", static_cast<double>(k),
                                 delta[static_cast<size_t>(k)][0] * 1e6, delta[static_cast<size_t>(k)][1] * 1e6, sig * 1e6) +
                             (sig_k ? " -- significant" : ""));
  }
  cand.testable = testable;
  if (testable) {
    // Candidate score without refit: the scatter about the measured circles' centres
    // (= the bias-corrected model centres moved by delta).
    const Readings meas = view.contact_readings(after_trigger(m), fs);
    const auto mis = contact_misfit(meas, b.plant, {cur.measured_circle[0].centre_m, cur.measured_circle[1].centre_m}, o);
    double ssr = 0.0;
    for (const auto& [rms, cnt] : mis) ssr += rms * rms * cnt;
    cand.delta_bic = offset_delta_bic(cur.misfit_ssr_m2, ssr, cur.misfit_points, fs, o);
    const double n_eff = std::max(1.0, cur.misfit_points * std::min(1.0, 1.0 / (fs * o.decorrelation_s)));
    cand.evidence = io::printf_text("contact circles off the model's centres by %.1f and %.1f um (%.0f decorrelated contact points)",
                        std::hypot(delta[0][0], delta[0][1]) * 1e6, std::hypot(delta[1][0], delta[1][1]) * 1e6, n_eff);
    cand.evidence += significant ? "" : "; within the estimator's uncertainty";
  } else {
    cand.evidence = "not testable: the rotor touched an aux bearing too briefly for a circle fit";
  }
  out.drop_ranking.push_back(cand);

  if (testable && significant) {
    // The offset is the measured circle centre minus the fitted simulation's, and the
    // simulation's own bias (where the flexible rotor meets the bearing, its sag) moves with
    // the offset: fixed-point iterations, each a refit, while the refitted simulation's
    // centres stay more than 2 standard errors off the measured ones and keep approaching them.
    auto with_offset = [&](const std::array<std::array<double, 2>, 2>& dl) {
      board::BoardConfig bo = bu;
      for (size_t k = 0; k < 2; ++k) {
        bo.plant.aux[k].centre_offset_x_m += dl[k][0];
        bo.plant.aux[k].centre_offset_y_m += dl[k][1];
      }
      return bo;
    };
    auto centre_chi2 = [&](const DropErrors& e, double* worst_z) {
      double c2 = 0.0, w = 0.0;
      for (size_t k = 0; k < 2; ++k) {
        const auto& mcir = e.measured_circle[k];
        const auto& sc = e.simulated_circle[k];
        if (!mcir.valid || !sc.valid) return std::numeric_limits<double>::infinity();
        const double sg = std::hypot(mcir.sigma_m, sc.sigma_m);
        const double z = sg > 0.0 ? std::hypot(mcir.centre_m[0] - sc.centre_m[0], mcir.centre_m[1] - sc.centre_m[1]) / sg : 0.0;
        c2 += z * z;
        w = std::max(w, z);
      }
      if (worst_z != nullptr) *worst_z = w;
      return c2;
    };
    board::BoardConfig b2 = with_offset(delta);
    say("drop part: refit with aux_bearing_offset");
    fit::DropFitResult refit = fit::fit_drop(m, b2, fo);
    DropErrors after = evaluate(m, refit, b2.plant, o, sag, view);
    for (int it = 0; it < o.max_offset_iterations; ++it) {
      double worst = 0.0;
      const double c2 = centre_chi2(after, &worst);
      if (!(worst > 2.0) || !std::isfinite(c2)) break;
      auto next = delta;
      for (size_t k = 0; k < 2; ++k)
        for (size_t c = 0; c < 2; ++c) next[k][c] += after.measured_circle[k].centre_m[c] - after.simulated_circle[k].centre_m[c];
      board::BoardConfig bn = with_offset(next);
      say("drop part: aux_bearing_offset fixed-point refit " + std::to_string(it + 1));
      fit::DropFitResult rn = fit::fit_drop(m, bn, fo);
      DropErrors an = evaluate(m, rn, bn.plant, o, sag, view);
      const double c2n = centre_chi2(an, nullptr);
      out.drop_notes.push_back(io::printf_text("offset iteration %.0f: centre chi2 %.1f -> %.1f", it + 1.0, c2, c2n) +
                               io::printf_text(", rotor %.0f modes per plane", static_cast<double>(rn.rotor_modes_per_plane)));
      if (!(c2n < c2)) break;
      delta = next;
      b2 = std::move(bn);
      refit = std::move(rn);
      after = std::move(an);
    }
    const double dbic = offset_delta_bic(cur.misfit_ssr_m2, after.misfit_ssr_m2, cur.misfit_points, fs, o);
    out.drop_notes.push_back(io::printf_text("refit with the offset: friction %.3f, contact misfit %.4g -> %.4g of the clearance, dBIC %.1f",
                                 refit.friction_coefficient, cur.error.statics, after.error.statics, dbic));
    out.drop_notes.push_back("with the offset: " + errs(cur.error) + " -> " + errs(after.error));
    // The engine decides on the contact geometry: the radial scatter of the contact points
    // about the model's (bias-corrected) centres, and each bearing's measured circle centre
    // against the refitted simulation's, in its standard errors.
    engine::CandidateEvidence ce;
    ce.element = "aux_bearing_offset";
    ce.evidence = cand.evidence;
    ce.delta_ic = dbic;
    ce.ic_basis = "BIC of the contact points' radial scatter about the model's centres (Gaussian, variance from the record, "
                  "decorrelated points), 4 parameters";
    const engine::ElementSpec* spec = engine::find_element("aux_bearing_offset");
    const char* pn[4] = {"x0_m", "y0_m", "x1_m", "y1_m"};
    for (size_t k = 0; k < 2; ++k) {
      const auto& mcir = cur.measured_circle[k];
      const auto& s0 = cur.simulated_circle[k];
      const auto& s1 = after.simulated_circle[k];
      const double sig0 = std::hypot(mcir.sigma_m, s0.sigma_m);
      const double z0 = sig0 > 0.0 ? std::hypot(mcir.centre_m[0] - s0.centre_m[0], mcir.centre_m[1] - s0.centre_m[1]) / sig0 : 0.0;
      double z1 = z0;
      if (s1.valid) {
        const double sig1 = std::hypot(mcir.sigma_m, s1.sigma_m);
        z1 = sig1 > 0.0 ? std::hypot(mcir.centre_m[0] - s1.centre_m[0], mcir.centre_m[1] - s1.centre_m[1]) / sig1 : 0.0;
      } else {
        ce.identified = false;
        ce.not_identified = io::printf_text("the refitted simulation touches aux bearing %.0f too briefly for a circle", static_cast<double>(k));
      }
      ce.effect_sigma = std::max(ce.effect_sigma, z0);
      // A centre the drop part would not call off (the offset evidence rule: max(4 sigma,
      // min_offset_fraction of the clearance)) does not veto by rising within that floor.
      const double floor_sigma = sig0 > 0.0 ? std::max(4.0, o.min_offset_fraction * b.plant.aux[k].clearance_m / sig0) : 0.0;
      ce.decision.push_back({io::printf_text("aux bearing %.0f centre, measured - model", static_cast<double>(k)), "sigma", z0, z1, false,
                             crit.min_effect_sigma, floor_sigma});
      for (size_t c = 0; c < 2; ++c)
        if (spec != nullptr && !engine::within_bounds(*spec, pn[2 * k + c], b2.plant.aux[k].centre_offset_x_m * (c == 0) +
                                                                              b2.plant.aux[k].centre_offset_y_m * (c == 1))) {
          ce.identified = false;
          ce.not_identified = std::string(pn[2 * k + c]) + " beyond its physical bound";
        }
    }
    ce.decision.push_back({"contact misfit", "clearance", cur.error.statics, after.error.statics});
    ce.information = information(cur, after);
    if (refit.bound_active && !base.bound_active)
      out.drop_notes.push_back(io::printf_text("the refit with the offset puts a fitted value on its bound (friction %.3f); reported, not decided on",
                                   refit.friction_coefficient));
    const engine::Decision dec = engine::decide(ce, crit);
    for (auto& cs : out.drop_ranking)
      if (cs.name == "aux_bearing_offset") cs = scored(ce, dec);
    if (dec.kept) {
      out.drop_after = after;
      bu = b2;
      base = refit;
      EffectAdded e;
      e.name = "aux_bearing_offset";
      e.parameters = {{"x0_m", delta[0][0]}, {"y0_m", delta[0][1]}, {"x1_m", delta[1][0]}, {"y1_m", delta[1][1]},
                      {"friction_coefficient", refit.friction_coefficient}};
      e.evidence = cand.evidence;
      e.delta_bic = dbic;
      drop_added.push_back(e);
    } else {
      out.drop_notes.push_back("aux_bearing_offset not kept: " + dec.reason);
    }
  }

  // ---- Candidate: aux_support_compliance ----
  {
    const Readings meas = after_trigger(m);
    std::array<std::array<double, 2>, 2> centres{};
    for (size_t k = 0; k < 2; ++k)
      centres[k] = out.drop_runout.testable ? out.drop_runout.centre_m[k]
                   : out.drop_after.measured_circle[k].valid ? out.drop_after.measured_circle[k].centre_m
                                                             : rig_centre(bu.plant, static_cast<int>(k));
    out.compliance = estimate_contact_compliance(meas, bu.plant, *rig_model, fs, centres, geo);
    CandidateScore sc;
    sc.name = "aux_support_compliance";
    const auto& cc = out.compliance;
    if (!cc.testable) {
      sc.testable = false;
      sc.evidence = "not testable: " + cc.why_not;
      out.drop_ranking.push_back(sc);
    } else {
      // A support under one bearing: its deflection grows with the contact force beyond the
      // contact law AND beyond the other bearing's (the rotor's own bending, seen through the
      // rigid sensor view, grows with the contact forces at both).
      const size_t k = cc.compliance_m_per_n[0] >= cc.compliance_m_per_n[1] ? 0 : 1, other = 1 - k;
      const double dc = cc.compliance_m_per_n[k] - cc.compliance_m_per_n[other];
      const double sd = std::hypot(cc.sigma_m_per_n[k], cc.sigma_m_per_n[other]);
      const double z = sd > 0.0 ? dc / sd : 0.0;
      const double change = dc * cc.mean_force_n[k];
      // Noise floor of that change: its standard error, and the scatter of single contact
      // points about the regression (most of it the rotor's bending, itself force-locked, so
      // a smaller force-locked change cannot be told from it).
      const double floor = std::max(crit.min_effect_sigma * sd * cc.mean_force_n[k], 0.5 * (cc.noise_m[0] + cc.noise_m[1]));
      const double n_eff = std::max(2.0, static_cast<double>(cc.points[k]) / std::max(1.0, fs * o.decorrelation_s));
      sc.delta_bic = z * z - std::log(n_eff);
      const double ks = dc > 0.0 ? 1.0 / dc : 0.0;
      sc.evidence = io::printf_text("contact deflection grows with the force at aux bearing %.0f by %.3g m/N beyond the other's", static_cast<double>(k), dc) +
                    io::printf_text(" (%.1f sigma; support stiffness %.3g N/m); ", z, ks) +
                    io::printf_text("predicted change of the contact radius at the mean force %.0f N: %.1f um", cc.mean_force_n[k], change * 1e6) +
                    io::printf_text(" against a floor of %.1f um", floor * 1e6) + io::printf_text("; BIC decrease %.1f", sc.delta_bic);
      // The engine's criterion on the force-deflection evidence. The refit cannot carry it:
      // the drop model holds one contact stiffness for both bearings
      // (DropModel::set_contact_stiffness), so a support under one bearing is not identified
      // by the drop fit and the candidate is reported, with its figures, and not kept.
      engine::CandidateEvidence ce;
      ce.element = "aux_support_compliance";
      ce.evidence = sc.evidence;
      ce.delta_ic = sc.delta_bic;
      ce.ic_basis = "the compliance difference's z^2 - ln n_eff (Gaussian regression of deflection on force)";
      ce.effect_sigma = change > floor ? z : 0.0;
      ce.identified = false;
      ce.not_identified = "the drop model holds one contact stiffness for both aux bearings, so a support under one bearing cannot be refitted";
      ce.decision.push_back({io::printf_text("aux bearing %.0f compliance beyond the other's", static_cast<double>(k)), "sigma", z, z});
      const engine::Decision dec = engine::decide(ce, crit);
      out.drop_ranking.push_back(scored(ce, dec));
      (void)ks;
    }
  }

  // ---- Unexplained (drop part) ----
  std::vector<UnexplainedItem> du;
  {
    // Bands: runs of adjacent 1/3-octave bands where the measured drop spectrum is off the
    // fitted model's by more than 6 dB (mean of the plane's sensors).
    const auto& e = out.drop_after;
    for (int p = 0; p < 2; ++p) {
      const auto& v = e.band_db[static_cast<size_t>(p)];
      for (size_t i = 0; i < v.size() && i < e.band_hz.size();) {
        if (std::abs(v[i]) <= 6.0) {
          ++i;
          continue;
        }
        size_t j = i;
        double peak = v[i];
        while (j + 1 < v.size() && j + 1 < e.band_hz.size() && std::abs(v[j + 1]) > 6.0 && (v[j + 1] > 0) == (v[i] > 0)) {
          ++j;
          if (std::abs(v[j]) > std::abs(peak)) peak = v[j];
        }
        UnexplainedItem u;
        u.part = "drop";
        u.kind = "band";
        u.plane = p;
        u.f_hz = e.band_hz[i];
        u.f_hi_hz = e.band_hz[j];
        u.level_db = peak;
        du.push_back(u);
        i = j + 1;
      }
    }
    // Spin-locked contact residuals not taken by an element (beyond the noise).
    if (out.drop_runout.testable && out.runout_applied.r_m == model::effects::SensorRunout{}.r_m)
      for (size_t p = 0; p < 2; ++p)
        for (size_t h = 0; h < static_cast<size_t>(model::effects::k_runout_orders); ++h) {
          const double amp = std::abs(out.drop_runout.runout.r_m[p][h]), sg = out.drop_runout.sigma_m[p][h];
          if (sg > 0.0 && amp / sg >= crit.min_effect_sigma) {
            UnexplainedItem u;
            u.part = "drop";
            u.kind = "order";
            u.order = static_cast<int>(h + 1);
            u.plane = static_cast<int>(p);
            u.f_hz = static_cast<double>(h + 1) * (lev_spin_hz > 0.0 ? lev_spin_hz : m.speed_at_trigger_hz);
            u.snr = (amp / sg) * (amp / sg);
            u.direction = "forward";
            u.amplitude_m = amp;
            du.push_back(u);
          }
        }
    // A compliance asymmetry beyond 3 standard errors that no element took.
    bool support_added = false;
    for (const auto& e2 : drop_added) support_added = support_added || e2.name == "aux_support_compliance";
    if (out.compliance.testable && !support_added) {
      const auto& cc = out.compliance;
      const size_t k = cc.compliance_m_per_n[0] >= cc.compliance_m_per_n[1] ? 0 : 1;
      const double dc = cc.compliance_m_per_n[k] - cc.compliance_m_per_n[1 - k];
      const double sd = std::hypot(cc.sigma_m_per_n[0], cc.sigma_m_per_n[1]);
      if (sd > 0.0 && dc / sd >= crit.min_effect_sigma) {
        UnexplainedItem u;
        u.part = "drop";
        u.kind = "contact_compliance";
        u.plane = static_cast<int>(k);
        u.value = dc;
        u.snr = (dc / sd) * (dc / sd);
        u.amplitude_m = dc * cc.mean_force_n[k];
        du.push_back(u);
      }
    }
  }

  std::stable_sort(out.drop_ranking.begin(), out.drop_ranking.end(), [](const CandidateScore& x, const CandidateScore& y) {
    if (x.testable != y.testable) return x.testable;
    return x.delta_bic > y.delta_bic;
  });

  // ---- The drop part's runout in the levitated part ----
  // A runout found by the contact geometry is a reading artefact of the whole record: the
  // levitated part's speed-order lines are re-evaluated with it held (in the same angle
  // reference), so a 1x line it explains leaves the levitated part's unexplained list.
  bool drop_runout_kept = false;
  for (const auto& e2 : drop_added) drop_runout_kept = drop_runout_kept || e2.name == "sensor_runout";
  if (drop_runout_kept && lev_data && lev_with_runout) {
    try {
      const SteadyEvaluation ev = *lev_with_runout;
      const size_t lines_before = static_cast<size_t>(std::count_if(out.levitated.unexplained.begin(), out.levitated.unexplained.end(),
                                                                    [](const UnexplainedItem& u) { return u.kind == "order"; }));
      const ErrorFigures e0 = out.levitated.after.error;
      out.levitated.after = ev;
      out.levitated.structure_after = analyse_structure(*lev_data, b, ev);
      out.levitated.unexplained = unexplained_items(*lev_data, b, ev, out.levitated.structure_after);
      const size_t lines_after = static_cast<size_t>(std::count_if(out.levitated.unexplained.begin(), out.levitated.unexplained.end(),
                                                                   [](const UnexplainedItem& u) { return u.kind == "order"; }));
      for (auto& cs : out.drop_ranking)
        if (cs.name == "sensor_runout" && cs.decided) {
          cs.information_features.push_back({"levitated part: unexplained speed-order lines", "lines", static_cast<double>(lines_before),
                                            static_cast<double>(lines_after)});
        }
      out.drop_notes.push_back(io::printf_text("levitated part re-evaluated with the drop's runout held: rms %.4f -> %.4f, ", e0.rms, ev.error.rms) +
                               io::printf_text("unexplained speed-order lines %.0f -> %.0f", static_cast<double>(lines_before), static_cast<double>(lines_after)));
    } catch (const std::exception& e) {
      out.drop_notes.push_back(std::string("levitated part not re-evaluated with the drop's runout: ") + e.what());
    }
  }

  // ---- The event ----
  std::vector<EffectAdded> all = out.levitated_analysed ? out.levitated.effects_added : std::vector<EffectAdded>{};
  // A runout named in the levitated part carries the drop part's 1x when that decided it.
  if (!out.runout_source.empty() && out.runout_source != "levitated")
    for (auto& e : all)
      if (e.name == "sensor_runout") {
        model::effects::EffectSet es;
        es.runout = out.runout_applied;
        e.parameters = effect_parameters(es, model::effects::EffectKind::sensor_runout);
        e.evidence += "; 1x from the drop part's contact geometry (" + out.runout_source + ")";
      }
  all.insert(all.end(), drop_added.begin(), drop_added.end());
  out.effects_added = all;
  if (out.levitated_analysed) {
    out.before = combine(out.levitated.before.error, out.drop_before.error);
    out.after = combine(out.levitated.after.error, out.drop_after.error);
    out.unexplained = out.levitated.unexplained;
  } else {
    out.before = out.drop_before.error;
    out.after = out.drop_after.error;
  }
  out.unexplained.insert(out.unexplained.end(), du.begin(), du.end());
  out.verdict.clear();
  for (const auto& e : out.effects_added) out.verdict += (out.verdict.empty() ? "" : "+") + e.name;
  if (out.verdict.empty()) out.verdict = "none";
  return out;
}

}  // namespace amb::host::residual
