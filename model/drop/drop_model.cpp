#include "model/drop/drop_model.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace amb::model::drop {
namespace {

constexpr double k_two_pi = 2.0 * M_PI;

// Orbit radius. Not std::hypot: its overflow-safe scaling cost 13 % of the step time, and
// displacements here are micrometres to millimetres (no overflow or underflow possible).
inline double radius(double x, double y) { return std::sqrt(x * x + y * y); }

double lag_alpha(double bandwidth_hz, double h) {
  return bandwidth_hz > 0.0 ? 1.0 - std::exp(-k_two_pi * bandwidth_hz * h) : 1.0;
}

// Inverse of the 2 x 2 matrix [[a, b], [c, d]] stored row-major.
std::array<double, 4> inverse2(double a, double b, double c, double d) {
  const double det = a * d - b * c;
  if (std::abs(det) < 1e-9) throw std::invalid_argument("drop model: parallel sensor or actuator axes");
  return {d / det, -b / det, -c / det, a / det};
}

void fail(const std::string& what) { throw std::invalid_argument("drop model: " + what); }

}  // namespace

DropModel::DropModel(const PlantParams& plant, const PidParams& pid, double controller_rate_hz,
                     const DropOptions& options)
    : DropModel(RigModel::make(plant), plant, pid, controller_rate_hz, options) {}

DropModel::DropModel(std::shared_ptr<const RigModel> rig, const PlantParams& plant, const PidParams& pid,
                     double controller_rate_hz, const DropOptions& options)
    : p_(plant), pid_(pid), o_(options), rig_(std::move(rig)) {
  if (!rig_) fail("no rig model");
  rig_->check_same_rig(p_, "drop model");
  if (const std::string e = o_.check(); !e.empty()) fail(e);
  if (o_.internal_controller && !(controller_rate_hz > 0.0)) fail("controller_rate_hz must be > 0");
  ctrl_period_s_ = controller_rate_hz > 0.0 ? 1.0 / controller_rate_hz : 0.0;
  solver_.tolerance_m_s = o_.solver_tolerance_m_s;
  solver_.max_iterations = o_.solver_max_iterations;
  for (size_t b = 0; b < 2; ++b) {
    const auto& a = p_.aux[b];
    const std::string n = "aux bearing " + std::to_string(b) + ": ";
    if (!(a.clearance_m > 0.0)) fail(n + "clearance_m must be > 0");
    if (!(a.collar_radius_m > 0.0)) fail(n + "collar_radius_m must be > 0");
    if (!(a.ring_inertia_kg_m2 > 0.0)) fail(n + "ring_inertia_kg_m2 must be > 0");
    if (!(a.friction_coefficient >= 0.0)) fail(n + "friction_coefficient must be >= 0");
    if (!(a.ring_friction_torque_n_m >= 0.0)) fail(n + "ring_friction_torque_n_m must be >= 0");
    ring_radius_m_[b] = a.collar_radius_m + a.clearance_m;
  }

  const int modes = o_.modes_per_plane > 0 ? o_.modes_per_plane : p_.rotor.modes_kept;
  red_ = modes == p_.rotor.modes_kept ? rig_->board_reduction() : rig_->reduction(modes);
  rows_ = make_step_rows(*rig_, red_, p_, "drop model");
  m_ = rows_.modes;
  for (size_t b = 0; b < 2; ++b) {
    const auto& s0 = rows_.sensor_dir[2 * b];
    const auto& s1 = rows_.sensor_dir[2 * b + 1];
    sensor_inv_[b] = inverse2(s0[0], s0[1], s1[0], s1[1]);
    const auto& a0 = rows_.act_dir[2 * b];
    const auto& a1 = rows_.act_dir[2 * b + 1];
    actuator_inv_[b] = inverse2(a0[0], a1[0], a0[1], a1[1]);
  }
  fext_x_ = ModeVec::Zero(m_);
  fext_y_ = ModeVec::Zero(m_);
  unb_s_step_ = rows_.unb_sin;
  unb_c_step_ = rows_.unb_cos;
  for (auto& mm : mats_) {
    mm.a_inv = LatMat::Identity(2 * m_, 2 * m_);
    mm.z = LatBasis::Zero(2 * m_, 4);
    mm.s_aux.setZero();
  }
  // Contact law: the board's (both bearings must agree) or the options' override.
  switch (o_.contact_law) {
    case ContactLawChoice::board:
      if (p_.aux[0].contact_law != p_.aux[1].contact_law) fail("the two aux bearings must use the same contact_law");
      contact_law_ = p_.aux[0].contact_law;
      break;
    case ContactLawChoice::rigid: contact_law_ = AuxContactLaw::rigid; break;
    case ContactLawChoice::hertz: contact_law_ = AuxContactLaw::hertz; break;
    case ContactLawChoice::linear: contact_law_ = AuxContactLaw::linear; break;
  }
  if (compliant()) {
    law_exp_ = contact_law_ == AuxContactLaw::hertz ? 1.5 : 1.0;
    for (size_t b = 0; b < 2; ++b) {
      if (!(p_.aux[b].contact_stiffness_n_per_m > 0.0)) fail("aux bearing " + std::to_string(b) + ": contact_stiffness_n_per_m must be > 0 for a compliant contact law");
      if (!(p_.aux[b].contact_damping_n_s_per_m >= 0.0)) fail("aux bearing " + std::to_string(b) + ": contact_damping_n_s_per_m must be >= 0");
    }
    for (size_t b = 0; b < 2; ++b) {
      law_k_[b] = contact_law_coefficient(p_.aux[b].contact_stiffness_n_per_m, law_exp_, o_.hertz_reference_penetration_m);
    }
  }
  reset(true, 0.0);
}

