#pragma once
// One rig reduction copied into fixed-capacity vectors, for a model whose time step must not
// allocate: the SIL plant (model/plant) and the drop model (model/drop) both take their modal
// data through it, so the two set up the same rotor the same way (docs/plant.md "The rig
// model").
//
// What comes from the rig model (`RigModel`, `RigReduction`): the kept modes' w^2, damping,
// gyroscopic coupling, gravity load and the modal rows at every plane. What comes from the
// user's own PlantParams (they may differ from the rig model's, see rig_model.hpp): the disks'
// unbalance, the AMB force laws and the actuator and sensor directions.
//
// Building allocates nothing beyond the fixed capacity (configure time, not in the step).
#include <array>
#include <string>

#include <Eigen/Core>

#include "model/amb/amb_force.hpp"
#include "model/plant/plant_params.hpp"
#include "model/rig/rig_model.hpp"

namespace amb::model {

inline constexpr int k_step_max_modes = 24;  ///< capacity: modes per lateral plane
using StepModeVec = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, k_step_max_modes, 1>;
using StepModeMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, k_step_max_modes, k_step_max_modes>;

/// A modal row (or a per-mode column, transposed) as a fixed-capacity vector. At most
/// k_step_max_modes entries.
StepModeVec to_step_vec(const Eigen::RowVectorXd& r);

/// The modal data of one reduction, per kept mode of one lateral plane (x and y share it).
struct StepRows {
  int modes = 0;                        ///< kept modes per plane
  double spin_inertia_kg_m2 = 0.0;      ///< the rotor's polar inertia, kg m^2
  StepModeVec w2;                       ///< modal stiffness (omega^2), 1/s^2
  StepModeVec damp;                     ///< modal damping, 1/s
  StepModeVec gravity_y;                ///< modal gravity load along -y, N
  StepModeMat polar;                    ///< gyroscopic coupling per unit spin speed
  std::array<StepModeVec, 2> amb;       ///< modal rows at the AMB planes [A, B], m per unit
  std::array<StepModeVec, 2> aux;       ///< modal rows at the aux-bearing planes [A, B]
  std::array<StepModeVec, 4> sensor;    ///< modal rows at the sensor planes [A1, A2, B1, B2]
  StepModeVec coupling;                 ///< modal row at the coupling end
  StepModeVec mid_disk;                 ///< modal row of the disk nearest mid-span
  double mid_disk_phase_rad = 0.0;      ///< that disk's unbalance phase, rad
  StepModeVec unb_sin, unb_cos;         ///< unbalance sums S and C (unbalance_expansion), kg m
  std::array<magnet::AxisLaw, 2> law{};                 ///< force law per AMB [A, B] (p.amb)
  std::array<std::array<double, 2>, 4> act_dir{};      ///< (x, y) direction per actuator axis
  std::array<std::array<double, 2>, 4> sensor_dir{};   ///< (x, y) direction per sensor channel
};

/// The rows of `red` (a reduction of `rig`) with the unbalance, force laws and directions of
/// `p`. Throws std::invalid_argument("<who>: ...") when the reduction keeps more than
/// k_step_max_modes modes or the rotor has no polar inertia.
StepRows make_step_rows(const RigModel& rig, const RigReduction& red, const PlantParams& p, const std::string& who);

}  // namespace amb::model
