#include "model/plant/rotor_amb_plant.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace amb::model {
namespace {

constexpr double k_two_pi = 2.0 * M_PI;

// Exact first-order lag factor over h for a bandwidth in Hz (0: no lag).
double lag_alpha(double bandwidth_hz, double h) {
  return bandwidth_hz > 0.0 ? 1.0 - std::exp(-k_two_pi * bandwidth_hz * h) : 1.0;
}

// First-order lag y' = a (u - y), a = 2 pi bandwidth, over a step h with u moving linearly
// from u0 to u1: y1 = y0 + alpha (u0 - y0) + ramp (u1 - u0), ramp = 1 - alpha / (a h)
// (-> a h / 2 for a slow lag, 1 for none).
double ramp_gain(double bandwidth_hz, double h) {
  if (!(bandwidth_hz > 0.0)) return 1.0;
  const double ah = k_two_pi * bandwidth_hz * h;
  return ah < 1e-6 ? 0.5 * ah : 1.0 - lag_alpha(bandwidth_hz, h) / ah;
}

}  // namespace

RotorAmbPlant::RotorAmbPlant(const PlantParams& p) : RotorAmbPlant(p, Options{}) {}

RotorAmbPlant::RotorAmbPlant(const PlantParams& p, const Options& o) : RotorAmbPlant(RigModel::make(p), p, o) {}

RotorAmbPlant::RotorAmbPlant(std::shared_ptr<const RigModel> rig, const PlantParams& p, const Options& o)
    : p_(p), o_(o), rig_(std::move(rig)), rng_(o.noise_seed) {
  if (!rig_) throw std::invalid_argument("plant: no rig model");
  rig_->check_same_rig(p, "plant");
  rows_ = make_step_rows(*rig_, rig_->board_reduction(), p, "plant");
  m_ = rows_.modes;
  for (size_t b = 0; b < 2; ++b) aux_inv_mass_[b] = rows_.aux[b].squaredNorm();

  // Sub-step rule (see header).
  double w_max = std::sqrt(rows_.w2.maxCoeff());
  double h_damp = 1e300;
  for (size_t b = 0; b < 2; ++b) {
    w_max = std::max(w_max, std::sqrt(p.aux[b].contact_stiffness_n_per_m * aux_inv_mass_[b]));
    if (p.aux[b].contact_damping_n_s_per_m > 0.0)
      h_damp = std::min(h_damp, 0.5 / (p.aux[b].contact_damping_n_s_per_m * aux_inv_mass_[b]));
  }
  h_rule_s_ = std::min(0.2 / w_max, h_damp);
  h_nominal_s_ = p.integration_step_s > 0.0 ? std::min(p.integration_step_s, h_rule_s_) : h_rule_s_;

  fconst_x_ = Vec::Zero(m_);
  fconst_y_ = Vec::Zero(m_);
  unb_s_step_ = rows_.unb_sin;
  unb_c_step_ = rows_.unb_cos;
  reset(false, 0.0);
}

void RotorAmbPlant::reset(bool levitated, double spin_hz) {
  film_extra_n_ = {};
  film_prev_v_m_s_ = {};
  film_prev_dt_s_ = 0.0;
  ex_ = Vec::Zero(m_);
  ey_ = Vec::Zero(m_);
  vx_ = Vec::Zero(m_);
  vy_ = Vec::Zero(m_);
  if (!levitated) {
    // Static rest on both touchdown bearings (bottom of each ring): the contacts act as
    // springs below the clearance; x is held at the ring centres by the same springs.
    Mat a = Mat(m_, m_);
    a = rows_.w2.asDiagonal();
    Vec rx = Vec::Zero(m_), ry = rows_.gravity_y;
    for (size_t b = 0; b < 2; ++b) {
      const double k = p_.aux[b].contact_stiffness_n_per_m;
      a += k * rows_.aux[b] * rows_.aux[b].transpose();
      rx += k * p_.aux[b].centre_offset_x_m * rows_.aux[b];
      ry += k * (p_.aux[b].centre_offset_y_m - p_.aux[b].clearance_m) * rows_.aux[b];
    }
    Eigen::LDLT<Mat> ldlt(a);
    ex_ = ldlt.solve(rx);
    ey_ = ldlt.solve(ry);
  }
  t_s_ = 0.0;
  spin_rad_s_ = k_two_pi * spin_hz;
  spin_angle_rad_ = 0.0;
  spin_accel_rad_s2_ = 0.0;
  ring_rad_s_ = {0.0, 0.0};
  current_a_ = {};
  // A levitated start has the bias flux established; a start at rest has none.
  for (size_t j = 0; j < 4; ++j) bias_a_[j] = levitated ? rows_.law[j / 2].bias_a : 0.0;
  amb_force_n_ = {};
  contact_ = {};
  friction_dissipated_j_ = 0.0;
  faults_ = PlantFaults{};
  counters_ = Counters{};
  rng_.reseed(o_.noise_seed);
  for (size_t s = 0; s < 4; ++s) {
    sensor_filtered_m_[s] = rows_.sensor_dir[s][0] * rows_.sensor[s].dot(ex_) + rows_.sensor_dir[s][1] * rows_.sensor[s].dot(ey_);
    sensor_true_m_[s] = sensor_filtered_m_[s];
    sensor_out_m_[s] = sensor_filtered_m_[s];
  }
  unb_s_step_ = rows_.unb_sin;
  unb_c_step_ = rows_.unb_cos;
}

