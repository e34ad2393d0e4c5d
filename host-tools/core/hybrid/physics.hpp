#pragma once
// The physics part of the hybrid model (seed 001 section 2): the 8-DOF rotor-bearing model of
// model/bearing/rotor_8dof.hpp set up for a motor test stand of the CWRU kind (drive-end
// bearing A carries the bearing state, fan-end bearing B is healthy), run at an operating
// point, and observed as the drive-end housing acceleration along the sensor direction.
//
// What is added to eq. 1 here (all outside model/bearing, which stays the seed's model):
//  - a ball defect (seed 001 models only the outer race; CWRU also has inner-race and ball
//    faults): a spot of width L on ball 0 that, when it faces a race (ball spin angle 0 for
//    the outer race, pi for the inner), releases r - sqrt(r^2 - (L/2)^2) of that ball's
//    deflection (seed 001 eq. 6 applied to the ball's own curvature);
//  - a residual unbalance force m e w^2 on the two discs (eq. 1 has none; a running machine
//    always has some, and its 1x line is in every measured spectrum);
//  - the motor load: eq. 1 has no torque term. The operating point's load goes to the
//    learned map as an input; the physics sees only the speed (documented in docs/hybrid.md).
// The housing is not modelled (eq. 1 fixes the outer races to ground): the simulated "housing
// acceleration" is the drive-end ball force on the outer ring along the sensor direction over
// an ASSUMED effective housing mass. The transfer path to a real sensor is what the learned
// map supplies.
#include <cstdint>
#include <string>
#include <vector>

#include "model/bearing/geometry.hpp"

namespace amb::host::hybrid {

/// Bearing states the model knows (CWRU naming: Normal, IR, OR, B).
enum class BearingState { healthy = 0, inner_race = 1, outer_race = 2, ball = 3 };
inline constexpr int k_state_count = 4;

/// "healthy", "inner_race", "outer_race", "ball".
const char* state_name(BearingState s);
/// Parse a state name (also accepts normal, ir, or, b, inner, outer); throws std::invalid_argument.
BearingState parse_state(const std::string& s);

/// Where the machine runs: an input of every model, never a label.
struct OperatingPoint {
  double speed_rpm = 0.0;  ///< shaft speed, rpm (> 0)
  double load = 0.0;       ///< motor load in the user's unit (CWRU: hp), >= 0
};

/// Rig parameters of the physics model. Defaults: a 2 hp induction-motor test stand with
/// SKF 6205 (drive end) and 6203 (fan end) bearings. Every mass, stiffness and damping value
/// is ASSUMED (the CWRU data set documents only the bearings and the defect sizes).
struct RigParams {
  std::string drive_end_bearing = "6205";  ///< catalogue name of bearing A (carries the state)
  std::string fan_end_bearing = "6203";    ///< catalogue name of bearing B (healthy)
  /// Effective contact angle of bearing A, rad (catalogue: 0 for deep-groove). Set by
  /// calibrate_kinematics() from the training records' defect lines; see there.
  double drive_end_contact_angle_rad = 0.0;
  double bearing_mass_kg = 0.5;            ///< m1 = m4: shaft share lumped at each bearing, kg (ASSUMED)
  double disc_mass_kg = 2.0;               ///< m2 = m3: rotor core halves, kg (ASSUMED)
  double shaft_stiffness_n_per_m = 5.0e7;  ///< k1..k4, N/m (ASSUMED; first bending mode well above 1 kHz)
  double bearing_damping_n_s_per_m = 200.0;  ///< cs1, cs2, N s/m (ASSUMED)
  double disc_damping_n_s_per_m = 200.0;     ///< cd1, cd2, N s/m (ASSUMED)
  double radial_clearance_m = 5e-6;        ///< both bearings, m (ASSUMED, normal clearance group)
  double defect_width_m = 0.1778e-3;       ///< groove / spot width L, m (CWRU 7 mil)
  /// Residual unbalance eccentricity of each disc, m. ASSUMED: ISO 1940 balance grade G2.5 (electric
  /// motor rotors) at 1800 rpm: e = 2.5 mm/s / (2 pi 30 Hz) = 13.3 um.
  double unbalance_eccentricity_m = 13.3e-6;
  double housing_mass_kg = 5.0;            ///< effective housing mass for force -> acceleration, kg (ASSUMED)
  double sensor_angle_rad = 1.5707963267948966;  ///< sensor direction from +x, rad (12 o'clock: +y, gravity is -y)
  /// Outer-race defect position, rad from +x (CWRU "ORat6": 6 o'clock, the load zone under gravity).
  double outer_defect_angle_rad = -1.5707963267948966;
  double sensor_noise_rel = 0.02;          ///< white sensor noise, fraction of the clean signal rms
  double settle_s = 0.2;                   ///< simulated before recording so start-up transients decay, s
  int steps_per_sample = 8;                ///< RK4 steps per output sample (h = 1 / (fs steps))
  bool valid(std::string* why = nullptr) const;
};

/// A measured record for the kinematic calibration.
struct CalibrationRecord {
  const std::vector<double>* signal = nullptr;  ///< acceleration, any unit
  double fs_hz = 0.0;                           ///< sample rate, Hz
  BearingState state = BearingState::healthy;
  double speed_rpm = 0.0;                       ///< nominal speed, rpm
};

/// What calibrate_kinematics() found.
struct KinematicCalibration {
  int lines_used = 0;               ///< records whose defect line was found (outer or inner race)
  double gamma_catalogue = 0.0;     ///< D_b / D_m of the catalogue geometry
  double gamma_effective = 0.0;     ///< mean of the gammas the found lines imply
  double contact_angle_rad = 0.0;   ///< effective contact angle set in the rig (0 if none found)
  std::string note;                 ///< one sentence for the report
};

/// Effective kinematics of the drive-end bearing from the training records. A loaded deep-
/// groove bearing runs at a small contact angle, so its defect lines sit off the catalogue
/// orders in opposite directions for the two races (BPFO = Z/2 (1 - gamma), BPFI = Z/2 (1 +
/// gamma)). For each outer- or inner-race record the envelope-spectrum line nearest the
/// catalogue order (within +-2 %, harmonics 1..3 combined) gives a gamma; their mean sets
/// cos(alpha) = gamma_eff / gamma_catalogue (alpha = 0 if gamma_eff >= gamma_catalogue or no
/// line is found). Uses only the records passed (the training set), never a prediction record.
KinematicCalibration calibrate_kinematics(const std::vector<CalibrationRecord>& records, double env_band_low_hz,
                                          double env_band_high_hz, RigParams& rig);

/// Simulate `duration_s` of drive-end housing acceleration (g) sampled at `fs_hz` for a bearing
/// state at an operating point. Deterministic for a given `seed` (noise only). Throws
/// std::invalid_argument on invalid input.
std::vector<double> simulate_drive_end(const RigParams& rig, BearingState state, const OperatingPoint& op,
                                       double fs_hz, double duration_s, uint64_t seed);

}  // namespace amb::host::hybrid