void DropModel::set_friction_coefficient(double mu) {
  if (!(mu >= 0.0)) fail("friction coefficient must be >= 0");
  for (auto& a : p_.aux) a.friction_coefficient = mu;
}

void DropModel::set_restitution(double e) {
  if (!(e >= 0.0 && e <= 1.0)) fail("restitution must be in [0, 1]");
  o_.restitution = e;
}

void DropModel::set_aux_centre_offset(int bearing, double x_m, double y_m) {
  if (bearing < 0 || bearing > 1) fail("bearing index must be 0 or 1");
  p_.aux[static_cast<size_t>(bearing)].centre_offset_x_m = x_m;
  p_.aux[static_cast<size_t>(bearing)].centre_offset_y_m = y_m;
}

void DropModel::set_contact_stiffness(double n_per_m) {
  if (!(n_per_m > 0.0)) fail("contact stiffness must be > 0");
  for (size_t b = 0; b < 2; ++b) {
    p_.aux[b].contact_stiffness_n_per_m = n_per_m;
    law_k_[b] = contact_law_coefficient(n_per_m, law_exp_, o_.hertz_reference_penetration_m);
  }
}

void DropModel::set_contact_exponent(double e) {
  if (!(e >= 1.0 && e <= 2.0)) fail("contact exponent must be in [1, 2]");
  if (!compliant()) return;
  law_exp_ = e;
  set_contact_stiffness(0.5 * (p_.aux[0].contact_stiffness_n_per_m + p_.aux[1].contact_stiffness_n_per_m));
}

void DropModel::set_contact_damping(double n_s_per_m) {
  if (!(n_s_per_m >= 0.0)) fail("contact damping must be >= 0");
  for (auto& a : p_.aux) a.contact_damping_n_s_per_m = n_s_per_m;
}

void DropModel::set_slip_regularisation(double m_s) {
  if (!(m_s >= 0.0)) fail("slip regularisation must be >= 0");
  o_.slip_regularisation_m_s = m_s;
}

void DropModel::set_ring_drag(double n_m) {
  if (!(n_m >= 0.0)) fail("ring drag must be >= 0");
  for (auto& a : p_.aux) a.ring_friction_torque_n_m = n_m;
}

double DropModel::contact_force_n(size_t b, double d_m) const {
  if (d_m <= 0.0) return 0.0;
  return law_k_[b] * (law_exp_ == 1.0 ? d_m : law_exp_ == 1.5 ? d_m * std::sqrt(d_m) : std::pow(d_m, law_exp_));
}

double DropModel::contact_energy_at(size_t b, double d_m) const {
  return d_m > 0.0 ? contact_force_n(b, d_m) * d_m / (law_exp_ + 1.0) : 0.0;
}

void DropModel::set_faults(const PlantFaults& faults) { s_.faults = faults; }

void DropModel::reset(bool levitated, double spin_hz) {
  DropState s;
  s.q = LatVec::Zero(2 * m_);
  s.u = LatVec::Zero(2 * m_);
  s.rng.reseed(o_.noise_seed);
  s.spin_rad_s = k_two_pi * spin_hz;
  if (!levitated) {
    // Static rest on the bottom of both rings: elastic equilibrium under gravity with the
    // two aux planes pinned (rigid contacts), i.e. the KKT system [[K, B], [B^T, 0]].
    for (int axis = 0; axis < 2; ++axis) {
      Eigen::MatrixXd kkt = Eigen::MatrixXd::Zero(m_ + 2, m_ + 2);
      Eigen::VectorXd rhs = Eigen::VectorXd::Zero(m_ + 2);
      for (int i = 0; i < m_; ++i) kkt(i, i) = rows_.w2(i);
      if (axis == 1) rhs.head(m_) = rows_.gravity_y;
      for (int b = 0; b < 2; ++b) {
        const auto& a = p_.aux[static_cast<size_t>(b)];
        kkt.block(0, m_ + b, m_, 1) = rows_.aux[static_cast<size_t>(b)];
        kkt.block(m_ + b, 0, 1, m_) = rows_.aux[static_cast<size_t>(b)].transpose();
        rhs(m_ + b) = axis == 0 ? a.centre_offset_x_m : a.centre_offset_y_m - a.clearance_m;
      }
      const Eigen::VectorXd sol = kkt.fullPivLu().solve(rhs);
      s.q.segment(axis * m_, m_) = sol.head(m_);
    }
  } else if (o_.internal_controller) {
    // Preload the PID integrators with each bearing's share of the weight (rigid-body modal
    // balance) so that the levitated state settles quickly.
    Eigen::Matrix2d a;
    Eigen::Vector2d g;
    int r = 0;
    for (int i = 0; i < m_ && r < 2; ++i)
      if (rows_.w2(i) == 0.0) {
        a(r, 0) = rows_.amb[0](i);
        a(r, 1) = rows_.amb[1](i);
        g(r) = -rows_.gravity_y(i);
        ++r;
      }
    if (r == 2) {
      const Eigen::Vector2d f = a.fullPivLu().solve(g);
      s.pid_integral_n[1] = -f(0);
      s.pid_integral_n[3] = -f(1);
    }
  }
  for (size_t k = 0; k < 4; ++k) {
    s.sensor_filtered_m[k] = rows_.sensor_dir[k][0] * rows_.sensor[k].dot(s.q.head(m_)) +
                             rows_.sensor_dir[k][1] * rows_.sensor[k].dot(s.q.tail(m_));
    s.sensor_out_m[k] = s.sensor_filtered_m[k];
  }
  s_ = s;
  counters_ = DropCounters{};
  for (auto& mm : mats_) mm.h = -1.0;
}