void RotorAmbPlant::set_faults(const PlantFaults& faults) { faults_ = faults; }

void RotorAmbPlant::set_journal(const journal::LinearJournal& j) {
  journal_ = j;
  journal_probe_m_ = {};
  journal_force_n_ = {};
  if (!j.enabled) return;
  if (!(j.ref_spin_rad_s > 0.0)) throw std::invalid_argument("plant: journal linearisation speed must be > 0");
  b_journal_ = to_step_vec(rig_->modal_row(rig_->board_reduction(), j.axial_m));
  for (size_t k = 0; k < 2; ++k) journal_probe_dir_[k] = magnet::axis_direction(j.probe_angle_deg[k]);
  // Sub-step rule with the film as a spring (up to twice the linearisation speed) and a damper.
  const double inv_mass = b_journal_.squaredNorm();
  const double k_max = 2.0 * j.coeff.stiffness_n_per_m.cwiseAbs().maxCoeff();
  const double c_max = j.coeff.damping_n_s_per_m.cwiseAbs().maxCoeff();
  h_rule_s_ = std::min(h_rule_s_, 0.2 / std::sqrt(k_max * inv_mass + rows_.w2.maxCoeff()));
  if (c_max > 0.0) h_rule_s_ = std::min(h_rule_s_, 0.5 / (c_max * inv_mass));
  h_nominal_s_ = p_.integration_step_s > 0.0 ? std::min(p_.integration_step_s, h_rule_s_) : h_rule_s_;
  amp_h_ = -1.0;
}

void RotorAmbPlant::set_journal_film(std::shared_ptr<journal::ReynoldsSolver> solver) {
  film_ = std::move(solver);
  film_extra_n_ = {};
  film_prev_v_m_s_ = {};
  film_prev_dt_s_ = 0.0;
}

