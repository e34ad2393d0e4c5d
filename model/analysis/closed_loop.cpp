#include "model/analysis/closed_loop.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "model/amb/amb_force.hpp"
#include "model/rotor/modal_reduction.hpp"
#include "model/rotor/rotor_model.hpp"

namespace amb::model::analysis {
namespace {

constexpr double k_two_pi = 2.0 * M_PI;
// Bandwidths given as 0 ("none") are modelled as this fast first-order lag so that every
// block stays strictly proper and the state space has no algebraic loops.
constexpr double k_fast_hz = 1e5;

double rad_s(double hz) { return k_two_pi * (hz > 0.0 ? hz : k_fast_hz); }

// Inverse of a 2x2 matrix [[a, b], [c, d]].
Eigen::Matrix2d inverse2(double a, double b, double c, double d) {
  Eigen::Matrix2d m;
  m << a, b, c, d;
  return m.inverse();
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

ClosedLoopModel::ClosedLoopModel(const PlantParams& rig, const PidParams& pid, const ClosedLoopOptions& o) {
  const rotor::RotorModel fe = rotor::build_rotor_model(rig.rotor);
  const int keep = o.modes_per_plane < 0 ? rig.rotor.modes_kept : o.modes_per_plane;
  const rotor::ReducedRotor red = rotor::reduce_rotor(fe, rig.rotor, keep);
  const int m = red.modes;
  modes_ = m;

  // ---- state layout ----
  int n = 0;
  const int ex = n, ey = n + m, vx = n + 2 * m, vy = n + 3 * m;
  n += 4 * m;
  std::array<int, 4> sensor{};
  for (int k = 0; k < 4; ++k) sensor[static_cast<size_t>(k)] = n++;
  std::array<int, 4> integ{}, dfilt{}, notch0{};  // per (plane, direction) = 2 b + d
  for (int c = 0; c < 4; ++c) {
    integ[static_cast<size_t>(c)] = n++;
    dfilt[static_cast<size_t>(c)] = n++;
    notch0[static_cast<size_t>(c)] = n;
    n += 2 * pid.notch_count;
  }
  const bool delay = o.loop_delay_s > 0.0;
  std::array<int, 4> pade{}, amp{};
  for (int j = 0; j < 4; ++j) {
    pade[static_cast<size_t>(j)] = delay ? n++ : -1;
    amp[static_cast<size_t>(j)] = n++;
  }
  a_ = Eigen::MatrixXd::Zero(n, n);

  using Row = Eigen::RowVectorXd;
  auto unit = [n](int i) {
    Row r = Row::Zero(n);
    r(i) = 1.0;
    return r;
  };

  // ---- rotor kinematics and the modal rows of displacement at a plane ----
  a_.block(ex, vx, m, m).setIdentity();
  a_.block(ey, vy, m, m).setIdentity();
  auto disp_rows = [&](double axial_m, Row& rx, Row& ry) {
    const Eigen::RowVectorXd b = rotor::modal_interpolation(fe, red, axial_m);
    rx = Row::Zero(n);
    ry = Row::Zero(n);
    rx.segment(ex, m) = b;
    ry.segment(ey, m) = b;
  };

  // ---- sensors: true reading along the sensor axis, first-order roll-off ----
  std::array<Row, 4> s_out;
  for (size_t k = 0; k < 4; ++k) {
    Row rx, ry;
    disp_rows(rig.sensor[k].axial_m, rx, ry);
    const auto d = magnet::axis_direction(rig.sensor[k].angle_deg);
    const Row truth = d[0] * rx + d[1] * ry;
    const double ws = rad_s(rig.sensor[k].bandwidth_hz);
    a_.row(sensor[k]) = ws * (truth - unit(sensor[k]));
    s_out[k] = unit(sensor[k]);
  }

  // ---- controller per plane and direction ----
  const double wf = rad_s(pid.derivative_filter_hz);
  std::array<Row, 4> cmd;
  for (size_t b = 0; b < 2; ++b) {
    const auto s1 = magnet::axis_direction(rig.sensor[2 * b].angle_deg);
    const auto s2 = magnet::axis_direction(rig.sensor[2 * b + 1].angle_deg);
    const Eigen::Matrix2d s_inv = inverse2(s1[0], s1[1], s2[0], s2[1]);
    std::array<Row, 2> force;
    for (size_t d = 0; d < 2; ++d) {
      const size_t c = 2 * b + d;
      const Row e = s_inv(static_cast<Eigen::Index>(d), 0) * s_out[2 * b] +
                    s_inv(static_cast<Eigen::Index>(d), 1) * s_out[2 * b + 1];
      a_.row(integ[c]) = e;
      a_.row(dfilt[c]) = wf * (e - unit(dfilt[c]));
      Row u = -(pid.kp_n_per_m * e + pid.ki_n_per_m_s * unit(integ[c]) +
                pid.kd_n_s_per_m * wf * (e - unit(dfilt[c])));
      for (int k = 0; k < pid.notch_count; ++k) {
        const NotchParams& nt = pid.notches[static_cast<size_t>(k)];
        const double w0 = k_two_pi * nt.centre_hz, bw = k_two_pi * nt.width_hz;
        const int z1 = notch0[c] + 2 * k, z2 = z1 + 1;
        a_.row(z1) = unit(z2);
        a_.row(z2) = u - w0 * w0 * unit(z1) - bw * unit(z2);
        u = u + (nt.depth * bw - bw) * unit(z2);
      }
      force[d] = u;
    }
    // (Fx, Fy) = sum_j u_j f_j  ->  f = U^-1 F; current demand i = f / ki.
    const auto u1 = magnet::axis_direction(rig.amb[b].actuator_angle_deg[0]);
    const auto u2 = magnet::axis_direction(rig.amb[b].actuator_angle_deg[1]);
    const Eigen::Matrix2d u_inv = inverse2(u1[0], u2[0], u1[1], u2[1]);
    for (size_t a = 0; a < 2; ++a)
      cmd[2 * b + a] = (u_inv(static_cast<Eigen::Index>(a), 0) * force[0] +
                        u_inv(static_cast<Eigen::Index>(a), 1) * force[1]) /
                       rig.amb[b].ki_n_per_a;
  }

  // ---- delay, amplifiers, injection points ----
  b_inj_.assign(4, Eigen::VectorXd::Zero(n));
  c_cmd_.assign(4, Row::Zero(n));
  for (size_t j = 0; j < 4; ++j) {
    const size_t b = j / 2;
    const double wa = rad_s(rig.amb[b].amplifier_bandwidth_hz);
    c_cmd_[j] = cmd[j];
    Row amp_in = cmd[j];
    if (delay) {
      // (1 - s tau/2) / (1 + s tau/2) = -1 + 2 / (1 + s tau/2)
      const double p = 2.0 / o.loop_delay_s;
      a_.row(pade[j]) = p * (cmd[j] - unit(pade[j]));
      amp_in = -cmd[j] + 2.0 * unit(pade[j]);
      b_inj_[j](pade[j]) = p;
      b_inj_[j](amp[j]) = -wa;
    } else {
      b_inj_[j](amp[j]) = wa;
    }
    a_.row(amp[j]) = wa * (amp_in - unit(amp[j]));
  }

  // ---- rotor dynamics: modal stiffness, damping, gyroscopics, AMB forces ----
  const double spin = k_two_pi * o.spin_hz;
  for (int i = 0; i < m; ++i) {
    a_(vx + i, ex + i) = -red.omega2(i);
    a_(vy + i, ey + i) = -red.omega2(i);
    a_(vx + i, vx + i) = -red.damping(i);
    a_(vy + i, vy + i) = -red.damping(i);
  }
  a_.block(vx, vy, m, m) += -spin * red.polar;
  a_.block(vy, vx, m, m) += spin * red.polar;
  for (size_t b = 0; b < 2; ++b) {
    const Eigen::RowVectorXd bb = rotor::modal_interpolation(fe, red, rig.amb[b].axial_m);
    Row rx, ry;
    disp_rows(rig.amb[b].axial_m, rx, ry);
    for (size_t a = 0; a < 2; ++a) {
      const size_t j = 2 * b + a;
      const auto u = magnet::axis_direction(rig.amb[b].actuator_angle_deg[a]);
      const Row force = rig.amb[b].ks_n_per_m * (u[0] * rx + u[1] * ry) + rig.amb[b].ki_n_per_a * unit(amp[j]);
      a_.block(vx, 0, m, n) += u[0] * bb.transpose() * force;
      a_.block(vy, 0, m, n) += u[1] * bb.transpose() * force;
    }
  }
}

bool ClosedLoopModel::stable() const { return spectral_abscissa() < 0.0; }

double ClosedLoopModel::spectral_abscissa() const {
  Eigen::EigenSolver<Eigen::MatrixXd> es(a_, false);
  return es.eigenvalues().real().maxCoeff();
}

std::vector<ClosedLoopMode> ClosedLoopModel::modes() const {
  Eigen::EigenSolver<Eigen::MatrixXd> es(a_, true);
  const Eigen::MatrixXcd& v = es.eigenvectors();
  // Participation factors p_ki = |w_ik v_ki| (w: left eigenvectors, rows of V^-1) are
  // independent of the states' units; a mode's rotor share is the part carried by the rotor
  // states (modal displacements and velocities). This separates the mechanical modes from
  // the controller, filter and amplifier modes they couple with.
  const Eigen::MatrixXcd w = v.partialPivLu().inverse();
  const Eigen::Index rotor_states = 4 * modes_;
  std::vector<ClosedLoopMode> out;
  for (Eigen::Index i = 0; i < es.eigenvalues().size(); ++i) {
    const std::complex<double> l = es.eigenvalues()(i);
    if (l.imag() <= 1e-9 * std::abs(l)) continue;
    double rotor = 0.0, total = 0.0;
    for (Eigen::Index k = 0; k < v.rows(); ++k) {
      const double pk = std::abs(w(i, k) * v(k, i));
      total += pk;
      if (k < rotor_states) rotor += pk;
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
  m.diagonal().array() += std::complex<double>(0.0, k_two_pi * f_hz);
  const Eigen::VectorXcd x = m.partialPivLu().solve(b_inj_[j].cast<std::complex<double>>());
  // Injection d at the demand: u = cmd + d, x' = A x + b d  =>  S = u / d = 1 + c (sI - A)^-1 b.
  return 1.0 + (c_cmd_[j].cast<std::complex<double>>() * x)(0);
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