void DropModel::controller_update(double period_s) {
  // The firmware's law (firmware/control/pid_axis.cpp): sensors -> bearing-frame (x, y),
  // PID on each with a filtered backward-difference derivative and conditional
  // integration, force -> actuator axes -> current = force / ki. Notches are not modelled.
  const double deriv_alpha = std::exp(-k_two_pi * pid_.derivative_filter_hz * period_s);
  for (size_t b = 0; b < 2; ++b) {
    double r[2];
    for (size_t k = 0; k < 2; ++k) {
      const size_t j = 2 * b + k;
      r[k] = s_.sensor_filtered_m[j] + (o_.sensor_noise ? p_.sensor[j].noise_rms_m * s_.rng.normal() : 0.0);
    }
    const auto& si = sensor_inv_[b];
    double xy[2] = {si[0] * r[0] + si[1] * r[1], si[2] * r[0] + si[3] * r[1]};
    if (o_.internal_controller_collocated) {
      const double nz = o_.sensor_noise ? p_.sensor[2 * b].noise_rms_m : 0.0;
      xy[0] = rows_.amb[b].dot(s_.q.head(m_)) + nz * s_.rng.normal();
      xy[1] = rows_.amb[b].dot(s_.q.tail(m_)) + nz * s_.rng.normal();
    }
    const double ki = p_.amb[b].ki_n_per_a;
    const double force_limit = pid_.current_limit_a * ki;
    double f[2];
    for (size_t a = 0; a < 2; ++a) {
      const size_t j = 2 * b + a;
      const double e = xy[a];
      s_.pid_deriv_m_s[j] = deriv_alpha * s_.pid_deriv_m_s[j] + (1.0 - deriv_alpha) * (e - s_.pid_prev_error_m[j]) / period_s;
      s_.pid_prev_error_m[j] = e;
      const double u = -(pid_.kp_n_per_m * e + s_.pid_integral_n[j] + pid_.kd_n_s_per_m * s_.pid_deriv_m_s[j]);
      const bool saturated = std::abs(u) > force_limit;
      const double di = pid_.ki_n_per_m_s * e * period_s;
      const bool further = saturated && ((u > 0.0 && di < 0.0) || (u < 0.0 && di > 0.0));
      if (!further)
        s_.pid_integral_n[j] = std::clamp(s_.pid_integral_n[j] + di, -pid_.integrator_limit_n, pid_.integrator_limit_n);
      f[a] = std::clamp(u, -force_limit, force_limit);
    }
    const auto& ai = actuator_inv_[b];
    for (size_t a = 0; a < 2; ++a) {
      const double fa = ai[2 * a] * f[0] + ai[2 * a + 1] * f[1];
      s_.demand_a[2 * b + a] = std::clamp(fa / ki, -pid_.current_limit_a, pid_.current_limit_a);
    }
  }
}

void DropModel::step(double dt_s, const PlantInputs& in) {
  if (!(dt_s > 0.0)) return;
  const int n = std::max(1, static_cast<int>(std::ceil(dt_s / o_.step_s - 1e-9)));
  const double h = dt_s / n;
  // Slow fault forces held over the call (as rotor_amb_plant.cpp).
  const PlantFaults& f = s_.faults;
  fext_x_.setZero();
  fext_y_.setZero();
  if (s_.t_s >= f.misalignment_start_s && f.misalignment_stiffness_n_per_m > 0.0) {
    const double drift = f.misalignment_rate_m_per_s * (s_.t_s - f.misalignment_start_s);
    const auto d = magnet::axis_direction(f.misalignment_direction_deg);
    fext_x_ += f.misalignment_stiffness_n_per_m * drift * d[0] * rows_.coupling;
    fext_y_ += f.misalignment_stiffness_n_per_m * drift * d[1] * rows_.coupling;
  }
  unb_s_step_ = rows_.unb_sin;
  unb_c_step_ = rows_.unb_cos;
  if (s_.t_s >= f.unbalance_growth_start_s) {
    const double du = f.unbalance_growth_kg_m_per_s * (s_.t_s - f.unbalance_growth_start_s);
    unb_s_step_ += du * std::sin(rows_.mid_disk_phase_rad) * rows_.mid_disk;
    unb_c_step_ += du * std::cos(rows_.mid_disk_phase_rad) * rows_.mid_disk;
  }
  for (int i = 0; i < n; ++i) substep(h, in);
  for (size_t k = 0; k < 4; ++k)
    s_.sensor_out_m[k] = s_.sensor_filtered_m[k] + (o_.sensor_noise ? p_.sensor[k].noise_rms_m * s_.rng.normal() : 0.0);
}