void RotorAmbPlant::step(double dt_s, const PlantInputs& in) {
  if (!(dt_s > 0.0)) return;
  film_extra_n_ = {};
  if (film_ && journal_.enabled && spin_rad_s_ > 0.0) {
    // Journal state at the middle of this step (see set_journal_film), from the bore centre.
    const double vx = b_journal_.dot(vx_), vy = b_journal_.dot(vy_);
    double ax = 0.0, ay = 0.0;
    if (film_prev_dt_s_ > 0.0) {
      ax = (vx - film_prev_v_m_s_[0]) / film_prev_dt_s_;
      ay = (vy - film_prev_v_m_s_[1]) / film_prev_dt_s_;
    }
    film_prev_v_m_s_ = {vx, vy};
    film_prev_dt_s_ = dt_s;
    const double hh = 0.5 * dt_s;
    const double x = b_journal_.dot(ex_) - journal_.bore_x_m + vx * hh + 0.5 * ax * hh * hh;
    const double y = b_journal_.dot(ey_) - journal_.bore_y_m + vy * hh + 0.5 * ay * hh * hh;
    const double vmx = vx + ax * hh, vmy = vy + ay * hh;
    try {
      const journal::FilmForces f = film_->solve({x, y, vmx, vmy}, spin_rad_s_);
      const auto& k = journal_.coeff.stiffness_n_per_m;
      const auto& c = journal_.coeff.damping_n_s_per_m;
      const double sc = spin_rad_s_ / journal_.ref_spin_rad_s;
      const double dx = x - journal_.lin_x_m, dy = y - journal_.lin_y_m;
      const double lx = sc * (journal_.coeff.fx0_n - k(0, 0) * dx - k(0, 1) * dy) - c(0, 0) * vmx - c(0, 1) * vmy;
      const double ly = sc * (journal_.coeff.fy0_n - k(1, 0) * dx - k(1, 1) * dy) - c(1, 0) * vmx - c(1, 1) * vmy;
      film_extra_n_ = {f.fx_n - lx, f.fy_n - ly};
    } catch (const std::invalid_argument&) {
      ++counters_.film_refused_steps;
    }
  }
  const int n = std::max(1, static_cast<int>(std::ceil(dt_s / h_nominal_s_ - 1e-9)));
  const double h = dt_s / n;
  if (h != amp_h_) {
    amp_h_ = h;
    for (size_t b = 0; b < 2; ++b) amp_alpha_[b] = lag_alpha(p_.amb[b].amplifier_bandwidth_hz, h);
    for (size_t s = 0; s < 4; ++s) {
      sensor_alpha_[s] = lag_alpha(p_.sensor[s].bandwidth_hz, h);
      sensor_ramp_[s] = ramp_gain(p_.sensor[s].bandwidth_hz, h);
    }
    // Implicit Rayleigh damping of the kick, and the film damping's direction through it.
    kick_den_ = (1.0 + h * rows_.damp.array()).matrix();
    if (journal_.enabled) {
      journal_u_ = b_journal_.cwiseQuotient(kick_den_);
      journal_g_ = b_journal_.dot(journal_u_);
    }
  }
  // Forces that change slowly enough to hold over one call: gravity, the misalignment
  // drift (coupling force at the right end) and the unbalance growth at the mid disk.
  fconst_x_ = Vec::Zero(m_);
  fconst_y_ = rows_.gravity_y;
  if (t_s_ >= faults_.misalignment_start_s && faults_.misalignment_stiffness_n_per_m > 0.0) {
    const double drift = faults_.misalignment_rate_m_per_s * (t_s_ - faults_.misalignment_start_s);
    const auto d = magnet::axis_direction(faults_.misalignment_direction_deg);
    const double f = faults_.misalignment_stiffness_n_per_m * drift;
    fconst_x_ += f * d[0] * rows_.coupling;
    fconst_y_ += f * d[1] * rows_.coupling;
  }
  unb_s_step_ = rows_.unb_sin;
  unb_c_step_ = rows_.unb_cos;
  if (t_s_ >= faults_.unbalance_growth_start_s) {
    const double du = faults_.unbalance_growth_kg_m_per_s * (t_s_ - faults_.unbalance_growth_start_s);
    unb_s_step_ += du * std::sin(rows_.mid_disk_phase_rad) * rows_.mid_disk;
    unb_c_step_ += du * std::cos(rows_.mid_disk_phase_rad) * rows_.mid_disk;
  }
  for (const double d : in.current_demand_a)
    if (std::abs(d) > p_.amb[0].coil_current_limit_a) {
      ++counters_.current_limited_steps;
      break;
    }
  for (int i = 0; i < n; ++i) substep(h, in);
  for (size_t s = 0; s < 4; ++s)
    sensor_out_m_[s] = sensor_filtered_m_[s] + p_.sensor[s].noise_rms_m * rng_.normal();
  if (journal_.enabled) {
    const double jx = b_journal_.dot(ex_) - journal_.bore_x_m, jy = b_journal_.dot(ey_) - journal_.bore_y_m;
    for (size_t k = 0; k < 2; ++k)
      journal_probe_m_[k] = journal_probe_dir_[k][0] * jx + journal_probe_dir_[k][1] * jy +
                            journal_.probe_noise_rms_m * rng_.normal();
  }
}

