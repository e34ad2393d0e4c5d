#include "model/bearing/hertz_contact.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace amb::model::bearing {

double wrap_angle_rad(double a) noexcept {
  // |mod(a + pi, 2 pi) - pi| of seed 003 eq. 4-5, with a floor-mod that works for a < 0.
  const double two_pi = 2.0 * M_PI;
  double r = std::fmod(a + M_PI, two_pi);
  if (r < 0.0) r += two_pi;
  return r - M_PI;
}

bool HertzContactLaw::configure(const ContactLawParams& p) {
  ok_ = false;
  if (!p.geometry.valid() || p.geometry.ball_count > k_max_balls) return false;
  if (!(p.hertz_constant_n_per_m1p5 >= 0.0) || !(p.radial_clearance_m >= 0.0)) return false;
  if (p.defect.location != DefectLocation::none &&
      (!(p.defect.width_m > 0.0) || !(p.defect.depth_m >= 0.0) || !std::isfinite(p.defect.angle_rad)))
    return false;
  if (p.defect.location == DefectLocation::ball &&
      (p.defect.ball_index < 0 || p.defect.ball_index >= p.geometry.ball_count))
    return false;
  if (!(p.ball_size.excess_diameter_m >= 0.0) || !std::isfinite(p.ball_size.excess_diameter_m) ||
      p.ball_size.ball_index < 0 || p.ball_size.ball_index >= p.geometry.ball_count)
    return false;
  p_ = p;
  z_ = p.geometry.ball_count;
  const DefectOrders orders = defect_orders(p.geometry);
  cage_ratio_ = orders.ftf;
  spin_ratio_ = orders.bsf;
  for (int j = 0; j < z_; ++j) {
    const double a = 2.0 * M_PI * j / z_;
    cos_pitch_[static_cast<size_t>(j)] = std::cos(a);
    sin_pitch_[static_cast<size_t>(j)] = std::sin(a);
  }
  defect_half_angle_rad_ = 0.0;
  defect_depth_m_ = 0.0;
  spot_depth_outer_m_ = 0.0;
  spot_depth_inner_m_ = 0.0;
  if (p.defect.location == DefectLocation::ball) {
    // The ball is the curved body the spot is cut in: arcsin(L / r), r the ball radius.
    const double r = 0.5 * p.geometry.ball_diameter_m;
    defect_half_angle_rad_ = 0.5 * std::asin(std::min(1.0, p.defect.width_m / r));
    spot_depth_outer_m_ = p.defect.depth_m;
    spot_depth_inner_m_ = p.defect.depth_m;
    if (p.defect.limit_depth_to_ball) {
      // Gap between the intact ball and the race L/2 from the contact (the race bridges the
      // pit): ball sagitta minus (concave outer) / plus (convex inner) the race's sagitta.
      const double half = std::min(r, 0.5 * p.defect.width_m);
      auto sagitta = [half](double radius) { return radius - std::sqrt(radius * radius - half * half); };
      spot_depth_outer_m_ = std::min(spot_depth_outer_m_,
                                     std::max(0.0, sagitta(r) - sagitta(p.geometry.outer_raceway_radius_m())));
      spot_depth_inner_m_ = std::min(spot_depth_inner_m_, sagitta(r) + sagitta(p.geometry.inner_raceway_radius_m()));
    }
    defect_depth_m_ = std::max(spot_depth_outer_m_, spot_depth_inner_m_);
  } else if (p.defect.location != DefectLocation::none) {
    // Seed 003: theta_d = arcsin(L / R_race), R_race the raceway radius the groove is cut in.
    const double r_race = p.defect.location == DefectLocation::outer_race
                              ? p.geometry.outer_raceway_radius_m()
                              : p.geometry.inner_raceway_radius_m();
    const double s = std::min(1.0, p.defect.width_m / r_race);
    defect_half_angle_rad_ = 0.5 * std::asin(s);
    defect_depth_m_ = p.defect.depth_m;
    if (p.defect.limit_depth_to_ball) {
      const double r = 0.5 * p.geometry.ball_diameter_m;
      const double half = std::min(r, 0.5 * p.defect.width_m);
      defect_depth_m_ = std::min(defect_depth_m_, r - std::sqrt(r * r - half * half));
    }
  }
  ok_ = true;
  return true;
}

double HertzContactLaw::profile_fraction(double theta_rel_rad) const noexcept {
  const double a = std::abs(wrap_angle_rad(theta_rel_rad));
  if (a > defect_half_angle_rad_) return 0.0;
  if (p_.defect.profile == DefectProfile::rectangular) return 1.0;
  return std::cos(a * M_PI / (2.0 * defect_half_angle_rad_));
}

double HertzContactLaw::defect_depth(double theta_rel_rad) const noexcept {
  const double a = std::abs(wrap_angle_rad(theta_rel_rad));
  if (a > defect_half_angle_rad_) return 0.0;
  if (p_.defect.profile == DefectProfile::rectangular) return defect_depth_m_;
  return defect_depth_m_ * std::cos(a * M_PI / (2.0 * defect_half_angle_rad_));
}

