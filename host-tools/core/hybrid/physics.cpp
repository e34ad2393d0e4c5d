#include "host-tools/core/hybrid/physics.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <random>
#include <stdexcept>

#include "model/bearing/catalogue.hpp"
#include "model/bearing/hertz_contact.hpp"
#include "model/bearing/rk4.hpp"
#include "model/bearing/rotor_8dof.hpp"
#include "host-tools/core/hybrid/spectra.hpp"

namespace amb::host::hybrid {
namespace mb = amb::model::bearing;

const char* state_name(BearingState s) {
  switch (s) {
    case BearingState::healthy: return "healthy";
    case BearingState::inner_race: return "inner_race";
    case BearingState::outer_race: return "outer_race";
    case BearingState::ball: return "ball";
  }
  return "?";
}

BearingState parse_state(const std::string& s) {
  std::string k;
  for (char c : s) k += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (k == "healthy" || k == "normal") return BearingState::healthy;
  if (k == "inner_race" || k == "inner" || k == "ir") return BearingState::inner_race;
  if (k == "outer_race" || k == "outer" || k == "or") return BearingState::outer_race;
  if (k == "ball" || k == "b") return BearingState::ball;
  throw std::invalid_argument("unknown bearing state '" + s + "' (healthy, inner_race, outer_race, ball)");
}

bool RigParams::valid(std::string* why) const {
  auto fail = [&](const std::string& m) {
    if (why) *why = m;
    return false;
  };
  if (!mb::find_bearing(drive_end_bearing)) return fail("unknown drive-end bearing '" + drive_end_bearing + "'");
  if (!mb::find_bearing(fan_end_bearing)) return fail("unknown fan-end bearing '" + fan_end_bearing + "'");
  if (!(bearing_mass_kg > 0) || !(disc_mass_kg > 0) || !(housing_mass_kg > 0)) return fail("masses must be > 0");
  if (!(shaft_stiffness_n_per_m > 0)) return fail("shaft stiffness must be > 0");
  if (!(bearing_damping_n_s_per_m >= 0) || !(disc_damping_n_s_per_m >= 0)) return fail("damping must be >= 0");
  if (!(radial_clearance_m >= 0)) return fail("clearance must be >= 0");
  if (!(defect_width_m > 0)) return fail("defect width must be > 0");
  if (!(drive_end_contact_angle_rad >= 0) || !(drive_end_contact_angle_rad < 0.7))
    return fail("drive-end contact angle in [0, 40] deg");
  if (!(unbalance_eccentricity_m >= 0)) return fail("unbalance eccentricity must be >= 0");
  if (!(sensor_noise_rel >= 0)) return fail("sensor noise must be >= 0");
  if (!(settle_s >= 0)) return fail("settle time must be >= 0");
  if (steps_per_sample < 1 || steps_per_sample > 1000) return fail("steps_per_sample in [1, 1000]");
  return true;
}

namespace {

// A spot on ball 0 of the drive-end bearing: it releases deflection when it faces a race.
struct BallSpot {
  bool active = false;
  double kb = 0.0;            // N/m^1.5
  double clearance_m = 0.0;   // m
  double depth_m = 0.0;       // r - sqrt(r^2 - (L/2)^2), m
  double half_angle_rad = 0;  // asin(L / D_b): half the spot's angle on the ball
  double cage_ratio = 0.0;    // cage angle per shaft angle
  double spin_ratio = 0.0;    // ball spin angle (relative to the cage) per shaft angle (BSF order)