void DropModel::refactor(double h, double spin_rad_s, StepMatrices& mm) {
  // A = I + h/2 (C + Omega G) + h^2/4 K, G = [[0, P], [-P, 0]] on (x modes, y modes).
  LatMat a = LatMat::Zero(2 * m_, 2 * m_);
  for (int i = 0; i < m_; ++i) {
    const double d = 1.0 + 0.5 * h * rows_.damp(i) + 0.25 * h * h * rows_.w2(i);
    a(i, i) = d;
    a(m_ + i, m_ + i) = d;
  }
  a.block(0, m_, m_, m_) = 0.5 * h * spin_rad_s * rows_.polar;
  a.block(m_, 0, m_, m_) = -0.5 * h * spin_rad_s * rows_.polar;
  mm.a_inv = a.partialPivLu().inverse();
  LatBasis b = LatBasis::Zero(2 * m_, 4);
  for (int k = 0; k < 2; ++k) {
    b.block(0, 2 * k, m_, 1) = rows_.aux[static_cast<size_t>(k)];
    b.block(m_, 2 * k + 1, m_, 1) = rows_.aux[static_cast<size_t>(k)];
  }
  mm.z.noalias() = mm.a_inv * b;
  mm.s_aux.noalias() = b.transpose() * mm.z;
  mm.h = h;
  mm.spin = spin_rad_s;
  ++counters_.refactorisations;
}

bool DropModel::compliant_contact_near(double h) const {
  // Sub-step when a compliant contact is closed and moving along its normal, or the rotor may
  // reach the ring within the step (end-of-step radius by the current velocity, plus a margin
  // of the velocity over the step). A closed contact whose normal velocity changes the
  // penetration by less than quiet_contact_share of it over the full step (rolling, sustained
  // whirl) takes the full step: its spring is linearised about a penetration that hardly moves.
  for (size_t b = 0; b < 2; ++b) {
    const auto& a = p_.aux[b];
    const ModeVec& bb = rows_.aux[b];
    const double x = bb.dot(s_.q.head(m_)) - a.centre_offset_x_m, y = bb.dot(s_.q.tail(m_)) - a.centre_offset_y_m;
    const double vx = bb.dot(s_.u.head(m_)), vy = bb.dot(s_.u.tail(m_));
    const double r = radius(x, y);
    if (r + 2.0 * h * radius(vx, vy) < a.clearance_m) continue;
    const double d0 = r - a.clearance_m;
    const bool quiet = d0 > 0.0 && std::abs(x * vx + y * vy) / r * h <= o_.quiet_contact_share * d0;
    if (!quiet) return true;
  }
  return false;
}

void DropModel::substep(double h, const PlantInputs& in) {
  if (compliant() && o_.contact_step_s < h && compliant_contact_near(h)) {
    const int n = static_cast<int>(std::ceil(h / o_.contact_step_s - 1e-9));
    const double hc = h / n;
    for (int i = 0; i < n; ++i) advance(hc, in, mats_[1]);
    counters_.contact_substeps += static_cast<std::uint64_t>(n);
    return;
  }
  advance(h, in, mats_[0]);
}