void RotorAmbPlant::substep(double h, const PlantInputs& in) {
  ++counters_.substeps;
  Vec fx = fconst_x_, fy = fconst_y_;

  // Amplifiers and AMB forces. Disabled amplifiers carry no current at all (bias included).
  for (size_t b = 0; b < 2; ++b) {
    const double xb = rows_.amb[b].dot(ex_), yb = rows_.amb[b].dot(ey_);
    double fxb = 0.0, fyb = 0.0;
    for (size_t a = 0; a < 2; ++a) {
      const size_t j = 2 * b + a;
      double force = 0.0;
      if (in.amplifiers_enabled) {
        double cmd = faults_.current_factor[j] * in.current_demand_a[j];
        if (t_s_ >= faults_.disturbance_start_s)
          cmd += faults_.disturbance_amplitude_a[j] *
                 std::sin(k_two_pi * faults_.disturbance_frequency_hz * (t_s_ - faults_.disturbance_start_s));
        const double lim = p_.amb[b].coil_current_limit_a;
        cmd = std::clamp(cmd, -lim, lim);
        // The force of this sub-step is the one at its start (x_n, i_n): the velocity update
        // below is the kick of a leapfrog step centred on t_n. The current then follows its
        // held command exactly to t_n + h. (Using the updated current here made the loop act
        // one sub-step early.)
        // The amplifier drives the coil currents i0 +- ic: the bias builds up through the same
        // lag as the control current when the amplifiers are switched on.
        magnet::AxisLaw law = rows_.law[b];
        law.bias_a = bias_a_[j];
        const double z = rows_.act_dir[j][0] * xb + rows_.act_dir[j][1] * yb;
        force = magnet::axis_force_n(law, z, current_a_[j]);
        current_a_[j] += amp_alpha_[b] * (cmd - current_a_[j]);
        bias_a_[j] += amp_alpha_[b] * (rows_.law[b].bias_a - bias_a_[j]);
      } else {
        current_a_[j] = 0.0;
        bias_a_[j] = 0.0;
      }
      amb_force_n_[j] = force;
      fxb += force * rows_.act_dir[j][0];
      fyb += force * rows_.act_dir[j][1];
    }
    fx += fxb * rows_.amb[b];
    fy += fyb * rows_.amb[b];
  }

  // Auxiliary bearings.
  double spin_torque = 0.0;
  bool any_contact = false;
  for (size_t b = 0; b < 2; ++b) {
    ContactState cs;
    cs.x_m = rows_.aux[b].dot(ex_);
    cs.y_m = rows_.aux[b].dot(ey_);
    const double dx = cs.x_m - p_.aux[b].centre_offset_x_m, dy = cs.y_m - p_.aux[b].centre_offset_y_m;
    if (dx * dx + dy * dy <= p_.aux[b].clearance_m * p_.aux[b].clearance_m) {
      contact_[b] = ContactResult{};
      continue;
    }
    any_contact = true;
    cs.vx_m_s = rows_.aux[b].dot(vx_);
    cs.vy_m_s = rows_.aux[b].dot(vy_);
    cs.spin_rad_s = spin_rad_s_;
    cs.ring_rad_s = ring_rad_s_[b];
    cs.lateral_inv_mass_1_per_kg = aux_inv_mass_[b];
    cs.spin_inertia_kg_m2 = rows_.spin_inertia_kg_m2;
    contact_[b] = aux_contact(p_.aux[b], cs, h, o_.slip_regularisation_m_s, o_.contact_exponent);
    fx += contact_[b].fx_n * rows_.aux[b];
    fy += contact_[b].fy_n * rows_.aux[b];
    spin_torque += contact_[b].spin_torque_n_m;
    friction_dissipated_j_ += h * contact_[b].friction_power_w;
  }
  if (any_contact) ++counters_.contact_substeps;

  // Journal bearing: linearised film force, scaled with speed (see journal_rig.hpp). The
  // stiffness part here; the damping part acts on the mean of the journal velocities before and
  // after the kick (trapezoidal, solved with the velocity update below), i.e. at t_n like the
  // other forces (the stored velocity is half a sub-step old).
  const double vjx0 = journal_.enabled ? b_journal_.dot(vx_) : 0.0;
  const double vjy0 = journal_.enabled ? b_journal_.dot(vy_) : 0.0;
  if (journal_.enabled) {
    const double dx = b_journal_.dot(ex_) - journal_.bore_x_m - journal_.lin_x_m;
    const double dy = b_journal_.dot(ey_) - journal_.bore_y_m - journal_.lin_y_m;
    const auto& k = journal_.coeff.stiffness_n_per_m;
    const double sc = spin_rad_s_ / journal_.ref_spin_rad_s;
    const double fjx = sc * (journal_.coeff.fx0_n - k(0, 0) * dx - k(0, 1) * dy) + film_extra_n_[0];
    const double fjy = sc * (journal_.coeff.fy0_n - k(1, 0) * dx - k(1, 1) * dy) + film_extra_n_[1];
    journal_force_n_ = {fjx, fjy};
    fx += fjx * b_journal_;
    fy += fjy * b_journal_;
  }

  // Unbalance (see constructor for the expansion).
  const double c = std::cos(spin_angle_rad_), s = std::sin(spin_angle_rad_);
  const double w2 = spin_rad_s_ * spin_rad_s_, wd = spin_accel_rad_s2_;
  const double cx = w2 * c + wd * s, sx = -w2 * s + wd * c;   // x: cx S + sx C
  fx += cx * unb_s_step_ + sx * unb_c_step_;
  fy += (w2 * s - wd * c) * unb_s_step_ + (w2 * c + wd * s) * unb_c_step_;

  // Lateral motion: explicit stiffness, implicit Rayleigh damping, then the gyroscopic
  // rotation (I - h W G + (h W)^2/2 G^2 with G = [[0, P], [-P, 0]]), then positions.
  vx_ = (vx_ + h * (fx - rows_.w2.cwiseProduct(ex_))).cwiseQuotient(kick_den_);
  vy_ = (vy_ + h * (fy - rows_.w2.cwiseProduct(ey_))).cwiseQuotient(kick_den_);
  if (journal_.enabled) {
    // Film damping F = -C (v0 + v1) / 2 at the journal, v = b . v_modal: with D the diagonal
    // of the update above and u = D^-1 b, v1_modal = v1_above - (h/2) u (C (v0 + v1)), so the
    // journal's new velocity solves (I + (h/2) g C) v1 = s - (h/2) g C v0, g = b . u.
    const auto& cj = journal_.coeff.damping_n_s_per_m;
    const Vec& u = journal_u_;
    const double hg = 0.5 * h * journal_g_;
    const double jx = b_journal_.dot(vx_) - hg * (cj(0, 0) * vjx0 + cj(0, 1) * vjy0);
    const double jy = b_journal_.dot(vy_) - hg * (cj(1, 0) * vjx0 + cj(1, 1) * vjy0);
    const double a00 = 1.0 + hg * cj(0, 0), a01 = hg * cj(0, 1), a10 = hg * cj(1, 0), a11 = 1.0 + hg * cj(1, 1);
    const double det = a00 * a11 - a01 * a10;
    const double v1x = (a11 * jx - a01 * jy) / det, v1y = (a00 * jy - a10 * jx) / det;
    const double fdx = -0.5 * (cj(0, 0) * (vjx0 + v1x) + cj(0, 1) * (vjy0 + v1y));
    const double fdy = -0.5 * (cj(1, 0) * (vjx0 + v1x) + cj(1, 1) * (vjy0 + v1y));
    vx_ += (h * fdx) * u;
    vy_ += (h * fdy) * u;
    journal_force_n_[0] += fdx;
    journal_force_n_[1] += fdy;
  }
  const double g = h * spin_rad_s_;
  if (g != 0.0) {
    const Vec pvx = rows_.polar * vx_, pvy = rows_.polar * vy_;
    const Vec ppvx = rows_.polar * pvx, ppvy = rows_.polar * pvy;
    vx_ += -g * pvy - 0.5 * g * g * ppvx;
    vy_ += g * pvx - 0.5 * g * g * ppvy;
  }
  ex_ += h * vx_;
  ey_ += h * vy_;

  // Spin: drive (speed loop with torque limit, only while the amplifiers are on) and the
  // contact friction torques.
  double drive = 0.0;
  if (in.amplifiers_enabled)
    drive = std::clamp(p_.drive_speed_gain_n_m_s * (k_two_pi * in.spin_speed_command_hz - spin_rad_s_),
                       -p_.drive_torque_limit_n_m, p_.drive_torque_limit_n_m);
  spin_accel_rad_s2_ = (drive + spin_torque) / rows_.spin_inertia_kg_m2;
  spin_rad_s_ += h * spin_accel_rad_s2_;
  spin_angle_rad_ = std::fmod(spin_angle_rad_ + h * spin_rad_s_, k_two_pi);

  // Rings: friction torque from the contact, drag implicit (linearised) for stability.
  for (size_t b = 0; b < 2; ++b) {
    const double j = p_.aux[b].ring_inertia_kg_m2, td = p_.aux[b].ring_friction_torque_n_m;
    const double eps = o_.ring_regularisation_rad_s, w = ring_rad_s_[b];
    const double den = std::sqrt(w * w + eps * eps);
    const double phi = w / den, dphi = eps * eps / (den * den * den);
    ring_rad_s_[b] = (w + h / j * (contact_[b].ring_torque_n_m - td * (phi - dphi * w))) / (1.0 + h * td * dphi / j);
  }

  // Sensors: true displacement along each sensor axis through the first-order roll-off,
  // exact for a displacement that moves linearly over the sub-step (first-order hold between
  // its values at t_n and t_n + h; holding the end value instead leads by half a sub-step).
  for (size_t k = 0; k < 4; ++k) {
    const double meas = rows_.sensor_dir[k][0] * rows_.sensor[k].dot(ex_) + rows_.sensor_dir[k][1] * rows_.sensor[k].dot(ey_);
    const double prev = sensor_true_m_[k];
    sensor_filtered_m_[k] += sensor_alpha_[k] * (prev - sensor_filtered_m_[k]) + sensor_ramp_[k] * (meas - prev);
    sensor_true_m_[k] = meas;
  }
  t_s_ += h;
}