  // Change of ball 0's force on the outer ring (N, x and y) for inner-minus-outer (dx, dy).
  void force_change(double dx, double dy, double shaft_angle, double& fx, double& fy) const {
    fx = fy = 0.0;
    if (!active) return;
    const double spin = shaft_angle * spin_ratio;
    const double a_out = std::abs(mb::wrap_angle_rad(spin));
    const double a_in = std::abs(mb::wrap_angle_rad(spin - M_PI));
    const double a = std::min(a_out, a_in);
    if (a > half_angle_rad) return;
    const double h = depth_m * std::cos(a * M_PI / (2.0 * half_angle_rad));  // seed 001 eq. 5 profile
    const double th = shaft_angle * cage_ratio;
    const double c = std::cos(th), s = std::sin(th);
    const double d = dx * c + dy * s - clearance_m;
    auto q = [&](double x) { return x > 0 ? kb * x * std::sqrt(x) : 0.0; };
    const double dq = q(d - h) - q(d);
    fx = dq * c;
    fy = dq * s;
  }
};

}  // namespace

std::vector<double> simulate_drive_end(const RigParams& rig, BearingState state, const OperatingPoint& op,
                                       double fs_hz, double duration_s, uint64_t seed) {
  std::string why;
  if (!rig.valid(&why)) throw std::invalid_argument("rig: " + why);
  if (!(op.speed_rpm > 0) || !(op.speed_rpm < 1e6)) throw std::invalid_argument("speed must be in (0, 1e6) rpm");
  if (!(fs_hz > 0) || !(duration_s > 0)) throw std::invalid_argument("fs and duration must be > 0");
  auto de = *mb::find_bearing(rig.drive_end_bearing);
  de.contact_angle_rad = rig.drive_end_contact_angle_rad;
  const auto fe = *mb::find_bearing(rig.fan_end_bearing);

  mb::Rotor8DofParams p;
  p.m1_kg = p.m4_kg = rig.bearing_mass_kg;
  p.m2_kg = p.m3_kg = rig.disc_mass_kg;
  p.cs1_n_s_per_m = p.cs2_n_s_per_m = rig.bearing_damping_n_s_per_m;
  p.cd1_n_s_per_m = p.cd2_n_s_per_m = rig.disc_damping_n_s_per_m;
  p.k1_n_per_m = p.k2_n_per_m = p.k3_n_per_m = p.k4_n_per_m = rig.shaft_stiffness_n_per_m;
  p.step_s = 1.0 / (fs_hz * rig.steps_per_sample);
  p.bearing_a.geometry = de;
  p.bearing_a.hertz_constant_n_per_m1p5 = mb::nominal_hertz_constant(de);
  p.bearing_a.radial_clearance_m = rig.radial_clearance_m;
  p.bearing_b.geometry = fe;
  p.bearing_b.hertz_constant_n_per_m1p5 = mb::nominal_hertz_constant(fe);
  p.bearing_b.radial_clearance_m = rig.radial_clearance_m;
  if (state == BearingState::inner_race || state == BearingState::outer_race) {
    mb::GrooveDefect& g = p.bearing_a.defect;
    g.location = state == BearingState::inner_race ? mb::DefectLocation::inner_race : mb::DefectLocation::outer_race;
    g.profile = mb::DefectProfile::cosine;  // seed 001 eq. 5
    g.width_m = rig.defect_width_m;
    g.depth_m = 1.0;  // capped at r - sqrt(r^2 - (L/2)^2) (seed 001 eq. 6)
    g.limit_depth_to_ball = true;
    g.angle_rad = state == BearingState::outer_race ? rig.outer_defect_angle_rad : 0.0;
  }
  mb::Rotor8DofModel model;
  if (!model.configure(p)) throw std::invalid_argument("8-DOF model refused the rig parameters");

  BallSpot spot;
  if (state == BearingState::ball) {
    const double r = 0.5 * de.ball_diameter_m;
    const double half = std::min(r, 0.5 * rig.defect_width_m);
    spot.active = true;
    spot.kb = p.bearing_a.hertz_constant_n_per_m1p5;
    spot.clearance_m = rig.radial_clearance_m;
    spot.depth_m = r - std::sqrt(r * r - half * half);
    spot.half_angle_rad = std::asin(half / r);
    const auto orders = mb::defect_orders(de);
    spot.cage_ratio = orders.ftf;
    spot.spin_ratio = orders.bsf;
  }

  const double f_hz = op.speed_rpm / 60.0;
  const double w = 2.0 * M_PI * f_hz;
  const double unb_n = rig.disc_mass_kg * rig.unbalance_eccentricity_m * w * w;
  auto rhs = [&](double, const mb::Rotor8DofState& y) {
    mb::Rotor8DofState d = model.derivative(y, f_hz);
    const double th = y[16];
    const double fx = unb_n * std::cos(th), fy = unb_n * std::sin(th);
    d[10] += fx / p.m2_kg;
    d[11] += fy / p.m2_kg;
    d[12] += fx / p.m3_kg;
    d[13] += fy / p.m3_kg;
    if (spot.active) {
      double bx = 0, by = 0;
      spot.force_change(y[0], y[1], th, bx, by);
      d[8] -= bx / p.m1_kg;  // the rotor receives minus the force on the outer ring
      d[9] -= by / p.m1_kg;
    }
    return d;
  };
  // Start from the static sag under gravity (inside the clearance) to shorten the transient.
  mb::Rotor8DofState y = mb::Rotor8DofState::Zero();
  const double h = p.step_s;
  const auto settle_steps = static_cast<long>(std::ceil(rig.settle_s / h));
  double t = 0.0;
  for (long i = 0; i < settle_steps; ++i, t += h) mb::rk4_step<17>(rhs, t, y, h);

  const auto n = static_cast<size_t>(std::llround(duration_s * fs_hz));
  std::vector<double> out(n);
  const double ca = std::cos(rig.sensor_angle_rad), sa = std::sin(rig.sensor_angle_rad);
  const double scale = 1.0 / (rig.housing_mass_kg * 9.80665);  // N -> g
  for (size_t k = 0; k < n; ++k) {
    const mb::SupportForce r = model.bearing_reaction(y, 0);  // on the rotor
    double fx = -r.fx_n, fy = -r.fy_n;                        // on the outer ring / housing
    if (spot.active) {
      double bx = 0, by = 0;
      spot.force_change(y[0], y[1], y[16], bx, by);
      fx += bx;
      fy += by;
    }
    out[k] = (fx * ca + fy * sa) * scale;
    for (int s = 0; s < rig.steps_per_sample; ++s, t += h) mb::rk4_step<17>(rhs, t, y, h);
  }
  double mean = 0.0;
  for (double v : out) mean += v;
  mean /= static_cast<double>(std::max<size_t>(n, 1));
  double var = 0.0;
  for (double& v : out) {
    v -= mean;
    var += v * v;
  }
  const double rms = std::sqrt(var / static_cast<double>(std::max<size_t>(n, 1)));
  if (rig.sensor_noise_rel > 0 && rms > 0) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> gauss(0.0, rig.sensor_noise_rel * rms);
    for (double& v : out) v += gauss(rng);
  }
  return out;
}

