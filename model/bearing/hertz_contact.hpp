#pragma once
// The Hertzian ball-race contact law shared by the 4-DOF (seed 003) and 8-DOF (seed 001)
// models: per-ball radial deflection with radial clearance and a local groove defect,
// Hertz force Q = k_b delta^1.5 for delta > 0, summed over the balls into the radial plane.
// The local defect is a groove across a raceway or a spot on one ball (see GrooveDefect).
//
//   delta_j = (x_in - x_out) cos(theta_j) + (y_in - y_out) sin(theta_j) - c - H_j   (003 eq. 2)
//   Q_j     = k_b delta_j^1.5 if delta_j > 0                                       (003 eq. 3)
//   F       = sum_j Q_j (cos theta_j, sin theta_j)                                   (003 eq. 6)
//   theta_j = theta_cage + 2 pi j / Z,  theta_cage = FTF order * shaft angle (integrated, so
//             it stays right for a time-varying speed; Algorithm 1's w_c t assumes constant w).
// F is the force the balls push on the OUTER ring; the inner ring receives -F.
// (Seed 001 eq. 2 prints sin for x and cos for y; that contradicts its own eq. 3 and is taken
// as an extraction/typesetting slip: one consistent convention is used here.)
#include <array>

#include "model/bearing/geometry.hpp"

namespace amb::model::bearing {

/// Upper bound on the ball count; tables are fixed-size so the law never allocates.
inline constexpr int k_max_balls = 32;

/// Where a local defect sits.
enum class DefectLocation {
  none,
  outer_race,
  inner_race,
  ball,  ///< a spot on one rolling element (GrooveDefect::ball_index)
};

/// Depth profile across the defect.
enum class DefectProfile {
  rectangular,  ///< seed 003 eq. 4-5: H = depth over the whole angular width
  cosine,       ///< seed 001 eq. 5: H = depth cos((theta - phi0) pi / (2 phi_d)), phi_d = half span
};

/// A local defect: a groove (EDM slot) across a raceway, or a spot (pit) on one ball.
///
/// Ball spot (location ball). The spot is a pit of width L (along the ball's rolling great
/// circle) and depth d on ball `ball_index`. The ball spins about its own axis at the ball-spin
/// rate relative to the cage, BSF = D_m/(2 D_b)(1 - gamma^2) x shaft (outer race fixed), so the
/// spot's spin angle is phi = BSF order x shaft angle + angle_rad. The spot faces the outer race
/// when phi = 0 (mod 2 pi) and the inner race when phi = pi: two contacts per spin revolution,
/// hence impacts at 2 x BSF. While it faces a race, that ball's contact deflection loses
/// H(phi) (rectangular or cosine profile over the angular half width 0.5 arcsin(L / r), r the
/// ball radius: seed 003's arcsin(L / R) rule with the ball as the curved body), the same
/// contact-deflection-loss model the groove uses (Ren et al.; Liu et al.). The ball rides with
/// the cage, so the loss only produces force where that ball is in the load zone: the impacts
/// are modulated at FTF. Depth cap (limit_depth_to_ball): the race bridges the pit, so the
/// extra approach is the gap between the intact ball and the race at L/2 from the contact,
/// s(r) - s(R_out) facing the (concave) outer race and s(r) + s(R_in) facing the (convex)
/// inner race, with s(R) = R - sqrt(R^2 - (L/2)^2) the sagitta of radius R over half width L/2.
struct GrooveDefect {
  DefectLocation location = DefectLocation::none;  ///< none / outer / inner race / ball
  DefectProfile profile = DefectProfile::rectangular;
  double width_m = 0.0;   ///< groove width L along the raceway (ball: spot width on the ball), m
  double depth_m = 0.0;   ///< groove (ball: spot) depth d_r, m
  /// Angular position, rad. Outer race: fixed angle in the housing frame. Inner race: angle
  /// on the inner ring relative to the shaft reference mark (rotates with the shaft). Ball: the
  /// spot's spin angle at shaft angle 0, measured from the direction facing the outer race.
  double angle_rad = 0.0;
  /// If true the depth is capped by geometry: a ball of radius r cannot reach the bottom of a
  /// groove narrower than itself, r - sqrt(r^2 - (L/2)^2) (seed 001 eq. 6); for a ball spot
  /// the race bridges the pit (see above).
  bool limit_depth_to_ball = true;
  /// Ball spot only: which ball (0 .. Z-1) carries it; ball j sits at cage angle + 2 pi j / Z.
  int ball_index = 0;
};

/// Ball-size variation: one ball larger in diameter than the others. A healthy bearing's
/// manufacturing imperfection, not a defect (ISO 3290-1: ball lot diameter variation 0.5 um for
/// grade G10, 1.4 um for G28). Its contact deflection grows by the excess, so it carries more
/// load than its neighbours wherever it is in the load zone; it goes round with the cage, so
/// the support force is modulated at the cage rate (FTF).
struct BallSizeVariation {
  double excess_diameter_m = 0.0;  ///< diameter of ball `ball_index` minus the others', m (>= 0; 0: all equal)
  int ball_index = 0;              ///< which ball (0 .. Z-1), at cage angle + 2 pi j / Z
};

/// Inputs of the contact law (parameters; immutable after the law is built).
struct ContactLawParams {
  BearingGeometry geometry;                   ///< ball count, diameters, contact angle
  double hertz_constant_n_per_m1p5 = 0.0;     ///< k_b (already scaled by eta), N/m^1.5
  double radial_clearance_m = 0.0;            ///< delta_0 / mu, m (>= 0)
  GrooveDefect defect;                        ///< optional local defect
  BallSizeVariation ball_size;                ///< optional: one ball larger than the others
};

/// Resultant force on the outer ring and contact bookkeeping.
struct SupportForce {
  double fx_n = 0.0;       ///< force on the outer ring along x, N (inner ring gets -fx_n)
  double fy_n = 0.0;       ///< force on the outer ring along y, N
  int balls_loaded = 0;    ///< number of balls in contact, dimensionless
};

/// Precomputed contact law. Build with make(); evaluate with force(). Never allocates.
class HertzContactLaw {
 public:
  HertzContactLaw() = default;
  /// Build from parameters. Returns false (and leaves the law inert) if the geometry is
  /// invalid, the ball count exceeds k_max_balls, or k_b / clearance / defect are negative.
  bool configure(const ContactLawParams& p);

