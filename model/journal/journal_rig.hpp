#pragma once
// A hydrodynamic journal bearing on the AMB rig (seed 002: node 25, next to AMB 2), as the
// board describes it, and its linearisation for the simulated plant.
//
// Placement. The AMB controllers hold the rotor at their sensor zero (integral action), so
// the journal's static position inside the bore is set by where the bore is: the board gives
// the static eccentricity ratio and its direction, and place_journal() finds the bore centre
// that realises it at the operating speed: the reduced rotor's static deflection under
// gravity and the film force at that position, with the displacement at both sensor planes
// held at zero (the AMB forces are the multipliers). This is how the seed's AMBs "place the
// shaft at a specific position inside the journal bearing".
//
// Linearisation (seed 002 eq. 22-23). At a fixed journal position the Reynolds problem with
// Reynolds cavitation is positively homogeneous in (spin, journal velocity): p(k W, k v) =
// k p(W, v). So the coefficients at the placed position scale exactly with speed:
// F(W) = (W / W0) (F0 - K0 dq) - C0 dq', dq from the linearisation point. The plant uses that
// (cheap, real-time safe); it is exact to first order in the orbit for any speed at that
// position, and the static position moves little with speed because the AMBs hold the rotor.
#include <array>

#include <Eigen/Core>
#include <functional>

#include "model/journal/reynolds_fvm.hpp"
#include "model/journal/wear_geometry.hpp"
#include "model/plant/plant_params.hpp"
#include "model/rig/rig_model.hpp"

namespace amb::model::journal {

/// The board's [rig.journal_bearing].
struct JournalBearingParams {
  bool present = false;                   ///< false: no journal bearing on this rig
  double axial_m = 0.0;                   ///< bearing plane from the rotor's left end, m
  BearingGeometry geometry;               ///< bore radius, width, clearance, viscosity
  double static_eccentricity = 0.0;       ///< journal's static eccentricity ratio e/C set by the AMBs, 0..0.95
  double static_direction_deg = 180.0;    ///< direction of that offset, deg from the upward vertical towards +x (180: down)
  ReynoldsOptions grid;                   ///< finite-volume grid (cells_theta, cells_axial)
  std::array<double, 2> probe_angle_deg{45.0, -45.0}; ///< journal probes' measuring directions, deg from vertical
  double probe_noise_rms_m = 0.0;         ///< white noise of each journal probe, m rms
  WearParams wear;                        ///< the bore's wear (plant truth; never read by identification)
};

/// The journal force element the plant steps.
struct LinearJournal {
  bool enabled = false;
  double axial_m = 0.0;                   ///< bearing plane, m
  double bore_x_m = 0.0, bore_y_m = 0.0;  ///< bore centre in the sensor-zero frame, m
  double lin_x_m = 0.0, lin_y_m = 0.0;    ///< journal centre relative to the bore at the linearisation, m
  double ref_spin_rad_s = 0.0;            ///< speed of the linearisation, rad/s
  DynamicCoefficients coeff;              ///< at ref_spin_rad_s
  std::array<double, 2> probe_angle_deg{45.0, -45.0};
  double probe_noise_rms_m = 0.0;
  double clearance_m = 0.0;               ///< for checks (orbit within the film)
};

/// Journal position inside the bore (relative to the bore centre) for the static set-point, m.
JournalState static_journal_state(const JournalBearingParams& jb);

/// Static rotor state with the sensor planes held at zero (integral action), under gravity
/// and an extra force (fx, fy) at `force_axial_m`; uses the rig's modal reduction.
struct RigStatics {
  std::array<double, 2> at_m{};                          ///< displacement (x, y) at the asked plane, m
  std::array<std::array<double, 2>, 2> amb_force_n{};    ///< per AMB: force on the rotor (x, y), N
  std::array<std::array<double, 2>, 2> amb_displacement_m{}; ///< per AMB: rotor at the actuator plane (x, y), m
};
RigStatics static_state(const PlantParams& rig, double at_axial_m, double force_axial_m, double fx_n, double fy_n);
/// The same on a rig model built once by the caller (model/rig).
RigStatics static_state(const RigModel& rig_model, double at_axial_m, double force_axial_m, double fx_n, double fy_n);

/// static_state(...).at_m.
std::array<double, 2> static_displacement_m(const PlantParams& rig, double at_axial_m, double force_axial_m,
                                            double fx_n, double fy_n);

/// Place the journal (see file comment) and linearise the film there at `spin_rad_s`.
/// Throws std::invalid_argument for an unusable bearing description.
LinearJournal place_journal(const PlantParams& rig, const JournalBearingParams& jb, double spin_rad_s);

/// Another film model's static force and coefficients at a journal state and spin speed
/// (rad/s): e.g. an independent solver in the tests, to make records the project's own
/// film did not make. Empty: the board's ReynoldsSolver on jb.grid.
using FilmCoefficientsFn = std::function<DynamicCoefficients(const JournalState&, double spin_rad_s)>;
/// place_journal with the film's coefficients from `film` (empty: the board's solver).
LinearJournal place_journal(const PlantParams& rig, const JournalBearingParams& jb, double spin_rad_s,
                            const FilmCoefficientsFn& film);

/// The same element linearised afresh about another journal position (x_m, y_m from the bore
/// centre, m) at the element's reference speed: the static force and the coefficients of
/// the film at that position (the bore and its wear unchanged). For a plant whose journal
/// settled slightly away from the placement point (the AMBs' integral action is slow): a
/// real film's coefficients are those of where the journal actually sits.
LinearJournal relinearise_journal(const LinearJournal& j, const JournalBearingParams& jb, double x_m, double y_m);
/// The same with the film's coefficients from `film` (empty: the board's solver).
LinearJournal relinearise_journal(const LinearJournal& j, const JournalBearingParams& jb, double x_m, double y_m,
                                  const FilmCoefficientsFn& film);

}  // namespace amb::model::journal