void DropModel::advance(double h, const PlantInputs& in, StepMatrices& M) {
  ++counters_.steps;
  if (h != M.lag_h) {
    M.lag_h = h;
    const bool lag = !o_.internal_controller || o_.internal_amplifier_lag;
    for (size_t b = 0; b < 2; ++b) M.amp_alpha[b] = lag ? lag_alpha(p_.amb[b].amplifier_bandwidth_hz, h) : 1.0;
    for (size_t k = 0; k < 4; ++k) M.sensor_alpha[k] = lag_alpha(p_.sensor[k].bandwidth_hz, h);
  }
  DropState& s = s_;
  const int m = m_;

  // Controller (internal mode): one update per controller period, on the sensors now.
  if (o_.internal_controller) {
    if (s.controller_clock_s <= 1e-12) {
      controller_update(ctrl_period_s_);
      s.controller_clock_s += ctrl_period_s_;
    }
    s.controller_clock_s -= h;
  }

  // 1. Smooth forces at the predicted midpoint (the AMBs' only while the amplifiers are on).
  ModeVec fx = fext_x_, fy = fext_y_;
  if (in.amplifiers_enabled) {
    const LatVec qm = s.q + 0.5 * h * s.u;
    for (size_t b = 0; b < 2; ++b) {
      const double xb = rows_.amb[b].dot(qm.head(m)), yb = rows_.amb[b].dot(qm.tail(m));
      double fxb = 0.0, fyb = 0.0;
      for (size_t a = 0; a < 2; ++a) {
        const size_t j = 2 * b + a;
        double cmd = s.faults.current_factor[j] * (o_.internal_controller ? s.demand_a[j] : in.current_demand_a[j]);
        if (s.t_s >= s.faults.disturbance_start_s)
          cmd += s.faults.disturbance_amplitude_a[j] *
                 std::sin(k_two_pi * s.faults.disturbance_frequency_hz * (s.t_s - s.faults.disturbance_start_s));
        const double lim = p_.amb[b].coil_current_limit_a;
        cmd = std::clamp(cmd, -lim, lim);
        s.current_a[j] += M.amp_alpha[b] * (cmd - s.current_a[j]);
        const double z = rows_.act_dir[j][0] * xb + rows_.act_dir[j][1] * yb;
        const double force = magnet::axis_force_n(rows_.law[b], z, s.current_a[j]);
        s.amb_force_n[j] = force;
        fxb += force * rows_.act_dir[j][0];
        fyb += force * rows_.act_dir[j][1];
      }
      fx += fxb * rows_.amb[b];
      fy += fyb * rows_.amb[b];
    }
  } else {
    s.current_a.fill(0.0);
    s.amb_force_n.fill(0.0);
  }
  {
    const double th = s.spin_angle_rad + 0.5 * h * s.spin_rad_s;
    const double c = std::cos(th), sn = std::sin(th);
    const double w2 = s.spin_rad_s * s.spin_rad_s, wd = s.spin_accel_rad_s2;
    fx += (w2 * c + wd * sn) * unb_s_step_ + (-w2 * sn + wd * c) * unb_c_step_;
    fy += (w2 * sn - wd * c) * unb_s_step_ + (w2 * c + wd * sn) * unb_c_step_;
  }
  double drive = 0.0;
  if (in.amplifiers_enabled)
    drive = std::clamp(p_.drive_speed_gain_n_m_s * (k_two_pi * in.spin_speed_command_hz - s.spin_rad_s),
                       -p_.drive_torque_limit_n_m, p_.drive_torque_limit_n_m);

  // 2. Free velocity of the midpoint rule (A^-1 rebuilt when the spin drifted by 0.1 %).
  if (h != M.h || std::abs(s.spin_rad_s - M.spin) > 1e-3 * std::max(1.0, std::abs(M.spin))) refactor(h, s.spin_rad_s, M);
  const double gs = 0.5 * h * M.spin;
  LatVec rhs(2 * m);
  {
    const auto ux = s.u.head(m), uy = s.u.tail(m), qx = s.q.head(m), qy = s.q.tail(m);
    const ModeVec pux = rows_.polar * ux, puy = rows_.polar * uy;
    const ModeVec diag = (1.0 - 0.5 * h * rows_.damp.array() - 0.25 * h * h * rows_.w2.array()).matrix();
    rhs.head(m) = diag.cwiseProduct(ux) - gs * puy - h * rows_.w2.cwiseProduct(qx) + h * fx;
    rhs.tail(m) = diag.cwiseProduct(uy) + gs * pux - h * rows_.w2.cwiseProduct(qy) + h * (fy + rows_.gravity_y);
  }
  LatVec u_free(2 * m);
  u_free.noalias() = M.a_inv * rhs;
  const double spin_free = s.spin_rad_s + h * drive / rows_.spin_inertia_kg_m2;

  // 3. Contacts: closed when the predicted end-of-step gap is <= 0; geometry at the midpoint.
  ContactProblem cp;
  cp.delassus.setZero();
  cp.free_velocity.setZero();
  cp.pre_velocity.setZero();
  cp.restitution = o_.restitution;
  std::array<std::array<double, 2>, 2> nrm{}, tng{};
  bool need_solve = false;
  const bool compliant_law = compliant();
  CompliantContactProblem ccp;
  for (size_t b = 0; b < 2; ++b) {
    const auto& a = p_.aux[b];
    const ModeVec& bb = rows_.aux[b];
    // The rotor centre at this aux plane now (relative to the bearing centre) and its velocity;
    // the predicted end and midpoint follow from them (q is advanced by h u below).
    const double x0 = bb.dot(s.q.head(m)) - a.centre_offset_x_m, y0 = bb.dot(s.q.tail(m)) - a.centre_offset_y_m;
    const double vx = bb.dot(s.u.head(m)), vy = bb.dot(s.u.tail(m));
    const double xe = x0 + h * vx, ye = y0 + h * vy;
    cp.active[b] = radius(xe, ye) >= a.clearance_m;
    if (compliant_law) {
      // Penetration now and at the predicted step end; the spring linearised about d_lin.
      const double d0 = radius(x0, y0) - a.clearance_m, d_end = radius(xe, ye) - a.clearance_m;
      cp.active[b] = d0 > 0.0 || d_end > 0.0;
      const double d_lin = std::max({d0, 0.5 * (d0 + d_end), 0.0});
      const double f_lin = contact_force_n(b, d_lin);
      const double k_t = law_exp_ == 1.0 ? law_k_[b] : (d_lin > 0.0 ? law_exp_ * f_lin / d_lin : 0.0);
      ccp.force0_n[b] = f_lin + k_t * (d0 - d_lin);
      ccp.force_rate_n_s_m[b] = 0.5 * h * k_t + a.contact_damping_n_s_per_m + o_.hunt_crossley_s_per_m * f_lin;
    }
    double xm = x0 + 0.5 * h * vx, ym = y0 + 0.5 * h * vy;
    double r = radius(xm, ym);
    if (r < 1e-12) {
      xm = xe;
      ym = ye;
      r = radius(xm, ym);
    }
    nrm[b] = r > 1e-12 ? std::array<double, 2>{xm / r, ym / r} : std::array<double, 2>{0.0, -1.0};
    tng[b] = {-nrm[b][1], nrm[b][0]};
    const double fvx = bb.dot(u_free.head(m)), fvy = bb.dot(u_free.tail(m));
    const int n = 2 * static_cast<int>(b), t = n + 1, d = 4 + static_cast<int>(b);
    cp.pre_velocity(n) = -(nrm[b][0] * vx + nrm[b][1] * vy);
    cp.pre_velocity(t) = tng[b][0] * vx + tng[b][1] * vy + a.collar_radius_m * s.spin_rad_s - ring_radius_m_[b] * s.ring_rad_s[b];
    cp.pre_velocity(d) = s.ring_rad_s[b];
    cp.free_velocity(n) = -(nrm[b][0] * fvx + nrm[b][1] * fvy);
    cp.free_velocity(t) = tng[b][0] * fvx + tng[b][1] * fvy + a.collar_radius_m * spin_free - ring_radius_m_[b] * s.ring_rad_s[b];
    cp.free_velocity(d) = s.ring_rad_s[b];
    cp.friction_coefficient[b] = a.friction_coefficient;
    cp.drag_bound_n_m_s[b] = a.ring_friction_torque_n_m * h;
    need_solve = need_solve || cp.active[b] || s.ring_rad_s[b] != 0.0;
  }

  LocalVec impulse = LocalVec::Zero();
  LocalVec post = cp.free_velocity;
  if (need_solve) {
    // Delassus W^T A^-1 W: lateral part from B^T A^-1 B and the contact directions
    // (normal rows push along -n, friction rows along t), plus spin and ring inertia.
    std::array<std::array<double, 2>, 4> dir{};
    for (int i = 0; i < 4; ++i) {
      const size_t b = static_cast<size_t>(i / 2);
      dir[static_cast<size_t>(i)] = (i % 2 == 0) ? std::array<double, 2>{-nrm[b][0], -nrm[b][1]} : tng[b];
    }
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) {
        double v = 0.0;
        for (int a = 0; a < 2; ++a)
          for (int c = 0; c < 2; ++c)
            v += dir[static_cast<size_t>(i)][static_cast<size_t>(a)] * M.s_aux(2 * (i / 2) + a, 2 * (j / 2) + c) *
                 dir[static_cast<size_t>(j)][static_cast<size_t>(c)];
        cp.delassus(i, j) = v;
      }
    for (int i = 1; i < 4; i += 2)
      for (int j = 1; j < 4; j += 2)
        cp.delassus(i, j) += p_.aux[static_cast<size_t>(i / 2)].collar_radius_m *
                             p_.aux[static_cast<size_t>(j / 2)].collar_radius_m / rows_.spin_inertia_kg_m2;
    for (size_t b = 0; b < 2; ++b) {
      const int t = 2 * static_cast<int>(b) + 1, d = 4 + static_cast<int>(b);
      const double jr = p_.aux[b].ring_inertia_kg_m2, rr = ring_radius_m_[b];
      cp.delassus(t, t) += rr * rr / jr;
      cp.delassus(t, d) = -rr / jr;
      cp.delassus(d, t) = -rr / jr;
      cp.delassus(d, d) = 1.0 / jr;
    }
    if ((cp.active[0] || cp.active[1]) && compliant_law) {
      ccp.delassus = cp.delassus;
      ccp.free_velocity = cp.free_velocity;
      ccp.pre_velocity = cp.pre_velocity;
      ccp.active = cp.active;
      ccp.friction_coefficient = cp.friction_coefficient;
      ccp.drag_bound_n_m_s = cp.drag_bound_n_m_s;
      ccp.step_s = h;
      ccp.slip_regularisation_m_s = o_.slip_regularisation_m_s;
      const ContactSolution sol = solve_compliant_contacts(ccp, solver_, s.warm_impulse);
      impulse = sol.impulse;
      post = sol.post_velocity;
      counters_.solver_max_sweeps = std::max(counters_.solver_max_sweeps, sol.iterations);
      if (!sol.converged) ++counters_.solver_unconverged;
    } else if (cp.active[0] || cp.active[1]) {
      const ContactSolution sol = solve_contacts(cp, solver_, s.warm_impulse);
      impulse = sol.impulse;
      post = sol.post_velocity;
      counters_.solver_max_sweeps = std::max(counters_.solver_max_sweeps, sol.iterations);
      if (!sol.converged) ++counters_.solver_unconverged;
    } else {
      // Only the ring drags (both contacts open): two decoupled 1-D problems, solved exactly
      // by the PGS's own update from zero (zero of the step-average ring speed, clamped to
      // the drag bound). Most steps after a drop are of this kind (rings spinning, rotor in
      // flight); the PGS would need two full sweeps to find the same value.
      for (int k = 0; k < 2; ++k) {
        const int d = 4 + k;
        const double bound = cp.drag_bound_n_m_s[static_cast<size_t>(k)];
        impulse(d) = std::clamp(-(cp.free_velocity(d) + cp.pre_velocity(d)) / cp.delassus(d, d), -bound, bound);
      }
      post = cp.free_velocity + cp.delassus * impulse;
    }
  }
  s.warm_impulse = impulse;

  // 4. Velocity update with the impulses, then positions (midpoint).
  Eigen::Vector4d coef;
  for (size_t b = 0; b < 2; ++b)
    for (size_t a = 0; a < 2; ++a)
      coef(static_cast<int>(2 * b + a)) = -nrm[b][a] * impulse(static_cast<int>(2 * b)) + tng[b][a] * impulse(static_cast<int>(2 * b + 1));
  LatVec u_new = u_free;
  u_new.noalias() += M.z * coef;
  double spin_new = spin_free;
  std::array<double, 2> ring_new{};
  for (size_t b = 0; b < 2; ++b) {
    spin_new += p_.aux[b].collar_radius_m * impulse(static_cast<int>(2 * b + 1)) / rows_.spin_inertia_kg_m2;
    ring_new[b] = s.ring_rad_s[b] + (-ring_radius_m_[b] * impulse(static_cast<int>(2 * b + 1)) + impulse(static_cast<int>(4 + b))) /
                                        p_.aux[b].ring_inertia_kg_m2;
  }

  // Energy ledger: every term is the exact work on the step-average velocity.
  LatVec u_avg = 0.5 * (s.u + u_new);
  const double spin_avg = 0.5 * (s.spin_rad_s + spin_new);
  EnergyLedger& L = s.ledger;
  L.damping_dissipated_j += h * (rows_.damp.dot(u_avg.head(m).cwiseAbs2()) + rows_.damp.dot(u_avg.tail(m).cwiseAbs2()));
  L.external_work_j += h * (fx.dot(u_avg.head(m)) + fy.dot(u_avg.tail(m)) + drive * spin_avg);
  double step_diss = 0.0;
  StepContact& rec = s.last_contact;
  for (size_t b = 0; b < 2; ++b) {
    const int n = 2 * static_cast<int>(b), t = n + 1, d = 4 + static_cast<int>(b);
    const double wn = -impulse(n) * 0.5 * (cp.pre_velocity(n) + post(n));
    const double wt = -impulse(t) * 0.5 * (cp.pre_velocity(t) + post(t));
    const double wd = -impulse(d) * 0.5 * (cp.pre_velocity(d) + post(d));
    L.impact_dissipated_j += wn;
    L.friction_dissipated_j += wt;
    L.ring_drag_dissipated_j += wd;
    step_diss += wn + wt + wd;
    rec.active[b] = cp.active[b];
    rec.normal_n[b] = impulse(n) / h;
    rec.friction_n[b] = impulse(t) / h;
    double ang = std::atan2(nrm[b][0], nrm[b][1]) * 180.0 / M_PI;
    rec.angle_deg[b] = ang < 0.0 ? ang + 360.0 : ang;
    rec.slip_m_s[b] = 0.5 * (cp.pre_velocity(t) + post(t));
    rec.friction_power_w[b] = wt / h;
  }
  L.min_step_contact_dissipation_j = std::min(L.min_step_contact_dissipation_j, step_diss);

  s.q += h * u_avg;
  s.u = u_new;
  s.spin_angle_rad = std::fmod(s.spin_angle_rad + h * spin_avg, k_two_pi);
  s.spin_accel_rad_s2 = (spin_new - s.spin_rad_s) / h;
  s.spin_rad_s = spin_new;
  for (size_t b = 0; b < 2; ++b) {
    s.ring_angle_rad[b] = std::fmod(s.ring_angle_rad[b] + 0.5 * h * (s.ring_rad_s[b] + ring_new[b]), k_two_pi);
    s.ring_rad_s[b] = ring_new[b];
  }
  s.t_s += h;
  rec.t_s = s.t_s;
  rec.h_s = h;

  bool any = false;
  std::array<double, 2> pen_end{};  // penetration at the step end per bearing, m
  for (size_t b = 0; b < 2; ++b) {
    any = any || cp.active[b];
    const auto p = aux_position_m(static_cast<int>(b));
    pen_end[b] = radius(p[0] - p_.aux[b].centre_offset_x_m, p[1] - p_.aux[b].centre_offset_y_m) - p_.aux[b].clearance_m;
    counters_.max_penetration_m = std::max(counters_.max_penetration_m, pen_end[b]);
  }
  if (any) ++counters_.contact_steps;
  if (compliant_law) {
    // The normal impulses' work went partly into the contact springs: book only the rest
    // (damping and the linearisation's residue) as impact dissipation.
    for (size_t b = 0; b < 2; ++b) {
      const double e_new = contact_energy_at(b, pen_end[b]);
      L.impact_dissipated_j -= e_new - s.contact_energy_j[b];
      s.contact_energy_j[b] = e_new;
    }
  } else if (o_.position_projection) {
    project_positions(cp.active);
  }

  for (size_t k = 0; k < 4; ++k) {
    const double meas = rows_.sensor_dir[k][0] * rows_.sensor[k].dot(s.q.head(m)) + rows_.sensor_dir[k][1] * rows_.sensor[k].dot(s.q.tail(m));
    s.sensor_filtered_m[k] += M.sensor_alpha[k] * (meas - s.sensor_filtered_m[k]);
  }
  if (observer_ != nullptr) observer_->on_step(rec);
}

