#include "model/bearing/hertz_4dof.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "model/bearing/rk4.hpp"

namespace amb::model::bearing {

bool Hertz4DofModel::configure(const Hertz4DofParams& p) {
  ok_ = false;
  const bool positive = p.shaft_mass_kg > 0 && p.housing_mass_kg > 0 && p.shaft_damping_n_s_per_m >= 0 &&
                        p.housing_damping_n_s_per_m >= 0 && p.shaft_stiffness_n_per_m >= 0 &&
                        p.housing_stiffness_n_per_m > 0 && p.stiffness_scale > 0 &&
                        p.hertz_constant_n_per_m1p5 >= 0 && p.max_step_s >= 0 && p.settle_s >= 0 &&
                        std::isfinite(p.load_x_n) && std::isfinite(p.load_y_n);
  if (!positive) return false;
  ContactLawParams cp;
  cp.geometry = p.bearing;
  const double kb_nom = p.hertz_constant_n_per_m1p5 > 0 ? p.hertz_constant_n_per_m1p5
                                                         : nominal_hertz_constant(p.bearing);
  cp.hertz_constant_n_per_m1p5 = p.stiffness_scale * kb_nom;
  cp.radial_clearance_m = p.radial_clearance_m;
  cp.defect = p.defect;
  cp.ball_size = p.ball_size;
  if (!law_.configure(cp)) return false;
  p_ = p;
  p_.hertz_constant_n_per_m1p5 = kb_nom;
  ok_ = true;
  return true;
}

SupportForce Hertz4DofModel::support_force(const Hertz4DofState& y) const noexcept {
  return law_.force(y[0] - y[4], y[2] - y[6], y[8]);
}

Hertz4DofState Hertz4DofModel::derivative(const Hertz4DofState& y, double shaft_speed_hz) const noexcept {
  const SupportForce f = support_force(y);
  Hertz4DofState d;
  d[0] = y[1];
  d[1] = (p_.load_x_n - f.fx_n - p_.shaft_damping_n_s_per_m * y[1] - p_.shaft_stiffness_n_per_m * y[0]) /
         p_.shaft_mass_kg;
  d[2] = y[3];
  d[3] = (p_.load_y_n - f.fy_n - p_.shaft_damping_n_s_per_m * y[3] - p_.shaft_stiffness_n_per_m * y[2]) /
         p_.shaft_mass_kg;
  d[4] = y[5];
  d[5] = (f.fx_n - p_.housing_damping_n_s_per_m * y[5] - p_.housing_stiffness_n_per_m * y[4]) /
         p_.housing_mass_kg;
  d[6] = y[7];
  d[7] = (f.fy_n - p_.housing_damping_n_s_per_m * y[7] - p_.housing_stiffness_n_per_m * y[6]) /
         p_.housing_mass_kg;
  d[8] = 2.0 * M_PI * shaft_speed_hz;
  return d;
}

double Hertz4DofModel::equivalent_stiffness_n_per_m(const Hertz4DofState& y) const noexcept {
  const SupportForce f = support_force(y);
  const double r = std::hypot(y[0] - y[4], y[2] - y[6]);
  return r > 0 ? std::hypot(f.fx_n, f.fy_n) / r : 0.0;
}

double Hertz4DofModel::sensor_acceleration(const Hertz4DofState& dydt) const noexcept {
  return dydt[5] * std::cos(p_.sensor_angle_rad) + dydt[7] * std::sin(p_.sensor_angle_rad);
}

namespace {
// Stribeck: peak ball load ~ 5 W / Z for a radially loaded ball bearing with small clearance.
double linearised_contact_stiffness(const HertzContactLaw& law, double load_n) {
  const auto& p = law.params();
  const double z = p.geometry.ball_count;
  const double kb = p.hertz_constant_n_per_m1p5;
  const double q_max = std::max(5.0 * load_n / z, 1.0);
  const double delta = std::cbrt((q_max / kb) * (q_max / kb));
  // dQ/d(delta) = 1.5 kb sqrt(delta) per ball; about Z/2 balls carry load.
  return 0.5 * z * 1.5 * kb * std::sqrt(delta);
}
}  // namespace

Hertz4DofState Hertz4DofModel::initial_state() const {
  Hertz4DofState y = Hertz4DofState::Zero();
  const double w = std::hypot(p_.load_x_n, p_.load_y_n);
  if (w <= 0) return y;
  const double kc = linearised_contact_stiffness(law_, w);
  // Springs in series: bearing contact then housing; in parallel with the shaft support.
  const double k_series = 1.0 / (1.0 / kc + 1.0 / p_.housing_stiffness_n_per_m);
  const double k_total = p_.shaft_stiffness_n_per_m + k_series;
  const double ux = p_.load_x_n / k_total;
  const double uy = p_.load_y_n / k_total;
  const double f_share = k_series / k_total;  // fraction of W through the bearing
  y[0] = ux + p_.radial_clearance_m * p_.load_x_n / w;
  y[2] = uy + p_.radial_clearance_m * p_.load_y_n / w;
  y[4] = f_share * p_.load_x_n / p_.housing_stiffness_n_per_m;
  y[6] = f_share * p_.load_y_n / p_.housing_stiffness_n_per_m;
  return y;
}

double Hertz4DofModel::choose_step_s(double max_shaft_speed_hz, double fs_hz) const {
  const double w = std::hypot(p_.load_x_n, p_.load_y_n);
  const double kc = linearised_contact_stiffness(law_, std::max(w, 10.0));
  const double w2 = std::max({(p_.shaft_stiffness_n_per_m + kc) / p_.shaft_mass_kg,
                              (p_.housing_stiffness_n_per_m + kc) / p_.housing_mass_kg});
  double h = 0.05 * 2.0 * M_PI / std::sqrt(w2);
  // Defect transit (groove under a ball, or a ball's spot past a race) in 4 steps at least;
  // no bound without a defect or with zero applied depth (then the model is the healthy one,
  // step for step).
  const double transit_s = law_.defect_transit_time_s(max_shaft_speed_hz);
  if (std::isfinite(transit_s)) h = std::min(h, 0.25 * transit_s);
  if (p_.max_step_s > 0) h = std::min(h, p_.max_step_s);
  const double period = 1.0 / fs_hz;
  const double n = std::ceil(period / h - 1e-9);
  return period / std::max(1.0, n);
}

void simulate_housing_acceleration_into(const Hertz4DofModel& model,
                                        const std::function<double(double t_s)>& shaft_speed_hz,
                                        double fs_hz, double duration_s, std::vector<double>& out) {
  if (!(fs_hz > 0) || !(duration_s > 0)) throw std::invalid_argument("fs_hz and duration_s must be > 0");
  const auto n_out = static_cast<size_t>(std::floor(duration_s * fs_hz));
  out.assign(n_out, 0.0);
  // Bound the speed for the step rule by sampling N(t) (the function is arbitrary).
  double max_speed = std::abs(shaft_speed_hz(0.0));
  for (int i = 1; i <= 256; ++i) max_speed = std::max(max_speed, std::abs(shaft_speed_hz(duration_s * i / 256.0)));
  const double h = model.choose_step_s(max_speed, fs_hz);
  const auto sub = static_cast<long>(std::llround(1.0 / (fs_hz * h)));
  auto rhs = [&](double t, const Hertz4DofState& y) {
    return model.derivative(y, shaft_speed_hz(std::max(t, 0.0)));
  };
  Hertz4DofState y = model.initial_state();
  const double settle = model.params().settle_s;
  const auto n_settle = static_cast<long>(std::ceil(settle / h));
  double t = -static_cast<double>(n_settle) * h;
  for (long i = 0; i < n_settle; ++i) {
    rk4_step<9>(rhs, t, y, h);
    t += h;
  }
  t = 0.0;
  for (size_t k = 0; k < n_out; ++k) {
    const double t0 = static_cast<double>(k) / fs_hz;
    for (long s = 0; s < sub; ++s) {
      const Hertz4DofState k1 = rk4_step<9>(rhs, t0 + static_cast<double>(s) * h, y, h);
      if (s == 0) out[k] = model.sensor_acceleration(k1);
    }
    // The shaft angle is not wrapped: the cage angle is an irrational multiple of it, so a
    // wrap would make the cage jump. Doubles keep ~1e-10 rad at 1e6 rad (hours of running).
  }
}

std::vector<double> simulate_housing_acceleration(const Hertz4DofParams& p,
                                                  const std::function<double(double t_s)>& shaft_speed_hz,
                                                  double fs_hz, double duration_s, double noise_rms,
                                                  uint64_t noise_seed) {
  Hertz4DofModel model;
  if (!model.configure(p)) throw std::invalid_argument("Hertz4DofParams out of range");
  if (!(noise_rms >= 0)) throw std::invalid_argument("noise_rms must be >= 0");
  std::vector<double> out;
  simulate_housing_acceleration_into(model, shaft_speed_hz, fs_hz, duration_s, out);
  if (noise_rms > 0) {
    std::mt19937_64 rng(noise_seed);
    std::normal_distribution<double> gauss(0.0, noise_rms);
    for (double& v : out) v += gauss(rng);
  }
  return out;
}

}  // namespace amb::model::bearing
