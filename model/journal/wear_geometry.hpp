#pragma once
// Wear of a hydrodynamic journal bearing's bore (seed 002 section 2.2): the extra film
// thickness delta_h(theta) added to the plain film, h = h0 + delta_h (seed 002 eq. 4).
//
// Angles. theta is the angle of a point of the bore wall measured counter-clockwise from +x
// in the rig frame (x right, y up), i.e. in the direction of the journal's spin (the rig
// spins about +z, turning +x towards +y). theta = 3 pi / 2 is the bottom of the bore: that
// is where seed 002 places the maximum depth when gamma = 0 (eq. 6: the span is centred on
// pi/2 + pi; eq. 11-13 with theta_s = 3 pi/2 - beta/2 + gamma). gamma moves the maximum
// depth in the direction of rotation; psi = theta - (3 pi/2 + gamma) is the angle from it.
//
// Models:
//  two-parameter (Dufrane / Machado-Cavalca, seed 002 eq. 5-7): delta_h = d0 - C (1 - cos psi)
//    inside the span, 0 outside; the span follows from the depth: beta = 2 acos(1 - d0 / C).
//  elliptical three-parameter (Alves et al., seed 002 eq. 8-13): an ellipse centred on the
//    bore centre with semi-axis b = r_b + d0 towards the maximum depth and a across it,
//    chosen so that it cuts the bore circle at psi = +-beta/2; in the canonical form of
//    eq. 11-13, delta_h = sqrt(b^2 cos^2 psi + a^2 sin^2 psi) - r_b inside the span.
// Both make h continuous with a kink (a jump of dh/dtheta) at the edges of the span; the
// Reynolds solver integrates the film exactly piecewise between cell centres, so a kink
// or a true step is handled without smoothing (see reynolds_fvm.hpp).
#include <array>
#include <cmath>
#include <string>

namespace amb::model::journal {

/// An angle wrapped to [0, 2 pi), rad (the bore angle theta's range).
inline double wrap_2pi(double a_rad) {
  const double two_pi = 2.0 * M_PI;
  a_rad = std::fmod(a_rad, two_pi);
  return a_rad < 0.0 ? a_rad + two_pi : a_rad;
}

enum class WearModel : int {
  none = 0,            ///< plain cylindrical bore
  two_parameter = 1,   ///< d0, gamma; span tied to depth (seed 002 eq. 5-7)
  elliptical = 2,      ///< d0, gamma, beta independent (seed 002 eq. 8-13)
};

const char* to_string(WearModel m);

struct WearParams {
  WearModel model = WearModel::none;
  double depth_m = 0.0;         ///< d0: maximum wear depth, m (0 <= d0; 2p: d0 < 2 C)
  double position_rad = 0.0;    ///< gamma: angle of the maximum depth from the bottom, towards the rotation, rad
  double span_rad = 0.0;        ///< beta: angular span of the wear, rad (elliptical only; 0 < beta < pi)
};

/// Wear evaluated for a given bore: precomputed once, cheap per angle.
class WearShape {
 public:
  WearShape() = default;
  /// `bore_radius_m`: r_b (the bearing's radius), `clearance_m`: C. Throws std::invalid_argument
  /// with the reason for parameters outside the model's domain (see WearParams).
  WearShape(const WearParams& w, double bore_radius_m, double clearance_m);

  /// Extra film thickness at wall angle theta (any real; wrapped), m. >= 0.
  double extra_film_m(double theta_rad) const;
  /// The span actually worn, rad (2p: from the depth; elliptical: beta; none: 0).
  double span_rad() const { return span_rad_; }
  /// Angles of the edges of the span in [0, 2 pi) (start, end in the direction of rotation);
  /// where dh/dtheta jumps. Meaningless when span_rad() == 0.
  std::array<double, 2> edges_rad() const { return edges_; }
  const WearParams& params() const { return w_; }

 private:
  WearParams w_{};
  double rb_ = 0.0, c_ = 0.0;
  double centre_rad_ = 0.0, span_rad_ = 0.0;
  double a2_ = 0.0, b2_ = 0.0;  // elliptical semi-axes squared, m^2
  std::array<double, 2> edges_{};
};

/// Span of the two-parameter model for a depth, rad: 2 acos(1 - d0 / C).
double two_parameter_span_rad(double depth_m, double clearance_m);

}  // namespace amb::model::journal
