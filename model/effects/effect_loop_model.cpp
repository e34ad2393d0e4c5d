#include "model/effects/effect_loop_model.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <stdexcept>

#include "model/amb/amb_force.hpp"

namespace amb::model::effects {
namespace {

constexpr double k_two_pi = 2.0 * M_PI;

// The firmware's notch biquad (firmware/control/pid_axis.cpp, design_notch): repeated here
// because model/ cannot depend on firmware/; both follow the same analog prototype and
// pre-warped bilinear transform, so the frequency responses agree.
cd notch_response(const NotchParams& n, double fs_hz, cd z) {
  const double w0 = k_two_pi * n.centre_hz;
  const double k = w0 / std::tan(w0 / (2.0 * fs_hz));
  const double zeta = n.width_hz / (2.0 * n.centre_hz);
  const double k2 = k * k, w2 = w0 * w0;
  const double nb1 = 2.0 * n.depth * zeta * w0 * k, da1 = 2.0 * zeta * w0 * k;
  const double a0 = k2 + da1 + w2;
  const double b0 = (k2 + nb1 + w2) / a0, b1 = 2.0 * (w2 - k2) / a0, b2 = (k2 - nb1 + w2) / a0;
  const double a1 = 2.0 * (w2 - k2) / a0, a2 = (k2 - da1 + w2) / a0;
  const cd zi = 1.0 / z;
  return (b0 + b1 * zi + b2 * zi * zi) / (1.0 + a1 * zi + a2 * zi * zi);
}

cd first_order(double bandwidth_hz, double w) {
  return bandwidth_hz > 0.0 ? 1.0 / cd(1.0, w / (k_two_pi * bandwidth_hz)) : cd(1.0, 0.0);
}

}  // namespace

EffectLoopModel::EffectLoopModel(const PlantParams& rig, const PidParams& pid, double rate_hz, double spin_hz,
                                 const EffectSet& effects)
    : EffectLoopModel(RigModel::make(rig), rig, pid, rate_hz, spin_hz, effects) {}

EffectLoopModel::EffectLoopModel(std::shared_ptr<const RigModel> rig_model, const PlantParams& rig, const PidParams& pid,
                                 double rate_hz, double spin_hz, const EffectSet& effects)
    : rig_(rig), pid_(pid), rate_hz_(rate_hz), spin_rad_s_(k_two_pi * spin_hz), fx_(effects), model_(std::move(rig_model)) {
  if (!(rate_hz > 0.0)) throw std::invalid_argument("EffectLoopModel: rate_hz must be > 0");
  if (!model_) throw std::invalid_argument("EffectLoopModel: no rig model");
  model_->check_same_rig(rig, "EffectLoopModel");
  m_ = red().modes;
  const bool ped = fx_.pedestal.has_value();
  n_ = 2 * m_ + (ped ? 2 : 0);
  ped_ = ped ? 2 * m_ : -1;
  const int ped_plane = ped ? fx_.pedestal->plane : -1;

  mass_ = Eigen::MatrixXd::Identity(n_, n_);
  k_ = Eigen::MatrixXd::Zero(n_, n_);
  c_ = Eigen::MatrixXd::Zero(n_, n_);
  g_ = Eigen::MatrixXd::Zero(n_, n_);
  gravity_ = Eigen::VectorXd::Zero(n_);

  // Rotor: mass-normalised modes; rotor_mode scales the flexible (non-zero) frequencies.
  const double scale2 = fx_.rotor_mode ? fx_.rotor_mode->frequency_scale * fx_.rotor_mode->frequency_scale : 1.0;
  for (int i = 0; i < m_; ++i) {
    const double w2 = red().omega2(i) * scale2;
    k_(i, i) = k_(m_ + i, m_ + i) = w2;
    c_(i, i) = c_(m_ + i, m_ + i) = red().damping(i);
  }
  g_.block(0, m_, m_, m_) = spin_rad_s_ * red().polar;
  g_.block(m_, 0, m_, m_) = -spin_rad_s_ * red().polar;

  // Gravity (-y) on the rotor: Phi^T M_planar (unit translation).
  Eigen::VectorXd unit_w = Eigen::VectorXd::Zero(fe().planar_mass.rows());
  for (Eigen::Index i = 0; i < unit_w.size(); i += 2) unit_w(i) = 1.0;
  gravity_.segment(m_, m_) = -rig.gravity_m_s2 * red().shapes.transpose() * (fe().planar_mass * unit_w);

  if (fx_.sensor_mass) {
    for (double z : fx_.sensor_mass->axial_m) {
      const Eigen::RowVectorXd b = rotor::modal_interpolation(fe(), red(), z);
      const Eigen::MatrixXd bb = fx_.sensor_mass->mass_kg * b.transpose() * b;
      mass_.block(0, 0, m_, m_) += bb;
      mass_.block(m_, m_, m_, m_) += bb;
      gravity_.segment(m_, m_) += -rig.gravity_m_s2 * fx_.sensor_mass->mass_kg * b.transpose();
    }
  }
  if (ped) {
    const auto& p = *fx_.pedestal;
    for (int d = 0; d < 2; ++d) {
      mass_(ped_ + d, ped_ + d) = p.mass_kg;
      k_(ped_ + d, ped_ + d) = p.stiffness_n_per_m();
      c_(ped_ + d, ped_ + d) = p.damping_n_s_per_m();
    }
  }

  for (int b = 0; b < 2; ++b) {
    const Eigen::RowVectorXd ba = rotor::modal_interpolation(fe(), red(), rig.amb[static_cast<size_t>(b)].axial_m);
    for (int a = 0; a < 2; ++a) {
      const int j = 2 * b + a;
      const auto u = magnet::axis_direction(rig.amb[static_cast<size_t>(b)].actuator_angle_deg[static_cast<size_t>(a)]);
      Eigen::VectorXd v = Eigen::VectorXd::Zero(n_);
      v.segment(0, m_) = u[0] * ba.transpose();
      v.segment(m_, m_) = u[1] * ba.transpose();
      if (b == ped_plane) {
        v(ped_) = -u[0];
        v(ped_ + 1) = -u[1];
      }
      n_amb_[static_cast<size_t>(j)] = v;
    }
  }
  for (int k = 0; k < 4; ++k) {
    const auto& s = rig.sensor[static_cast<size_t>(k)];
    const Eigen::RowVectorXd bs = rotor::modal_interpolation(fe(), red(), s.axial_m);
    const auto d = magnet::axis_direction(s.angle_deg);
    Eigen::VectorXd v = Eigen::VectorXd::Zero(n_);
    v.segment(0, m_) = d[0] * bs.transpose();
    v.segment(m_, m_) = d[1] * bs.transpose();
    if (k / 2 == ped_plane) {
      v(ped_) = -d[0];
      v(ped_ + 1) = -d[1];
    }
    s_row_[static_cast<size_t>(k)] = v;
  }

  // Static point: integral action holds the sensors at 0; the currents carry gravity.
  // [D0, -ki n_j; S, 0] [q; i_eq] = [f_g; 0].
  Eigen::MatrixXd kkt = Eigen::MatrixXd::Zero(n_ + 4, n_ + 4);
  kkt.block(0, 0, n_, n_) = k_;
  for (int j = 0; j < 4; ++j) {
    const auto& amb = rig.amb[static_cast<size_t>(j / 2)];
    kkt.block(0, 0, n_, n_) -= fx_.update.force_scale * amb.ks_n_per_m * n_amb_[static_cast<size_t>(j)] * n_amb_[static_cast<size_t>(j)].transpose();
    kkt.block(0, n_ + j, n_, 1) = -fx_.update.force_scale * amb.ki_n_per_a * n_amb_[static_cast<size_t>(j)];
    kkt.block(n_ + j, 0, 1, n_) = s_row_[static_cast<size_t>(j)].transpose();
  }
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n_ + 4);
  rhs.head(n_) = gravity_;
  const Eigen::VectorXd sol = kkt.fullPivLu().solve(rhs);
  for (int j = 0; j < 4; ++j) {
    const auto& amb = rig.amb[static_cast<size_t>(j / 2)];
    const double eq = sol(n_ + j);
    double ic = eq, ratio = 1.0;
    if (fx_.saturation) {
      ic = control_for_equivalent_a(*fx_.saturation, amb.bias_current_a, eq);
      ratio = equivalent_current_slope(*fx_.saturation, amb.bias_current_a, ic);
    }
    static_.current_a[static_cast<size_t>(j)] = ic;
    static_.ki_ratio[static_cast<size_t>(j)] = ratio;
    ki_eff_[static_cast<size_t>(j)] = fx_.update.force_scale * amb.ki_n_per_a * ratio;
  }
}

