#include "model/analysis/closed_loop.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <unsupported/Eigen/MatrixFunctions>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "model/amb/amb_force.hpp"
#include "model/rotor/modal_reduction.hpp"
#include "model/rotor/rotor_model.hpp"

namespace amb::model::analysis {
namespace {

// unit(i): the row vector of length `size` with a one at i (a state picked out of a row space).
struct UnitRows {
  int size = 0;
  Eigen::RowVectorXd operator()(int i) const {
    Eigen::RowVectorXd u = Eigen::RowVectorXd::Zero(size);
    u(i) = 1.0;
    return u;
  }
};

constexpr double k_two_pi = 2.0 * M_PI;
// Bandwidths given as 0 ("none") are modelled as this fast first-order lag so that every
// block stays strictly proper and the state space has no algebraic loops.
constexpr double k_fast_hz = 1e5;
constexpr double k_max_delay_periods = 8.0;

double rad_s(double hz) { return k_two_pi * (hz > 0.0 ? hz : k_fast_hz); }

// Inverse of a 2x2 matrix [[a, b], [c, d]].
Eigen::Matrix2d inverse2(double a, double b, double c, double d) {
  Eigen::Matrix2d m;
  m << a, b, c, d;
  return m.inverse();
}

// The rig without its controller: rotor modal states, sensor roll-off, amplifiers.
// dx/dt = a x + b i_demand (4 actuator axes); the sensor readings are the states `sensor`.
struct RigBlock {
  Eigen::MatrixXd a, b;
  std::array<int, 4> sensor{};
  int modes = 0;
};

RigBlock build_rig(const RigModel& rig_model, const PlantParams& rig, int modes_per_plane, double spin_hz) {
  const rotor::RotorModel& fe = rig_model.rotor();
  const int keep = modes_per_plane < 0 ? rig.rotor.modes_kept : modes_per_plane;
  const rotor::ReducedRotor red = rotor::truncate_basis(rig_model.modal_basis(), fe, keep);
  const int m = red.modes;
  RigBlock r;
  r.modes = m;

  // State layout: rotor first (the participation shares in modes() rely on it).
  int n = 0;
  const int ex = n, ey = n + m, vx = n + 2 * m, vy = n + 3 * m;
  n += 4 * m;
  for (int k = 0; k < 4; ++k) r.sensor[static_cast<size_t>(k)] = n++;
  std::array<int, 4> amp{};
  for (int j = 0; j < 4; ++j) amp[static_cast<size_t>(j)] = n++;
  r.a = Eigen::MatrixXd::Zero(n, n);
  r.b = Eigen::MatrixXd::Zero(n, 4);

  using Row = Eigen::RowVectorXd;
  const UnitRows unit{n};
  auto disp_rows = [&](double axial_m, Row& rx, Row& ry) {
    const Eigen::RowVectorXd b = rotor::modal_interpolation(fe, red, axial_m);
    rx = Row::Zero(n);
    ry = Row::Zero(n);
    rx.segment(ex, m) = b;
    ry.segment(ey, m) = b;
  };

  r.a.block(ex, vx, m, m).setIdentity();
  r.a.block(ey, vy, m, m).setIdentity();

  // Sensors: true reading along the sensor axis, first-order roll-off.
  for (size_t k = 0; k < 4; ++k) {
    Row rx, ry;
    disp_rows(rig.sensor[k].axial_m, rx, ry);
    const auto d = magnet::axis_direction(rig.sensor[k].angle_deg);
    const double ws = rad_s(rig.sensor[k].bandwidth_hz);
    r.a.row(r.sensor[k]) = ws * (d[0] * rx + d[1] * ry - unit(r.sensor[k]));
  }

  // Amplifiers: first-order lag from the demand to the coil current.
  for (size_t j = 0; j < 4; ++j) {
    const double wa = rad_s(rig.amb[j / 2].amplifier_bandwidth_hz);
    r.a(amp[j], amp[j]) = -wa;
    r.b(amp[j], static_cast<Eigen::Index>(j)) = wa;
  }

  // Rotor dynamics: modal stiffness, damping, gyroscopics, AMB forces.
  const double spin = k_two_pi * spin_hz;
  for (int i = 0; i < m; ++i) {
    r.a(vx + i, ex + i) = -red.omega2(i);
    r.a(vy + i, ey + i) = -red.omega2(i);
    r.a(vx + i, vx + i) = -red.damping(i);
    r.a(vy + i, vy + i) = -red.damping(i);
  }
  r.a.block(vx, vy, m, m) += -spin * red.polar;
  r.a.block(vy, vx, m, m) += spin * red.polar;
  for (size_t b = 0; b < 2; ++b) {
    const Eigen::RowVectorXd bb = rotor::modal_interpolation(fe, red, rig.amb[b].axial_m);
    Row rx, ry;
    disp_rows(rig.amb[b].axial_m, rx, ry);
    for (size_t a = 0; a < 2; ++a) {
      const size_t j = 2 * b + a;
      const auto u = magnet::axis_direction(rig.amb[b].actuator_angle_deg[a]);
      const Row force = rig.amb[b].ks_n_per_m * (u[0] * rx + u[1] * ry) + rig.amb[b].ki_n_per_a * unit(amp[j]);
      r.a.block(vx, 0, m, n) += u[0] * bb.transpose() * force;
      r.a.block(vy, 0, m, n) += u[1] * bb.transpose() * force;
    }
  }
  return r;
}

// The controller from the 4 sensor readings y to the 4 current demands:
//   continuous: dxc/dt = ac xc + bc y;  sampled: xc[k+1] = ac xc[k] + bc y[k];  i = cc xc + dc y.
struct ControllerBlock {
  Eigen::MatrixXd ac, bc, cc, dc;
};

// One direction (x or y) of one plane, SISO from the error e to the force F. Rows are over
// [channel states, e]: `next` gives the derivative (continuous) or the next value (sampled).
struct Channel {
  int n = 0;
  Eigen::MatrixXd next;   // n x (n + 1)
  Eigen::RowVectorXd out; // 1 x (n + 1)
};

Channel continuous_channel(const PidParams& pid) {
  Channel c;
  const bool lead = pid.lead_zero_hz > 0.0;
  c.n = 2 + 2 * pid.notch_count + (lead ? 1 : 0);  // integral, derivative filter, (z1, z2) per notch, lead
  const int n = c.n, e = n;
  c.next = Eigen::MatrixXd::Zero(n, n + 1);
  using Row = Eigen::RowVectorXd;
  const UnitRows unit{n + 1};
  const int integ = 0, dfilt = 1;
  const double wf = rad_s(pid.derivative_filter_hz);
  c.next.row(integ) = unit(e);
  c.next.row(dfilt) = wf * (unit(e) - unit(dfilt));
  Row u = -(pid.kp_n_per_m * unit(e) + pid.ki_n_per_m_s * unit(integ) + pid.kd_n_s_per_m * wf * (unit(e) - unit(dfilt)));
  for (int k = 0; k < pid.notch_count; ++k) {
    // (s^2 + depth BW s + w0^2) / (s^2 + BW s + w0^2) = 1 + (depth - 1) BW s / (s^2 + BW s + w0^2)
    const NotchParams& nt = pid.notches[static_cast<size_t>(k)];
    const double w0 = k_two_pi * nt.centre_hz, bw = k_two_pi * nt.width_hz;
    const int z1 = 2 + 2 * k, z2 = z1 + 1;
    c.next.row(z1) = unit(z2);
    c.next.row(z2) = u - w0 * w0 * unit(z1) - bw * unit(z2);
    u = u + (nt.depth * bw - bw) * unit(z2);
  }
  if (lead) {
    // (1 + s/wz) / (1 + s/wp) = wp/wz + (1 - wp/wz) / (1 + s/wp): state l' = wp (u - l).
    const double wz = k_two_pi * pid.lead_zero_hz, wp = k_two_pi * pid.lead_pole_hz;
    const int l = n - 1;
    c.next.row(l) = wp * (u - unit(l));
    u = (wp / wz) * u + (1.0 - wp / wz) * unit(l);
  }
  c.out = u;
  return c;
}

// The firmware's PidAxis::step, linear part, term by term (firmware/control/pid_axis.cpp):
//   deriv = alpha deriv + (1 - alpha) (e - e_prev) / T;  u = -(KP e + I + KD deriv);
//   e_prev = e;  I += KI e T;  each notch: direct form I biquad, Tustin with the centre pre-warped.
Channel sampled_channel(const PidParams& pid, double t_s) {
  Channel c;
  const bool lead = pid.lead_zero_hz > 0.0;
  c.n = 3 + 4 * pid.notch_count + (lead ? 2 : 0);  // e_prev, deriv, integral, (x1, x2, y1, y2) per notch, lead (x1, y1)
  const int n = c.n, e = n;
  c.next = Eigen::MatrixXd::Zero(n, n + 1);
  using Row = Eigen::RowVectorXd;
  const UnitRows unit{n + 1};
  const int e_prev = 0, deriv = 1, integ = 2;
  const double alpha = std::exp(-k_two_pi * pid.derivative_filter_hz * t_s);
  const Row deriv_new = alpha * unit(deriv) + (1.0 - alpha) / t_s * (unit(e) - unit(e_prev));
  c.next.row(e_prev) = unit(e);
  c.next.row(deriv) = deriv_new;
  c.next.row(integ) = unit(integ) + pid.ki_n_per_m_s * t_s * unit(e);
  Row u = -(pid.kp_n_per_m * unit(e) + unit(integ) + pid.kd_n_s_per_m * deriv_new);
  for (int k = 0; k < pid.notch_count; ++k) {
    // Same design as fw::design_notch (checked against it in tests/plant/closed_loop_test).
    const NotchParams& nt = pid.notches[static_cast<size_t>(k)];
    const double w0 = k_two_pi * nt.centre_hz;
    const double kk = w0 / std::tan(w0 * t_s / 2.0);
    const double zeta = nt.width_hz / (2.0 * nt.centre_hz);
    const double k2 = kk * kk, w2 = w0 * w0;
    const double nb1 = 2.0 * nt.depth * zeta * w0 * kk, da1 = 2.0 * zeta * w0 * kk;
    const double a0 = k2 + da1 + w2;
    const double b0 = (k2 + nb1 + w2) / a0, b1 = 2.0 * (w2 - k2) / a0, b2 = (k2 - nb1 + w2) / a0;
    const double a1 = 2.0 * (w2 - k2) / a0, a2 = (k2 - da1 + w2) / a0;
    const int x1 = 3 + 4 * k, x2 = x1 + 1, y1 = x1 + 2, y2 = x1 + 3;
    const Row y = b0 * u + b1 * unit(x1) + b2 * unit(x2) - a1 * unit(y1) - a2 * unit(y2);
    c.next.row(x2) = unit(x1);
    c.next.row(x1) = u;
    c.next.row(y2) = unit(y1);
    c.next.row(y1) = y;
    u = y;
  }
  if (lead) {
    // Same design as the firmware's (Tustin): y = b0 x + b1 x1 - a1 y1.
    const double cz = 2.0 / (t_s * k_two_pi * pid.lead_zero_hz), cp = 2.0 / (t_s * k_two_pi * pid.lead_pole_hz);
    const double b0 = (1.0 + cz) / (1.0 + cp), b1 = (1.0 - cz) / (1.0 + cp), a1 = (1.0 - cp) / (1.0 + cp);
    const int x1 = n - 2, y1 = n - 1;
    const Row y = b0 * u + b1 * unit(x1) - a1 * unit(y1);
    c.next.row(x1) = u;
    c.next.row(y1) = y;
    u = y;
  }
  c.out = u;
  return c;
}

ControllerBlock build_controller(const PlantParams& rig, const PidParams& pid, double t_s) {
  const Channel ch = t_s > 0.0 ? sampled_channel(pid, t_s) : continuous_channel(pid);
  const int nc = ch.n;
  ControllerBlock k;
  k.ac = Eigen::MatrixXd::Zero(4 * nc, 4 * nc);
  k.bc = Eigen::MatrixXd::Zero(4 * nc, 4);
  k.cc = Eigen::MatrixXd::Zero(4, 4 * nc);
  k.dc = Eigen::MatrixXd::Zero(4, 4);
  for (int b = 0; b < 2; ++b) {
    // Sensors -> (x, y) (AxisTransform::sensors_to_xy), PID per direction, (Fx, Fy) ->
    // actuator axes (xy_to_actuators), current = force / ki.
    const auto s1 = magnet::axis_direction(rig.sensor[static_cast<size_t>(2 * b)].angle_deg);
    const auto s2 = magnet::axis_direction(rig.sensor[static_cast<size_t>(2 * b + 1)].angle_deg);
    const Eigen::Matrix2d s_inv = inverse2(s1[0], s1[1], s2[0], s2[1]);
    const auto& amb = rig.amb[static_cast<size_t>(b)];
    const auto u1 = magnet::axis_direction(amb.actuator_angle_deg[0]);
    const auto u2 = magnet::axis_direction(amb.actuator_angle_deg[1]);
    const Eigen::Matrix2d u_inv = inverse2(u1[0], u2[0], u1[1], u2[1]);
    for (int d = 0; d < 2; ++d) {
      const int c0 = (2 * b + d) * nc;
      // e = s_inv(d, :) . (y_2b, y_2b+1)
      Eigen::RowVector4d e_of_y = Eigen::RowVector4d::Zero();
      e_of_y(2 * b) = s_inv(d, 0);
      e_of_y(2 * b + 1) = s_inv(d, 1);
      k.ac.block(c0, c0, nc, nc) = ch.next.leftCols(nc);
      k.bc.block(c0, 0, nc, 4) = ch.next.col(nc) * e_of_y;
      for (int a = 0; a < 2; ++a) {
        const double g = u_inv(a, d) / amb.ki_n_per_a;  // current on axis a per unit force in direction d
        k.cc.block(2 * b + a, c0, 1, nc) += g * ch.out.head(nc);
        k.dc.row(2 * b + a) += g * ch.out(nc) * e_of_y;
      }
    }
  }
  return k;
}

}  // namespace

IsoZone iso14839_zone(double peak) {
  if (peak < 3.0) return IsoZone::A;
  if (peak < 4.0) return IsoZone::B;
  if (peak < 5.0) return IsoZone::C;
  return IsoZone::D;
}

const char* to_string(IsoZone z) {
  switch (z) {
    case IsoZone::A: return "A";
    case IsoZone::B: return "B";
    case IsoZone::C: return "C";
    default: return "D";
  }
}

ClosedLoopModel::ClosedLoopModel(const PlantParams& rig, const PidParams& pid, const ClosedLoopOptions& o)
    : ClosedLoopModel(RigModel(rig), rig, pid, o) {}

ClosedLoopModel::ClosedLoopModel(const RigModel& rig_model, const PlantParams& rig, const PidParams& pid,
                                 const ClosedLoopOptions& o) {
  rig_model.check_same_rig(rig, "closed loop");
  if (!(o.sample_rate_hz >= 0.0) || !std::isfinite(o.sample_rate_hz))
    throw std::invalid_argument("closed loop: sample_rate_hz must be >= 0 (0: continuous), got " +
                                std::to_string(o.sample_rate_hz));
  if (!(o.loop_delay_periods >= 0.0 && o.loop_delay_periods <= k_max_delay_periods))
    throw std::invalid_argument("closed loop: loop_delay_periods must be in [0, 8], got " +
                                std::to_string(o.loop_delay_periods));
  if (o.sample_rate_hz == 0.0 && o.loop_delay_periods > 0.0)
    throw std::invalid_argument("closed loop: loop_delay_periods needs the sampled loop (sample_rate_hz > 0)");
  const RigBlock p = build_rig(rig_model, rig, o.modes_per_plane, o.spin_hz);
  modes_ = p.modes;
  period_s_ = o.sample_rate_hz > 0.0 ? 1.0 / o.sample_rate_hz : 0.0;
  const ControllerBlock k = build_controller(rig, pid, period_s_);
  const int np = static_cast<int>(p.a.rows()), nc = static_cast<int>(k.ac.rows());
  Eigen::MatrixXd cy = Eigen::MatrixXd::Zero(4, np);  // sensor readings from the rig states
  for (int s = 0; s < 4; ++s) cy(s, p.sensor[static_cast<size_t>(s)]) = 1.0;
  c_sensor_ = Eigen::MatrixXd::Zero(4, np + nc);  // widened below when the sampled loop adds demand memory
  c_sensor_.leftCols(np) = cy;

  if (period_s_ == 0.0) {
    // x = [rig; controller]; i = cmd + d.
    const int n = np + nc;
    a_ = Eigen::MatrixXd::Zero(n, n);
    a_.topLeftCorner(np, np) = p.a + p.b * k.dc * cy;
    a_.topRightCorner(np, nc) = p.b * k.cc;
    a_.bottomLeftCorner(nc, np) = k.bc * cy;
    a_.bottomRightCorner(nc, nc) = k.ac;
    group_.resize(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) group_[static_cast<size_t>(i)] = i;
    groups_ = n;
    rotor_groups_ = 4 * modes_;
    b_inj_.assign(4, Eigen::VectorXd::Zero(n));
    c_cmd_.assign(4, Eigen::RowVectorXd::Zero(n));
    for (int j = 0; j < 4; ++j) {
      b_inj_[static_cast<size_t>(j)].head(np) = p.b.col(j);
      c_cmd_[static_cast<size_t>(j)].head(np) = k.dc.row(j) * cy;
      c_cmd_[static_cast<size_t>(j)].tail(nc) = k.cc.row(j);
    }
    return;
  }

  // Sampled: demand i[k] computed from the sample y[k] at t_k = k T is applied from
  // t_k + (q + f) T on (q whole periods, 0 <= f < 1). Over [t_k, t_k+1) the rig is driven by
  // i[k-q-1] on the first f T and by i[k-q] on the rest:
  //   x[k+1] = Phi(T) x[k] + Phi((1-f) T) Gamma(f T) i[k-q-1] + Gamma((1-f) T) i[k-q],
  // Phi(t) = exp(A t), Gamma(t) = int_0^t exp(A s) ds B, both from one exponential of the
  // augmented matrix [[A, B], [0, 0]] t. Past demands are states m_1 = i[k-1] .. m_L.
  const double t = period_s_;
  const int q = static_cast<int>(std::floor(o.loop_delay_periods + 1e-12));
  const double f = std::max(0.0, o.loop_delay_periods - q);
  const bool split = f > 1e-12;
  auto phi_gamma = [&](double dt, Eigen::MatrixXd& phi, Eigen::MatrixXd& gamma) {
    Eigen::MatrixXd aug = Eigen::MatrixXd::Zero(np + 4, np + 4);
    aug.topLeftCorner(np, np) = p.a * dt;
    aug.topRightCorner(np, 4) = p.b * dt;
    const Eigen::MatrixXd e = aug.exp();
    phi = e.topLeftCorner(np, np);
    gamma = e.topRightCorner(np, 4);
  };
  Eigen::MatrixXd phi_t, gamma_t, phi_late, gamma_late, phi_early, gamma_early;
  phi_gamma(t, phi_t, gamma_t);
  Eigen::MatrixXd g_new = gamma_t, g_old;  // multiply i[k-q] and i[k-q-1]
  if (split) {
    phi_gamma((1.0 - f) * t, phi_late, gamma_late);
    phi_gamma(f * t, phi_early, gamma_early);
    g_new = gamma_late;
    g_old = phi_late * gamma_early;
  }
  const int mem = q + (split ? 1 : 0);
  const int n = np + nc + 4 * mem;
  const int m0 = np + nc;  // m_i at m0 + 4 (i - 1)
  Eigen::MatrixXd fmat = Eigen::MatrixXd::Zero(n, n);  // next state without the present demand
  Eigen::MatrixXd g = Eigen::MatrixXd::Zero(n, 4);     // next state per unit present demand
  fmat.topLeftCorner(np, np) = phi_t;
  fmat.block(np, 0, nc, np) = k.bc * cy;
  fmat.block(np, np, nc, nc) = k.ac;
  if (q == 0)
    g.topRows(np) = g_new;
  else
    fmat.block(0, m0 + 4 * (q - 1), np, 4) = g_new;
  if (split) fmat.block(0, m0 + 4 * q, np, 4) = g_old;
  if (mem > 0) g.block(m0, 0, 4, 4).setIdentity();
  for (int i = 1; i < mem; ++i) fmat.block(m0 + 4 * i, m0 + 4 * (i - 1), 4, 4).setIdentity();
  Eigen::MatrixXd cmd = Eigen::MatrixXd::Zero(4, n);  // i[k] = cmd x[k] + d[k]
  cmd.leftCols(np) = k.dc * cy;
  cmd.block(0, np, 4, nc) = k.cc;
  a_ = fmat + g * cmd;
  // Participation groups (see modes()): rotor (x, y) coordinate pairs, then per plane its
  // sensors, amplifiers, controller and past demands.
  group_.resize(static_cast<size_t>(n));
  const int mr = p.modes;
  for (int i = 0; i < 4 * mr; ++i) group_[static_cast<size_t>(i)] = (i / (2 * mr)) * mr + i % mr;
  rotor_groups_ = 2 * mr;
  for (int s = 0; s < 4; ++s) group_[static_cast<size_t>(p.sensor[static_cast<size_t>(s)])] = rotor_groups_ + s / 2;
  for (int a = 0; a < 4; ++a) group_[static_cast<size_t>(4 * mr + 4 + a)] = rotor_groups_ + 2 + a / 2;
  for (int i = np; i < m0; ++i) group_[static_cast<size_t>(i)] = rotor_groups_ + 4 + (i - np) / (nc / 2);
  for (int i = m0; i < n; ++i) group_[static_cast<size_t>(i)] = rotor_groups_ + 6 + ((i - m0) % 4) / 2;
  groups_ = rotor_groups_ + 8;
  c_sensor_.conservativeResize(4, n);
  c_sensor_.rightCols(n - np - nc).setZero();
  b_inj_.assign(4, Eigen::VectorXd::Zero(n));
  c_cmd_.assign(4, Eigen::RowVectorXd::Zero(n));
  for (int j = 0; j < 4; ++j) {
    b_inj_[static_cast<size_t>(j)] = g.col(j);
    c_cmd_[static_cast<size_t>(j)] = cmd.row(j);
  }
}

bool ClosedLoopModel::stable() const {
  Eigen::EigenSolver<Eigen::MatrixXd> es(a_, false);
  if (sampled()) return es.eigenvalues().cwiseAbs().maxCoeff() < 1.0;
  return es.eigenvalues().real().maxCoeff() < 0.0;
}

double ClosedLoopModel::spectral_abscissa() const {
  Eigen::EigenSolver<Eigen::MatrixXd> es(a_, false);
  if (sampled()) return std::log(es.eigenvalues().cwiseAbs().maxCoeff()) / period_s_;
  return es.eigenvalues().real().maxCoeff();
}

std::vector<ClosedLoopMode> ClosedLoopModel::modes() const {
  Eigen::EigenSolver<Eigen::MatrixXd> es(a_, true);
  const Eigen::MatrixXcd& v = es.eigenvectors();
  // Participation factors p_ki = |w_ik v_ki| (w: left eigenvectors, rows of V^-1) are
  // independent of the states' units; a mode's rotor share is the part carried by the rotor
  // states (modal displacements and velocities). This separates the mechanical modes from
  // the controller, filter and amplifier modes they couple with. In the sampled loop the x and
  // y modes of a plane are exactly degenerate and the solver returns any mix of them, whose
  // factors cancel between the x and y states; there the factors are summed per group (a
  // rotor mode's x and y coordinates, a plane's sensors, amplifiers, controller, past demands)
  // before taking the magnitude.
  const Eigen::MatrixXcd w = v.partialPivLu().inverse();
  std::vector<ClosedLoopMode> out;
  for (Eigen::Index i = 0; i < es.eigenvalues().size(); ++i) {
    const std::complex<double> z = es.eigenvalues()(i);
    if (z.imag() <= 1e-9 * std::abs(z)) continue;
    if (sampled() && std::abs(z) < 1e-12) continue;  // pure delay (pole at z = 0): no frequency
    const std::complex<double> l = sampled() ? std::log(z) / period_s_ : z;
    std::vector<std::complex<double>> sum(static_cast<size_t>(groups_));
    for (Eigen::Index k = 0; k < v.rows(); ++k) sum[static_cast<size_t>(group_[static_cast<size_t>(k)])] += w(i, k) * v(k, i);
    double rotor = 0.0, total = 0.0;
    for (int g = 0; g < groups_; ++g) {
      const double pg = std::abs(sum[static_cast<size_t>(g)]);
      total += pg;
      if (g < rotor_groups_) rotor += pg;
    }
    ClosedLoopMode mode;
    mode.eigenvalue = l;
    mode.natural_rad_s = std::abs(l);
    mode.damping_ratio = -l.real() / std::abs(l);
    mode.rotor_share = total > 0.0 ? rotor / total : 0.0;
    out.push_back(mode);
  }
  std::sort(out.begin(), out.end(),
            [](const ClosedLoopMode& a, const ClosedLoopMode& b) { return a.natural_rad_s < b.natural_rad_s; });
  return out;
}

std::vector<ClosedLoopMode> ClosedLoopModel::rotor_modes(double min_share, double merge_rel) const {
  std::vector<ClosedLoopMode> out;
  for (const auto& md : modes()) {
    if (md.rotor_share < min_share) continue;
    if (!out.empty() && std::abs(md.natural_rad_s - out.back().natural_rad_s) <= merge_rel * md.natural_rad_s)
      continue;
    out.push_back(md);
  }
  return out;
}

std::complex<double> ClosedLoopModel::sensitivity(int axis, double f_hz) const {
  const auto j = static_cast<size_t>(axis);
  Eigen::MatrixXcd m = -a_.cast<std::complex<double>>();
  // s = j w (continuous) or z = exp(j w T) (sampled).
  const std::complex<double> s(0.0, k_two_pi * f_hz);
  m.diagonal().array() += sampled() ? std::exp(s * period_s_) : s;
  const Eigen::VectorXcd x = m.partialPivLu().solve(b_inj_[j].cast<std::complex<double>>());
  // Injection d at the demand: u = cmd + d, x' = A x + b d  =>  S = u / d = 1 + c (sI - A)^-1 b
  // (sampled: x[k+1] = A x[k] + b d[k]  =>  S = 1 + c (zI - A)^-1 b).
  return 1.0 + (c_cmd_[j].cast<std::complex<double>>() * x)(0);
}

InjectionResponse ClosedLoopModel::injection_response(int axis, double f_hz) const {
  const auto j = static_cast<size_t>(axis);
  Eigen::MatrixXcd m = -a_.cast<std::complex<double>>();
  const std::complex<double> s(0.0, k_two_pi * f_hz);
  m.diagonal().array() += sampled() ? std::exp(s * period_s_) : s;
  const Eigen::VectorXcd x = m.partialPivLu().solve(b_inj_[j].cast<std::complex<double>>());
  InjectionResponse r;
  r.demand = 1.0 + (c_cmd_[j].cast<std::complex<double>>() * x)(0);
  const Eigen::VectorXcd y = c_sensor_.cast<std::complex<double>>() * x;
  for (int k = 0; k < 4; ++k) r.sensor_m_per_a[static_cast<size_t>(k)] = y(k);
  return r;
}

SensitivityPeak ClosedLoopModel::sensitivity_peak(int axis, double f_min, double f_max, int points) const {
  SensitivityPeak p;
  int best = 0;
  std::vector<double> f(static_cast<size_t>(points)), mag(static_cast<size_t>(points));
  for (int i = 0; i < points; ++i) {
    f[static_cast<size_t>(i)] = f_min * std::pow(f_max / f_min, static_cast<double>(i) / (points - 1));
    mag[static_cast<size_t>(i)] = std::abs(sensitivity(axis, f[static_cast<size_t>(i)]));
    if (mag[static_cast<size_t>(i)] > mag[static_cast<size_t>(best)]) best = i;
  }
  // Golden-section refinement between the neighbours of the best grid point.
  double lo = f[static_cast<size_t>(std::max(0, best - 1))], hi = f[static_cast<size_t>(std::min(points - 1, best + 1))];
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
  double m1 = std::abs(sensitivity(axis, x1)), m2 = std::abs(sensitivity(axis, x2));
  for (int it = 0; it < 40; ++it) {
    if (m1 > m2) {
      hi = x2; x2 = x1; m2 = m1; x1 = hi - g * (hi - lo); m1 = std::abs(sensitivity(axis, x1));
    } else {
      lo = x1; x1 = x2; m1 = m2; x2 = lo + g * (hi - lo); m2 = std::abs(sensitivity(axis, x2));
    }
  }
  p.peak = std::max({mag[static_cast<size_t>(best)], m1, m2});
  p.frequency_hz = m1 > m2 ? x1 : x2;
  if (mag[static_cast<size_t>(best)] >= std::max(m1, m2)) p.frequency_hz = f[static_cast<size_t>(best)];
  p.peak_db = 20.0 * std::log10(p.peak);
  p.zone = iso14839_zone(p.peak);
  return p;
}

}  // namespace amb::model::analysis