void DropModel::project_positions(const std::array<bool, 2>& closed) {
  // Minimal-norm displacement dq = H^-1 sum_b lambda_b v_b, v_b = n_b (x) b_aux_b, with
  // v_b^T dq = -penetration_b for every closed, penetrating contact. Metric
  // H = I + h^2/4 K (the step's own): the stiff modes, whose elastic energy a mass-norm
  // projection would disturb most, move least.
  std::array<double, 2> pen{};
  std::array<std::array<double, 2>, 2> n{};
  int count = 0;
  for (size_t b = 0; b < 2; ++b) {
    if (!closed[b]) continue;
    const auto p = aux_position_m(static_cast<int>(b));
    const double dx = p[0] - p_.aux[b].centre_offset_x_m, dy = p[1] - p_.aux[b].centre_offset_y_m;
    const double r = radius(dx, dy);
    if (r > p_.aux[b].clearance_m && r > 0.0) {
      pen[b] = r - p_.aux[b].clearance_m;
      n[b] = {dx / r, dy / r};
      ++count;
    }
  }
  if (count == 0) return;
  const double e_before = mechanical_energy_j();
  const ModeVec hm = (1.0 + 0.25 * o_.step_s * o_.step_s * rows_.w2.array()).matrix();
  Eigen::Matrix2d g = Eigen::Matrix2d::Identity();
  Eigen::Vector2d rhs = Eigen::Vector2d::Zero();
  for (size_t b = 0; b < 2; ++b) {
    if (pen[b] == 0.0) continue;
    for (size_t c = 0; c < 2; ++c) {
      if (pen[c] == 0.0) continue;
      g(static_cast<int>(b), static_cast<int>(c)) = (n[b][0] * n[c][0] + n[b][1] * n[c][1]) * rows_.aux[b].dot(rows_.aux[c].cwiseQuotient(hm));
    }
    rhs(static_cast<int>(b)) = -pen[b];
  }
  const Eigen::Vector2d lambda = g.ldlt().solve(rhs);
  for (size_t b = 0; b < 2; ++b) {
    if (pen[b] == 0.0) continue;
    s_.q.head(m_) += lambda(static_cast<int>(b)) * n[b][0] * rows_.aux[b].cwiseQuotient(hm);
    s_.q.tail(m_) += lambda(static_cast<int>(b)) * n[b][1] * rows_.aux[b].cwiseQuotient(hm);
  }
  s_.ledger.projection_energy_j += mechanical_energy_j() - e_before;
}