Eigen::MatrixXcd EffectLoopModel::dynamic_stiffness(double w) const {
  Eigen::MatrixXcd d = k_.cast<cd>();
  for (int j = 0; j < 4; ++j) {
    const double ks = fx_.update.force_scale * rig_.amb[static_cast<size_t>(j / 2)].ks_n_per_m;
    d -= (ks * n_amb_[static_cast<size_t>(j)] * n_amb_[static_cast<size_t>(j)].transpose()).cast<cd>();
  }
  d += cd(0.0, w) * (c_ + g_).cast<cd>();
  d -= (w * w * mass_).cast<cd>();
  return d;
}

Eigen::Matrix4cd EffectLoopModel::controller(double w) const {
  const double t = 1.0 / rate_hz_;
  const cd z = std::exp(cd(0.0, w * t)), zi = 1.0 / z;
  const double alpha = std::exp(-k_two_pi * pid_.derivative_filter_hz * t);
  // The firmware's PidAxis: integral updated after use (one-sample delay), filtered
  // backward difference for the derivative, notches in series; u = -(P + I + D).
  cd c = pid_.kp_n_per_m + pid_.ki_n_per_m_s * t * zi / (1.0 - zi) +
         pid_.kd_n_s_per_m * (1.0 - alpha) * (1.0 - zi) / (t * (1.0 - alpha * zi));
  c = -c;
  for (int k = 0; k < pid_.notch_count; ++k) c *= notch_response(pid_.notches[static_cast<size_t>(k)], rate_hz_, z);
  Eigen::Matrix4cd kc = Eigen::Matrix4cd::Zero();
  for (int b = 0; b < 2; ++b) {
    const auto s1 = magnet::axis_direction(rig_.sensor[static_cast<size_t>(2 * b)].angle_deg);
    const auto s2 = magnet::axis_direction(rig_.sensor[static_cast<size_t>(2 * b + 1)].angle_deg);
    Eigen::Matrix2d s;
    s << s1[0], s1[1], s2[0], s2[1];
    const auto u1 = magnet::axis_direction(rig_.amb[static_cast<size_t>(b)].actuator_angle_deg[0]);
    const auto u2 = magnet::axis_direction(rig_.amb[static_cast<size_t>(b)].actuator_angle_deg[1]);
    Eigen::Matrix2d u;
    u << u1[0], u2[0], u1[1], u2[1];
    const Eigen::Matrix2d blk = u.inverse() * s.inverse() / rig_.amb[static_cast<size_t>(b)].ki_n_per_a;
    kc.block(2 * b, 2 * b, 2, 2) = c * blk.cast<cd>();
  }
  return kc;
}

