#include "model/journal/wear_geometry.hpp"

#include <cmath>
#include <stdexcept>

namespace amb::model::journal {
namespace {
constexpr double k_two_pi = 2.0 * M_PI;

// Angle in (-pi, pi].
double wrap_pi(double a) {
  a = wrap_2pi(a);
  return a > M_PI ? a - k_two_pi : a;
}
}  // namespace

const char* to_string(WearModel m) {
  switch (m) {
    case WearModel::none: return "none";
    case WearModel::two_parameter: return "2p";
    case WearModel::elliptical: return "3p";
  }
  return "?";
}

double two_parameter_span_rad(double depth_m, double clearance_m) {
  return 2.0 * std::acos(1.0 - depth_m / clearance_m);
}

WearShape::WearShape(const WearParams& w, double bore_radius_m, double clearance_m)
    : w_(w), rb_(bore_radius_m), c_(clearance_m) {
  if (!(bore_radius_m > 0.0) || !(clearance_m > 0.0) || clearance_m >= bore_radius_m)
    throw std::invalid_argument("wear: need 0 < clearance < bore radius");
  if (!std::isfinite(w.position_rad)) throw std::invalid_argument("wear: gamma (position_rad) is not finite");
  centre_rad_ = wrap_2pi(1.5 * M_PI + w.position_rad);
  if (w.model == WearModel::none || w.depth_m == 0.0) {
    span_rad_ = 0.0;
    return;
  }
  if (!(w.depth_m > 0.0)) throw std::invalid_argument("wear: depth d0 must be >= 0 m");
  if (w.model == WearModel::two_parameter) {
    if (!(w.depth_m < 2.0 * clearance_m))
      throw std::invalid_argument("wear: two-parameter depth d0 must be below 2 C (the span would pass 360 deg)");
    span_rad_ = two_parameter_span_rad(w.depth_m, clearance_m);
  } else if (w.model == WearModel::elliptical) {
    if (!(w.span_rad > 0.0) || !(w.span_rad < M_PI))
      throw std::invalid_argument("wear: elliptical span beta must be in (0, 180) deg");
    span_rad_ = w.span_rad;
    const double b = rb_ + w.depth_m;
    const double s = std::sin(0.5 * span_rad_), c = std::cos(0.5 * span_rad_);
    b2_ = b * b;
    a2_ = (rb_ * rb_ - b2_ * c * c) / (s * s);
    if (!(a2_ > 0.0))
      throw std::invalid_argument("wear: elliptical wear too deep for its span (semi-axis a would be imaginary)");
  } else {
    throw std::invalid_argument("wear: unknown model");
  }
  edges_ = {wrap_2pi(centre_rad_ - 0.5 * span_rad_), wrap_2pi(centre_rad_ + 0.5 * span_rad_)};
}

double WearShape::extra_film_m(double theta_rad) const {
  if (span_rad_ <= 0.0) return 0.0;
  const double psi = wrap_pi(theta_rad - centre_rad_);
  if (std::abs(psi) >= 0.5 * span_rad_) return 0.0;
  if (w_.model == WearModel::two_parameter) return std::max(0.0, w_.depth_m - c_ * (1.0 - std::cos(psi)));
  const double cp = std::cos(psi), sp = std::sin(psi);
  return std::max(0.0, std::sqrt(b2_ * cp * cp + a2_ * sp * sp) - rb_);
}

}  // namespace amb::model::journal