std::array<double, 2> DropModel::aux_position_m(int bearing) const {
  const ModeVec& b = rows_.aux[static_cast<size_t>(bearing)];
  return {b.dot(s_.q.head(m_)), b.dot(s_.q.tail(m_))};
}

std::array<double, 2> DropModel::displacement_at(double axial_m) const {
  const Eigen::RowVectorXd b = rig_->modal_row(red_, axial_m);
  double x = 0.0, y = 0.0;
  for (int i = 0; i < m_; ++i) {
    x += b(i) * s_.q(i);
    y += b(i) * s_.q(m_ + i);
  }
  return {x, y};
}

double DropModel::mechanical_energy_j() const {
  double e = 0.5 * s_.u.squaredNorm() + 0.5 * rows_.spin_inertia_kg_m2 * s_.spin_rad_s * s_.spin_rad_s;
  e += 0.5 * (rows_.w2.dot(s_.q.head(m_).cwiseAbs2()) + rows_.w2.dot(s_.q.tail(m_).cwiseAbs2()));
  e -= rows_.gravity_y.dot(s_.q.tail(m_));
  for (size_t b = 0; b < 2; ++b) e += 0.5 * p_.aux[b].ring_inertia_kg_m2 * s_.ring_rad_s[b] * s_.ring_rad_s[b];
  if (compliant()) e += s_.contact_energy_j[0] + s_.contact_energy_j[1];
  return e;
}