cd EffectLoopModel::amplifier_response(int axis, double f_hz) const { return amplifier(axis, k_two_pi * f_hz); }

cd EffectLoopModel::amplifier(int axis, double w) const {
  const double t = 1.0 / rate_hz_;
  // Zero-order hold of the demand over the next period (the sim HAL applies it at once).
  const cd zoh = w * t < 1e-9 ? cd(1.0, 0.0) : (1.0 - std::exp(cd(0.0, -w * t))) / cd(0.0, w * t);
  cd a = zoh * first_order(rig_.amb[static_cast<size_t>(axis / 2)].amplifier_bandwidth_hz, w);
  if (fx_.amplifier_lag && fx_.amplifier_lag->time_constant_s > 0.0)
    a *= 1.0 / cd(1.0, w * fx_.amplifier_lag->time_constant_s);
  if (fx_.update.loop_delay_s > 0.0) a *= std::exp(cd(0.0, -w * fx_.update.loop_delay_s));
  return a;
}


LoopResponse EffectLoopModel::at(double f_hz, const std::vector<AccelPoint>& points) const {
  const double w = k_two_pi * f_hz;
  const Eigen::PartialPivLU<Eigen::MatrixXcd> lu(dynamic_stiffness(w));
  Eigen::MatrixXcd bi(n_, 4);
  for (int j = 0; j < 4; ++j) bi.col(j) = (ki_eff_[static_cast<size_t>(j)] * n_amb_[static_cast<size_t>(j)]).cast<cd>();
  const Eigen::MatrixXcd x = lu.solve(bi);
  Eigen::Matrix4cd t;
  for (int k = 0; k < 4; ++k)
    t.row(k) = first_order(rig_.sensor[static_cast<size_t>(k)].bandwidth_hz, w) *
               (s_row_[static_cast<size_t>(k)].transpose().cast<cd>() * x);
  if (fx_.sensor_gain)
    for (int k = 0; k < 4; ++k) t.row(k) *= fx_.sensor_gain->gain[static_cast<size_t>(k)];
  Eigen::Matrix4cd a = Eigen::Matrix4cd::Zero();
  for (int j = 0; j < 4; ++j) a(j, j) = amplifier(j, w);
  const Eigen::Matrix4cd l = a * controller(w);
  const Eigen::Matrix4cd minv = (Eigen::Matrix4cd::Identity() - l * t).inverse();
  LoopResponse r;
  r.noise.resize(8, 4);
  r.injection.resize(8, 4);
  const Eigen::Matrix4cd i_noise = minv * l;
  r.noise.topRows(4) = t * i_noise + Eigen::Matrix4cd::Identity();
  r.noise.bottomRows(4) = i_noise;
  r.injection.topRows(4) = t * minv;
  r.injection.bottomRows(4) = minv;
  r.accel_injection.resize(static_cast<Eigen::Index>(points.size()), 4);
  for (size_t p = 0; p < points.size(); ++p) {
    const Eigen::RowVectorXd b = rotor::modal_interpolation(fe(), red(), points[p].axial_m);
    const auto d = magnet::axis_direction(points[p].angle_deg);
    Eigen::RowVectorXcd c = Eigen::RowVectorXcd::Zero(n_);
    c.segment(0, m_) = (d[0] * b).cast<cd>();
    c.segment(m_, m_) = (d[1] * b).cast<cd>();
    r.accel_injection.row(static_cast<Eigen::Index>(p)) = -w * w * (c * x * minv);
  }
  return r;
}

