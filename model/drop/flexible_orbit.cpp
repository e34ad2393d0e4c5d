#include "model/drop/flexible_orbit.hpp"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <stdexcept>

#include "model/rotor/modal_reduction.hpp"

namespace amb::model::drop {

namespace {
int checked_modes(int bending_modes) {
  if (bending_modes < 1) throw std::invalid_argument("flexible orbit: at least one bending mode");
  return 2 + bending_modes;
}
}  // namespace

FlexibleOrbit::FlexibleOrbit(const rotor::RotorModel& rotor, const RotorParams& params, std::array<double, 2> sensor_axial_m,
                             std::array<double, 2> aux_axial_m, int bending_modes, double gravity_m_s2) {
  init(rotor, rotor::reduce_rotor(rotor, params, checked_modes(bending_modes)), sensor_axial_m, aux_axial_m, gravity_m_s2);
}

FlexibleOrbit::FlexibleOrbit(const RigModel& rig, std::array<double, 2> sensor_axial_m, std::array<double, 2> aux_axial_m,
                             int bending_modes) {
  init(rig.rotor(), rotor::truncate_basis(rig.modal_basis(), rig.rotor(), checked_modes(bending_modes)), sensor_axial_m,
       aux_axial_m, rig.params().gravity_m_s2);
}

void FlexibleOrbit::init(const rotor::RotorModel& rotor, const rotor::ReducedRotor& red, std::array<double, 2> sensor_axial_m,
                         std::array<double, 2> aux_axial_m, double gravity_m_s2) {
  if (std::abs(sensor_axial_m[1] - sensor_axial_m[0]) < 1e-9 || std::abs(aux_axial_m[1] - aux_axial_m[0]) < 1e-9)
    throw std::invalid_argument("flexible orbit: the two sensor planes (and the two aux planes) must differ");
  if (red.modes < 3 || red.omega2(0) != 0.0 || red.omega2(1) != 0.0 || !(red.omega2(2) > 0.0))
    throw std::invalid_argument("flexible orbit: the rotor model has no bending mode above its two rigid-body modes");
  nf_ = red.modes - 2;
  Eigen::MatrixXd s(2, red.modes), a(2, red.modes);
  for (int i = 0; i < 2; ++i) {
    s.row(i) = rotor::modal_interpolation(rotor, red, sensor_axial_m[static_cast<size_t>(i)]);
    a.row(i) = rotor::modal_interpolation(rotor, red, aux_axial_m[static_cast<size_t>(i)]);
  }
  const Eigen::Matrix2d s_r = s.leftCols(2), a_r = a.leftCols(2);
  s_f_ = s.rightCols(nf_);
  a_f_ = a.rightCols(nf_);
  s_r_inv_ = s_r.inverse();
  a_r_ = a_r;
  const Eigen::MatrixXd p = a_f_.transpose() * a_r.transpose().inverse();  // nf x 2
  e_ = p * s_r.inverse();
  const Eigen::MatrixXd l = Eigen::MatrixXd::Identity(nf_, nf_) + e_ * s_f_;
  l_inv_ = l.inverse();
  w_f_ = red.omega2.tail(nf_);
  d_f_ = red.damping.tail(nf_);
  const Eigen::VectorXd g = rotor::modal_gravity_load(rotor, red, gravity_m_s2);
  c_y_ = g.tail(nf_) - p * g.head(2);
  for (int k = 0; k < nf_; ++k) bending_hz_.push_back(std::sqrt(w_f_(k)) / (2.0 * M_PI));
  const Eigen::MatrixXd zero_dynamics = l_inv_ * w_f_.asDiagonal();
  Eigen::EigenSolver<Eigen::MatrixXd> es(zero_dynamics, false);
  usable_ = es.info() == Eigen::Success;
  for (Eigen::Index k = 0; k < es.eigenvalues().size(); ++k) {
    const std::complex<double> ev = es.eigenvalues()(k);
    const bool ok = ev.real() > 0.0 && std::abs(ev.imag()) <= 1e-9 * std::abs(ev.real());
    usable_ = usable_ && ok;
    inverse_hz_.push_back(ok ? std::sqrt(ev.real()) / (2.0 * M_PI) : 0.0);
  }
}

template <class PerSample>
void FlexibleOrbit::integrate(const std::vector<std::array<double, 4>>& planes_m, double dt_s, bool with_gravity,
                              PerSample&& sample) const {
  // Sub-steps: the fastest of the bending and inverse modes resolved to 0.1 rad per step.
  double w_max = std::sqrt(w_f_.maxCoeff());
  for (double f : inverse_hz_) w_max = std::max(w_max, 2.0 * M_PI * f);
  const int sub = std::max(1, static_cast<int>(std::ceil(w_max * dt_s / 0.1)));
  const double h = dt_s / sub;
  for (int plane = 0; plane < 2; ++plane) {  // 0: x, 1: y (gravity)
    const Eigen::VectorXd c = plane == 1 && with_gravity ? c_y_ : Eigen::VectorXd::Zero(nf_);
    const auto y_at = [&](size_t i) { return Eigen::Vector2d(planes_m[i][static_cast<size_t>(plane)], planes_m[i][static_cast<size_t>(2 + plane)]); };
    Eigen::Vector2d y_rate = (y_at(1) - y_at(0)) / dt_s;
    // At the first sample: straight and at rest.
    Eigen::VectorXd u = -e_ * y_at(0), w = -e_ * y_rate;
    const auto accel = [&](const Eigen::VectorXd& uu, const Eigen::VectorXd& ww, const Eigen::Vector2d& y,
                           const Eigen::Vector2d& yd) -> Eigen::VectorXd {
      const Eigen::VectorXd q = l_inv_ * (uu + e_ * y), qd = l_inv_ * (ww + e_ * yd);
      return c - d_f_.cwiseProduct(qd) - w_f_.cwiseProduct(q);
    };
    for (size_t i = 0;; ++i) {
      const Eigen::Vector2d y0 = y_at(i);
      sample(i, plane, Eigen::VectorXd(l_inv_ * (u + e_ * y0)));
      if (i + 1 >= planes_m.size()) break;
      y_rate = (y_at(i + 1) - y0) / dt_s;
      for (int j = 0; j < sub; ++j) {  // classical Runge-Kutta, y linear between samples
        const Eigen::Vector2d ya = y0 + y_rate * (j * h), ym = ya + y_rate * (0.5 * h), yb = ya + y_rate * h;
        const Eigen::VectorXd k1u = w, k1w = accel(u, w, ya, y_rate);
        const Eigen::VectorXd k2u = w + 0.5 * h * k1w, k2w = accel(u + 0.5 * h * k1u, k2u, ym, y_rate);
        const Eigen::VectorXd k3u = w + 0.5 * h * k2w, k3w = accel(u + 0.5 * h * k2u, k3u, ym, y_rate);
        const Eigen::VectorXd k4u = w + h * k3w, k4w = accel(u + h * k3u, k4u, yb, y_rate);
        u += h / 6.0 * (k1u + 2.0 * k2u + 2.0 * k3u + k4u);
        w += h / 6.0 * (k1w + 2.0 * k2w + 2.0 * k3w + k4w);
      }
    }
  }
}

std::vector<std::array<double, 4>> FlexibleOrbit::rigid_part(const std::vector<std::array<double, 4>>& planes_m,
                                                             double dt_s, bool with_gravity) const {
  std::vector<std::array<double, 4>> out(planes_m);
  if (planes_m.size() < 2 || !(dt_s > 0.0)) return out;
  integrate(planes_m, dt_s, with_gravity, [&](size_t i, int plane, const Eigen::VectorXd& q) {
    const Eigen::Vector2d bend = s_f_ * q;
    out[i][static_cast<size_t>(plane)] -= bend(0);
    out[i][static_cast<size_t>(2 + plane)] -= bend(1);
  });
  return out;
}

std::vector<std::array<double, 4>> FlexibleOrbit::aux_planes(const std::vector<std::array<double, 4>>& planes_m,
                                                             double dt_s) const {
  std::vector<std::array<double, 4>> out(planes_m.size());
  if (planes_m.size() < 2 || !(dt_s > 0.0)) return out;
  integrate(planes_m, dt_s, true, [&](size_t i, int plane, const Eigen::VectorXd& q) {
    const auto p = static_cast<size_t>(plane);
    const Eigen::Vector2d y(planes_m[i][p], planes_m[i][2 + p]);
    const Eigen::Vector2d aux = a_r_ * (s_r_inv_ * (y - s_f_ * q)) + a_f_ * q;
    out[i][p] = aux(0);
    out[i][2 + p] = aux(1);
  });
  return out;
}

}  // namespace amb::model::drop
