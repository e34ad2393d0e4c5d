#pragma once
// Rubbing states of a contact event from the slope of the contact polar angle (seed 000
// section 2.3): swinging (contact intermittent, the angle oscillates about the bottom: net
// slope ~ 0), forward rub (sustained contact, the contact point runs round with the spin)
// and backward rub/whirl (sustained contact, running round against the spin).
//
// Works on an orbit only (a measured one or a simulated one through the same sensor view),
// never on contact forces, so measurement and simulation are classified alike:
//  * contact: orbit radius about the bearing centre >= contact_radius_fraction x clearance;
//  * whirl angle phi = atan2(y, x) (counter-clockwise, i.e. positive with a positive spin),
//    unwrapped; its slope is the centred difference over slope_window_s, which spans about
//    one pendulum period sqrt(c/g) x 2 pi of a swing, so a swing's net slope is ~ 0;
//  * rub: contact over at least rub_contact_fraction of the window and
//    |slope| >= rub_slope_rad_s; forward when the slope has the sign of the spin, else backward;
//  * swinging: every other sample from the first contact to the end of the window.
#include <cstdint>
#include <string>
#include <vector>

namespace amb::model::drop {

enum class RubState : std::uint8_t { none = 0, swing = 1, forward = 2, backward = 3 };

struct RubbingOptions {
  double contact_radius_fraction = 0.95; ///< contact when radius >= this x clearance, 1
  double slope_window_s = 0.04;          ///< window of the centred angle slope, s
  double rub_slope_rad_s = 2.0 * 3.141592653589793 * 5.0; ///< |slope| of a full annular rub, rad/s
  double rub_contact_fraction = 0.8;     ///< contact share of the window for a rub, 1
  std::string check() const;             ///< empty when usable
};

struct RubbingDurations {
  double swing_s = 0.0;     ///< seed 000 t_swing, s
  double forward_s = 0.0;   ///< t_fwrub, s
  double backward_s = 0.0;  ///< t_bwrub, s
};

struct RubbingResult {
  std::vector<RubState> state;      ///< per sample
  std::vector<double> angle_rad;    ///< unwrapped whirl angle (counter-clockwise), rad
  std::vector<double> slope_rad_s;  ///< its windowed slope, rad/s
  std::vector<std::uint8_t> contact;///< 1 where the orbit touches the bearing
  RubbingDurations durations;
  int first_contact = -1;           ///< sample index of the first contact (-1: none)
};

/// Classify the samples from `first` to the end. x, y: rotor centre relative to the
/// bearing centre (m), uniformly sampled at `period_s` (s); `clearance_m` (m);
/// `spin_sign` +1 or -1 (direction of the spin about +z).
RubbingResult classify_rubbing(const std::vector<double>& x_m, const std::vector<double>& y_m, double period_s,
                               double clearance_m, double spin_sign, int first, const RubbingOptions& o);

const char* to_string(RubState s);

}  // namespace amb::model::drop