double HertzContactLaw::defect_transit_time_s(double shaft_speed_hz) const noexcept {
  const double speed = std::abs(shaft_speed_hz);
  if (!ok_ || !(defect_half_angle_rad_ > 0) || !(defect_depth_m_ > 0) || !(speed > 0))
    return std::numeric_limits<double>::infinity();
  // Angular speed of the defect past the contact: the cage over a fixed outer race, the shaft
  // minus the cage over an inner-race groove, the ball's spin (relative to the cage) for a spot.
  const DefectLocation loc = p_.defect.location;
  const double rel = loc == DefectLocation::outer_race   ? cage_ratio_
                     : loc == DefectLocation::inner_race ? 1.0 - cage_ratio_
                                                         : spin_ratio_;
  return 2.0 * defect_half_angle_rad_ / (2.0 * M_PI * speed * rel);
}

template <class Loss>
SupportForce HertzContactLaw::ball_loads(double dx_m, double dy_m, double cc, double sc, Loss&& loss) const noexcept {
  SupportForce out;
  for (int j = 0; j < z_; ++j) {
    const auto k = static_cast<size_t>(j);
    // cos/sin(theta_cage + 2 pi j/Z) by the addition theorem: 2 trig calls per evaluation.
    const double cj = cc * cos_pitch_[k] - sc * sin_pitch_[k];
    const double sj = sc * cos_pitch_[k] + cc * sin_pitch_[k];
    double delta = dx_m * cj + dy_m * sj - p_.radial_clearance_m;
    if (j == p_.ball_size.ball_index) delta += p_.ball_size.excess_diameter_m;
    if (delta > -defect_depth_m_) delta -= loss(j, delta);
    if (delta > 0.0) {
      const double q = p_.hertz_constant_n_per_m1p5 * delta * std::sqrt(delta);
      out.fx_n += q * cj;
      out.fy_n += q * sj;
      ++out.balls_loaded;
    }
  }
  return out;
}

SupportForce HertzContactLaw::force(double dx_m, double dy_m, double shaft_angle_rad) const noexcept {
  return force_at_cage_angle(dx_m, dy_m, cage_ratio_ * shaft_angle_rad, shaft_angle_rad);
}

SupportForce HertzContactLaw::force_at_cage_angle(double dx_m, double dy_m, double cage_angle_rad,
                                                  double shaft_angle_rad) const noexcept {
  if (!ok_) return SupportForce{};
  const double cc = std::cos(cage_angle_rad);
  const double sc = std::sin(cage_angle_rad);
  const DefectLocation loc = p_.defect.location;
  if (loc == DefectLocation::none) return ball_loads(dx_m, dy_m, cc, sc, [](int, double) { return 0.0; });
  if (loc == DefectLocation::ball) {
    const int spot_ball = p_.defect.ball_index;
    // Spin angle of the spot (relative to the cage; outer race fixed): 0 faces the outer race,
    // pi the inner race. Both faces cannot be reached at once (half width < pi / 2).
    const double phi = spin_ratio_ * shaft_angle_rad + p_.defect.angle_rad;
    const double spot_m = spot_depth_outer_m_ * profile_fraction(phi) + spot_depth_inner_m_ * profile_fraction(phi - M_PI);
    return ball_loads(dx_m, dy_m, cc, sc, [&](int j, double) { return j == spot_ball ? spot_m : 0.0; });
  }
  // Defect centre in the same frame as theta_j (inner-race defect turns with the shaft).
  const double defect_centre = loc == DefectLocation::inner_race ? p_.defect.angle_rad + shaft_angle_rad : p_.defect.angle_rad;
  return ball_loads(dx_m, dy_m, cc, sc, [&](int j, double) {
    return defect_depth(cage_angle_rad + 2.0 * M_PI * j / z_ - defect_centre);
  });
}

double nominal_hertz_constant(const BearingGeometry& g, double fi, double fo, double e_pa, double nu) {
  if (!g.valid() || fi <= 0.5 || fo <= 0.5) return 0.0;
  const double d = g.ball_diameter_m;
  const double dm = g.pitch_diameter_m;
  const double ca = std::cos(g.contact_angle_rad);
  const double e_eff = e_pa / (1.0 - nu * nu);  // E' for two equal bodies: 2/(2(1-nu^2)/E)
  // One ball-race contact; `sign` +1 for the (convex) inner race, -1 for the (concave) outer.
  auto contact_constant = [&](double conformity, double sign) {
    // Race radius in the rolling direction (Harris): (d_m - sign D cos a) / (2 cos a).
    const double race_r = (dm - sign * d * ca) / (2.0 * ca);
    const double inv_rx = 2.0 / d + sign / race_r;
    const double inv_ry = 2.0 / d - 1.0 / (conformity * d);
    const double rx = 1.0 / inv_rx;
    const double ry = 1.0 / inv_ry;
    const double ratio = ry / rx;                        // > 1 for ball bearings
    const double r = 1.0 / (inv_rx + inv_ry);
    const double kappa = 1.0339 * std::pow(ratio, 0.636);  // Hamrock-Brewe ellipticity
    const double e2 = 1.0003 + 0.5968 / ratio;             // 2nd kind elliptic integral
    const double f1 = 1.5277 + 0.6023 * std::log(ratio);   // 1st kind elliptic integral
    return M_PI * kappa * e_eff * std::sqrt(2.0 * e2 * r / 9.0) / std::pow(f1, 1.5);
  };
  const double ki = contact_constant(fi, +1.0);
  const double ko = contact_constant(fo, -1.0);
  // Deflections add: delta = (Q/Ki)^(2/3) + (Q/Ko)^(2/3).
  return std::pow(std::pow(ki, -2.0 / 3.0) + std::pow(ko, -2.0 / 3.0), -1.5);
}

}  // namespace amb::model::bearing