KinematicCalibration calibrate_kinematics(const std::vector<CalibrationRecord>& records, double env_band_low_hz,
                                          double env_band_high_hz, RigParams& rig) {
  std::string why;
  if (!rig.valid(&why)) throw std::invalid_argument("rig: " + why);
  KinematicCalibration c;
  const auto geo = *mb::find_bearing(rig.drive_end_bearing);
  c.gamma_catalogue = geo.gamma();
  const auto orders = mb::defect_orders(geo);
  const int z = geo.ball_count;
  double sum = 0.0;
  for (const auto& r : records) {
    if (r.state != BearingState::outer_race && r.state != BearingState::inner_race) continue;
    if (r.signal == nullptr || !(r.fs_hz > 0) || !(r.speed_rpm > 0)) continue;
    const double fr = r.speed_rpm / 60.0;
    const double order = r.state == BearingState::outer_race ? orders.bpfo : orders.bpfi;
    const double duration = static_cast<double>(r.signal->size()) / r.fs_hz;
    // Fine envelope spectrum: one Welch window of the whole record (finest resolution).
    SpectralOptions o;
    o.env_band_low_hz = env_band_low_hz;
    o.env_band_high_hz = env_band_high_hz;
    o.env_df_hz = std::max(0.05, 1.0 / duration);
    o.env_bin_min_hz = o.env_df_hz;
    o.env_min_hz = 0.5 * order * fr;
    o.env_max_hz = std::min(3.5 * order * fr, 0.4 * (env_band_high_hz - env_band_low_hz));
    o.psd_df_hz = o.env_df_hz;
    o.psd_bin_min_hz = o.env_df_hz;
    o.psd_max_hz = std::min(0.45 * r.fs_hz, std::max(env_band_high_hz, o.psd_min_hz + 20 * o.psd_bin_min_hz));
    o.rel_bin_width = 0.0;
    if (!o.valid() || 0.5 * r.fs_hz < std::max(o.psd_max_hz, env_band_high_hz)) continue;
    const Spectra s = compute_spectra(*r.signal, r.fs_hz, o);
    const Grid g = env_grid(o);
    // Harmonics 1..3 searched together: the fundamental f that maximises the summed peak power.
    double best_f = 0.0, best_p = -1.0;
    const double f0 = order * fr;
    for (double f = 0.98 * f0; f <= 1.02 * f0; f += 0.25 * o.env_df_hz / 3.0) {
      double p = 0.0;
      for (int h = 1; h <= 3; ++h) {
        const double fh = h * f;
        if (fh > g.edges.back()) break;
        const auto k = std::min(g.bins() - 1, static_cast<size_t>(std::max(0.0, (fh - g.edges.front()) / o.env_df_hz)));
        p += s.env[k] * s.env[k];
      }
      if (p > best_p) {
        best_p = p;
        best_f = f;
      }
    }
    if (!(best_f > 0)) continue;
    const double ratio = best_f / fr;
    const double gamma = r.state == BearingState::outer_race ? 1.0 - 2.0 * ratio / z : 2.0 * ratio / z - 1.0;
    sum += gamma;
    ++c.lines_used;
  }
  if (c.lines_used == 0) {
    c.gamma_effective = c.gamma_catalogue;
    c.note = "no outer- or inner-race training record: catalogue kinematics kept";
    rig.drive_end_contact_angle_rad = 0.0;
    return c;
  }
  c.gamma_effective = sum / c.lines_used;
  const double cos_a = c.gamma_effective / (geo.ball_diameter_m / geo.pitch_diameter_m);
  c.contact_angle_rad = cos_a < 1.0 ? std::acos(std::max(cos_a, std::cos(0.69))) : 0.0;
  rig.drive_end_contact_angle_rad = c.contact_angle_rad;
  c.note = "effective contact angle " + std::to_string(c.contact_angle_rad * 180.0 / M_PI) + " deg from " +
           std::to_string(c.lines_used) + " defect line(s)";
  return c;
}

}  // namespace amb::host::hybrid