PlantOutputs RotorAmbPlant::outputs() const {
  PlantOutputs o;
  o.t_s = t_s_;
  o.displacement_m = sensor_out_m_;
  o.coil_current_a = current_a_;
  o.spin_speed_hz = spin_rad_s_ / k_two_pi;
  o.spin_angle_rad = spin_angle_rad_;
  return o;
}

std::array<double, 2> RotorAmbPlant::displacement_at(double axial_m) const {
  const Eigen::RowVectorXd b = rig_->modal_row(rig_->board_reduction(), axial_m);
  double x = 0.0, y = 0.0;
  for (int i = 0; i < m_; ++i) {
    x += b(i) * ex_(i);
    y += b(i) * ey_(i);
  }
  return {x, y};
}

double RotorAmbPlant::contact_energy_j() const {
  double e = 0.0;
  for (size_t b = 0; b < 2; ++b) {
    const double dx = rows_.aux[b].dot(ex_) - p_.aux[b].centre_offset_x_m;
    const double dy = rows_.aux[b].dot(ey_) - p_.aux[b].centre_offset_y_m;
    const double pen = std::hypot(dx, dy) - p_.aux[b].clearance_m;
    if (pen > 0.0) e += 0.5 * p_.aux[b].contact_stiffness_n_per_m * pen * pen;
  }
  return e;
}