PlantOutputs DropModel::outputs() const {
  PlantOutputs o;
  o.t_s = s_.t_s;
  o.displacement_m = s_.sensor_out_m;
  o.coil_current_a = s_.current_a;
  o.spin_speed_hz = s_.spin_rad_s / k_two_pi;
  o.spin_angle_rad = s_.spin_angle_rad;
  return o;
}

PlantTruth DropModel::truth() const {
  PlantTruth t;
  for (size_t b = 0; b < 2; ++b) {
    const auto p = aux_position_m(static_cast<int>(b));
    t.aux_x_m[b] = p[0];
    t.aux_y_m[b] = p[1];
    t.contact_force_n[b] = s_.last_contact.normal_n[b];
    t.friction_force_n[b] = s_.last_contact.friction_n[b];
    t.ring_speed_rad_s[b] = s_.ring_rad_s[b];
    t.amb_x_m[b] = rows_.amb[b].dot(s_.q.head(m_));
    t.amb_y_m[b] = rows_.amb[b].dot(s_.q.tail(m_));
  }
  t.amb_force_n = s_.amb_force_n;
  double ke = 0.5 * s_.u.squaredNorm() + 0.5 * rows_.spin_inertia_kg_m2 * s_.spin_rad_s * s_.spin_rad_s;
  for (size_t b = 0; b < 2; ++b) ke += 0.5 * p_.aux[b].ring_inertia_kg_m2 * s_.ring_rad_s[b] * s_.ring_rad_s[b];
  t.kinetic_energy_j = ke;
  t.potential_energy_j = mechanical_energy_j() - ke;
  t.friction_dissipated_j = s_.ledger.friction_dissipated_j;
  return t;
}

}  // namespace amb::model::drop