  /// Support force for inner-minus-outer displacement (dx_m, dy_m) in m and shaft angle
  /// shaft_angle_rad (integral of the shaft speed, rad). Cage angle follows kinematically.
  SupportForce force(double dx_m, double dy_m, double shaft_angle_rad) const noexcept;

  /// Same, with the cage angle given directly (rad), for callers that integrate it themselves.
  SupportForce force_at_cage_angle(double dx_m, double dy_m, double cage_angle_rad,
                                   double shaft_angle_rad) const noexcept;

  const ContactLawParams& params() const { return p_; }
  /// Cage angle per shaft angle (FTF order), dimensionless.
  double cage_ratio() const { return cage_ratio_; }
  /// Ball-spin angle per shaft angle (BSF order, spin relative to the cage), dimensionless.
  double spin_ratio() const { return spin_ratio_; }
  /// Half angular width of the defect, rad (0 without defect): on the race for a groove, on
  /// the ball for a ball spot.
  double defect_half_angle_rad() const { return defect_half_angle_rad_; }
  /// Depth actually applied at the defect centre, m (ball spot: the larger of its two faces).
  double defect_depth_m() const { return defect_depth_m_; }
  /// Ball spot: depth applied while the spot faces the outer / inner race, m (0 otherwise).
  double ball_spot_depth_outer_m() const { return spot_depth_outer_m_; }
  double ball_spot_depth_inner_m() const { return spot_depth_inner_m_; }
  /// Time a ball needs to cross the defect at shaft speed shaft_speed_hz (Hz), s: the step
  /// limit of the integrators. Infinity without a defect, with zero applied depth, or at zero
  /// speed.
  double defect_transit_time_s(double shaft_speed_hz) const noexcept;
  bool configured() const { return ok_; }

 private:
  double defect_depth(double theta_rel_rad) const noexcept;
  double profile_fraction(double theta_rel_rad) const noexcept;
  // Sum of the Z ball loads at cage angle (cos_cage, sin_cage); loss(j, delta) is the depth a
  // defect takes off ball j's deflection delta (m; only called where delta > -defect depth).
  template <class Loss>
  SupportForce ball_loads(double dx_m, double dy_m, double cos_cage, double sin_cage, Loss&& loss) const noexcept;

  ContactLawParams p_{};
  bool ok_ = false;
  int z_ = 0;
  double cage_ratio_ = 0.0;
  double defect_half_angle_rad_ = 0.0;
  double defect_depth_m_ = 0.0;
  double spin_ratio_ = 0.0;
  double spot_depth_outer_m_ = 0.0;
  double spot_depth_inner_m_ = 0.0;
  std::array<double, k_max_balls> cos_pitch_{};  // cos(2 pi j / Z)
  std::array<double, k_max_balls> sin_pitch_{};  // sin(2 pi j / Z)
};

/// Nominal Hertz constant k_b (N/m^1.5) of a radial ball bearing: inner and outer contacts in
/// series, each from the Hamrock-Brewe point-contact approximations (ellipticity, elliptic
/// integrals). groove_conformity_* = groove radius / ball diameter (typically 0.515-0.53).
/// Steel on steel by default (E 208 GPa, nu 0.3).
double nominal_hertz_constant(const BearingGeometry& g, double groove_conformity_inner = 0.52,
                              double groove_conformity_outer = 0.52,
                              double youngs_modulus_pa = 208e9, double poisson_ratio = 0.3);

/// Wrap an angle to (-pi, pi].
double wrap_angle_rad(double a) noexcept;

}  // namespace amb::model::bearing
