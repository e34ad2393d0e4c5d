#pragma once
// Labelled records made with the project's own bearing models, for bearing-check's calibration
// (healthy records only) and validation (tables in docs/bearing.md):
//  - seed 003's 4-DOF Hertzian model (hertz_4dof.hpp): housing acceleration;
//  (faults: an outer- or inner-race groove, or a spot on one ball - hertz_contact.hpp)
//  - seed 001's 8-DOF rotor (rotor_8dof.hpp, two SKF 6200): bearing B's support force, the
//    signal a stiff housing's accelerometer would see up to scale;
// seen through a transfer path (none, or one/two housing resonances in parallel with a weak
// direct path) with white Gaussian noise relative to the path's output rms. The checker never
// sees any of these settings.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "model/bearing/catalogue.hpp"
#include "model/bearing/hertz_4dof.hpp"
#include "model/bearing/rotor_8dof.hpp"

namespace amb::test::bearing {

namespace mb = amb::model::bearing;

/// Seed 003's 4-DOF defaults (6206, 500 N) with a 0.5 mm wide, 0.3 mm deep groove (the seed's
/// 0.2 and 0.5 mm grooves) at `loc`, in the load zone (load along +y).
inline mb::Hertz4DofParams with_defect(mb::DefectLocation loc) {
  mb::Hertz4DofParams p;
  p.defect.location = loc;
  p.defect.width_m = 0.5e-3;
  p.defect.depth_m = 0.3e-3;
  p.defect.angle_rad = M_PI / 2;
  return p;
}

/// RBJ band-pass biquad (0 dB peak) at f0_hz with quality q, applied in place.
inline void bandpass(std::vector<double>& x, double fs_hz, double f0_hz, double q) {
  const double w0 = 2.0 * M_PI * f0_hz / fs_hz, alpha = std::sin(w0) / (2.0 * q), a0 = 1.0 + alpha;
  const double b0 = alpha / a0, b2 = -alpha / a0, a1 = -2.0 * std::cos(w0) / a0, a2 = (1.0 - alpha) / a0;
  double x1 = 0, x2 = 0, y1 = 0, y2 = 0;
  for (double& v : x) {
    const double y = b0 * v + b2 * x2 - a1 * y1 - a2 * y2;
    x2 = x1;
    x1 = v;
    y2 = y1;
    y1 = y;
    v = y;
  }
}

/// Transfer path: 0 direct; 1 one resonance at 0.23 fs (Q 12); 2 two at 0.1 fs (Q 20) and
/// 0.37 fs (Q 6). Paths 1 and 2 keep a direct share of 0.1.
inline std::vector<double> through_path(const std::vector<double>& x, double fs_hz, int path) {
  if (path == 0) return x;
  std::vector<double> out(x.size()), a = x, b = x;
  if (path == 1) {
    bandpass(a, fs_hz, 0.23 * fs_hz, 12.0);
    for (size_t i = 0; i < x.size(); ++i) out[i] = 0.1 * x[i] + a[i];
  } else {
    bandpass(a, fs_hz, 0.1 * fs_hz, 20.0);
    bandpass(b, fs_hz, 0.37 * fs_hz, 6.0);
    for (size_t i = 0; i < x.size(); ++i) out[i] = 0.1 * x[i] + 0.5 * a[i] + b[i];
  }
  return out;
}

inline void add_noise(std::vector<double>& x, double noise_rel, uint64_t seed) {
  double ss = 0;
  for (double v : x) ss += v * v;
  const double sd = noise_rel * std::sqrt(ss / static_cast<double>(x.size()));
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n(0.0, sd);
  for (double& v : x) v += n(rng);
}

/// One labelled record's settings.
struct RecordSpec {
  std::string model = "4dof";        ///< "4dof" (seed 003) or "8dof" (seed 001)
  std::string bearing = "6206";      ///< catalogue name
  mb::DefectLocation defect = mb::DefectLocation::none;
  double width_mm = 0.5;             ///< groove / ball-spot width, mm (depth: 0.6 x width, capped by the model)
  /// Radial load relative to the race records': 4-DOF W_y = 500 N x load_scale (seed 003's
  /// load); 8-DOF: both discs' masses x load_scale (the bearings carry the rotor's weight).
  double load_scale = 1.0;
  double speed_hz = 30.0;            ///< true shaft speed, Hz
  double fs_hz = 12000.0;            ///< sample rate, Hz
  double duration_s = 10.0;          ///< record length, s
  double noise_rel = 0.5;            ///< noise rms / path output rms
  int path = 0;                      ///< transfer path (through_path)
  uint64_t seed = 1;                 ///< noise (and speed fluctuation) seed
  /// Relative rms of a random speed fluctuation (Ornstein-Uhlenbeck, correlation time 0.1 s):
  /// without it the model's impacts are strictly periodic (no slip), i.e. discrete spectral
  /// lines, which no real bearing produces (rolling elements slip 1-2 %, Smith & Randall 2015).
  double speed_fluctuation = 0.002;
  /// Ball-size variation of a healthy bearing (mb::BallSizeVariation): ball 0 larger than the
  /// others by this much in diameter, um (0: all equal). Not a defect: the label stays.
  double ball_excess_um = 0.0;
  std::string label() const {
    return defect == mb::DefectLocation::outer_race   ? "outer_race"
           : defect == mb::DefectLocation::inner_race ? "inner_race"
           : defect == mb::DefectLocation::ball       ? "ball"
                                                      : "healthy";
  }
};

inline std::vector<double> make_record(const RecordSpec& s) {
  const auto g = *mb::find_bearing(s.bearing);
  std::vector<double> clean;
  // Speed fluctuation: OU process on a 1 ms grid, interpolated.
  std::vector<double> eps(static_cast<size_t>((s.duration_s + 1.0) / 1e-3) + 2, 0.0);
  if (s.speed_fluctuation > 0) {
    std::mt19937_64 rng(s.seed ^ 0x5eedULL);
    std::normal_distribution<double> n(0.0, 1.0);
    const double a = std::exp(-1e-3 / 0.1), b = s.speed_fluctuation * std::sqrt(1.0 - a * a);
    for (size_t i = 1; i < eps.size(); ++i) eps[i] = a * eps[i - 1] + b * n(rng);
  }
  auto speed = [&](double t) {
    const double u = std::clamp(t, 0.0, s.duration_s + 0.5) / 1e-3;
    const auto i = static_cast<size_t>(u);
    const double f = u - static_cast<double>(i);
    return s.speed_hz * (1.0 + (1.0 - f) * eps[i] + f * eps[i + 1]);
  };
  if (s.model == "4dof") {
    mb::Hertz4DofParams p;
    p.bearing = g;
    p.defect.location = s.defect;
    p.defect.width_m = s.width_mm * 1e-3;
    p.defect.depth_m = 0.6 * s.width_mm * 1e-3;
    p.defect.angle_rad = M_PI / 2;  // race groove: in the load zone (ball spot: its spin phase)
    p.load_y_n *= s.load_scale;
    p.ball_size.excess_diameter_m = s.ball_excess_um * 1e-6;
    clean = mb::simulate_housing_acceleration(p, speed, s.fs_hz, s.duration_s, 0.0, 1);
  } else {
    mb::Rotor8DofParams p;
    mb::ContactLawParams cp;
    cp.geometry = g;
    cp.hertz_constant_n_per_m1p5 = mb::nominal_hertz_constant(g);
    cp.radial_clearance_m = 5e-6;
    p.bearing_a = cp;
    cp.defect.location = s.defect;
    cp.defect.profile = mb::DefectProfile::cosine;
    cp.defect.width_m = s.width_mm * 1e-3;
    cp.defect.depth_m = 0.6 * s.width_mm * 1e-3;
    cp.defect.angle_rad = -M_PI / 2;  // race groove: load zone under gravity (ball spot: spin phase)
    cp.ball_size.excess_diameter_m = s.ball_excess_um * 1e-6;
    p.bearing_b = cp;
    p.m2_kg *= s.load_scale;
    p.m3_kg *= s.load_scale;
    p.step_s = 1.0 / (s.fs_hz * std::ceil(1.0 / (s.fs_hz * 2e-6)));  // <= 2 us, integer steps per sample
    mb::Rotor8DofModel m;
    if (!m.configure(p)) return {};
    // The fixed step must resolve the defect's transit (4 steps), as the 4-DOF step rule does;
    // the speed fluctuation stays well inside +5 %.
    mb::HertzContactLaw law;
    if (!law.configure(cp) || p.step_s > 0.25 * law.defect_transit_time_s(1.05 * s.speed_hz)) return {};
    mb::Rotor8DofState y = mb::Rotor8DofState::Zero();
    std::function<double(double)> sp = speed;
    const int per = static_cast<int>(std::lround(1.0 / (s.fs_hz * p.step_s)));
    double t = 0;
    for (int i = 0; i < static_cast<int>(0.2 / p.step_s); ++i, t += p.step_s) m.step(y, t, sp);  // settle
    const auto n = static_cast<size_t>(s.duration_s * s.fs_hz);
    clean.resize(n);
    for (size_t k = 0; k < n; ++k) {
      for (int i = 0; i < per; ++i, t += p.step_s) m.step(y, t, sp);
      clean[k] = m.bearing_reaction(y, 1).fy_n;
    }
  }
  auto x = through_path(clean, s.fs_hz, s.path);
  add_noise(x, s.noise_rel, s.seed);
  return x;
}

}  // namespace amb::test::bearing