PlantTruth RotorAmbPlant::truth() const {
  PlantTruth t;
  for (size_t b = 0; b < 2; ++b) {
    t.aux_x_m[b] = rows_.aux[b].dot(ex_);
    t.aux_y_m[b] = rows_.aux[b].dot(ey_);
    t.contact_force_n[b] = contact_[b].normal_n;
    t.friction_force_n[b] = contact_[b].friction_n;
    t.ring_speed_rad_s[b] = ring_rad_s_[b];
    t.amb_x_m[b] = rows_.amb[b].dot(ex_);
    t.amb_y_m[b] = rows_.amb[b].dot(ey_);
  }
  t.amb_force_n = amb_force_n_;
  // Kinetic: lateral (mass-normalised modal velocities), spin and the two rings.
  t.kinetic_energy_j = 0.5 * (vx_.squaredNorm() + vy_.squaredNorm()) + 0.5 * rows_.spin_inertia_kg_m2 * spin_rad_s_ * spin_rad_s_;
  for (size_t b = 0; b < 2; ++b)
    t.kinetic_energy_j += 0.5 * p_.aux[b].ring_inertia_kg_m2 * ring_rad_s_[b] * ring_rad_s_[b];
  // Potential: shaft elastic + contact penalty springs + gravity (zero at the sensor zero).
  // The magnetic field energy of the AMBs is not included (the amplifiers are an input).
  t.potential_energy_j = 0.5 * (rows_.w2.dot(ex_.cwiseProduct(ex_)) + rows_.w2.dot(ey_.cwiseProduct(ey_))) +
                         contact_energy_j() - rows_.gravity_y.dot(ey_);
  t.friction_dissipated_j = friction_dissipated_j_;
  return t;
}

}  // namespace amb::model