Eigen::VectorXcd EffectLoopModel::forward_force(double f_hz, double axial_m) const {
  const double w = k_two_pi * f_hz;
  const Eigen::PartialPivLU<Eigen::MatrixXcd> lu(dynamic_stiffness(w));
  const Eigen::RowVectorXd b = rotor::modal_interpolation(fe(), red(), axial_m);
  Eigen::VectorXcd f = Eigen::VectorXcd::Zero(n_);
  f.segment(0, m_) = b.transpose().cast<cd>();
  f.segment(m_, m_) = cd(0.0, -1.0) * b.transpose().cast<cd>();
  const Eigen::VectorXcd q = lu.solve(f);
  Eigen::Vector4cd e;
  for (int k = 0; k < 4; ++k)
    e(k) = first_order(rig_.sensor[static_cast<size_t>(k)].bandwidth_hz, w) *
           (s_row_[static_cast<size_t>(k)].transpose().cast<cd>() * q)(0);
  return at(f_hz).noise * e;
}

Eigen::VectorXcd EffectLoopModel::forward_runout(double f_hz, int plane) const {
  Eigen::Vector4cd e = Eigen::Vector4cd::Zero();
  for (int k = 2 * plane; k < 2 * plane + 2; ++k) {
    const auto d = magnet::axis_direction(rig_.sensor[static_cast<size_t>(k)].angle_deg);
    e(k) = cd(d[0], -d[1]);
  }
  return at(f_hz).noise * e;
}

StaticPoint EffectLoopModel::static_levitated() const { return static_; }

std::array<double, 4> EffectLoopModel::rest_sensors_m() const {
  // Rotor resting on both aux bearings at their lowest points: per direction, the FE rotor
  // (reduced) under gravity with the two contact points held. KKT: [K A^T; A 0].
  std::array<Eigen::VectorXd, 2> q;
  const double scale2 = fx_.rotor_mode ? fx_.rotor_mode->frequency_scale * fx_.rotor_mode->frequency_scale : 1.0;
  for (int dir = 0; dir < 2; ++dir) {
    Eigen::MatrixXd kkt = Eigen::MatrixXd::Zero(m_ + 2, m_ + 2);
    for (int i = 0; i < m_; ++i) kkt(i, i) = red().omega2(i) * scale2;
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(m_ + 2);
    if (dir == 1) rhs.head(m_) = gravity_.segment(m_, m_);
    for (int p = 0; p < 2; ++p) {
      const auto& aux = rig_.aux[static_cast<size_t>(p)];
      const Eigen::RowVectorXd b = rotor::modal_interpolation(fe(), red(), aux.axial_m);
      kkt.block(m_ + p, 0, 1, m_) = b;
      kkt.block(0, m_ + p, m_, 1) = b.transpose();
      double off = dir == 0 ? aux.centre_offset_x_m : aux.centre_offset_y_m;
      if (fx_.aux_offset) off += dir == 0 ? fx_.aux_offset->x_m[static_cast<size_t>(p)] : fx_.aux_offset->y_m[static_cast<size_t>(p)];
      rhs(m_ + p) = off - (dir == 1 ? aux.clearance_m : 0.0);
    }
    q[static_cast<size_t>(dir)] = kkt.fullPivLu().solve(rhs).head(m_);
  }
  std::array<double, 4> out{};
  for (int k = 0; k < 4; ++k) {
    const auto& s = rig_.sensor[static_cast<size_t>(k)];
    const Eigen::RowVectorXd b = rotor::modal_interpolation(fe(), red(), s.axial_m);
    const auto d = magnet::axis_direction(s.angle_deg);
    out[static_cast<size_t>(k)] = d[0] * b.dot(q[0]) + d[1] * b.dot(q[1]);
  }
  return out;
}

}  // namespace amb::model::effects
