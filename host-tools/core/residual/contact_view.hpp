#pragma once
// Where a drop's rotor meets its aux bearings, as the contact geometry reads it.
//
// The contact circles (drop_contact.hpp) are fitted to the rotor centre at the aux-bearing
// planes. The sensors sit inboard of those planes, and the straight line through the two
// sensor planes is the rotor centre at the aux planes only for a rigid rotor. A flexible
// rotor in contact bends: under its weight between the two contacts, and far more under the
// impacts, which decelerate a rotor whose mass is spread along the shaft while the contact
// forces act at its ends. With the amplifiers cut, the loads are gravity and the two contacts
// at known planes, so the bending is a known function of the record
// (model/drop/flexible_orbit.hpp): this view integrates it and gives the rotor centre at the
// aux planes, rigid-body part plus bending there.
//
// The view hands the contact code readings of a straight rotor through those aux-plane
// centres (same sensors, same angles), so every circle, misfit and centre downstream reads
// the true contact points, the measured record's and the simulation's alike. It replaces the
// static sag bias (SagViewShift) where the board's rotor has a bending mode that the two
// sensor planes can invert; otherwise it is the plain straight-line view.
#include <array>
#include <memory>
#include <vector>

#include "host-tools/core/residual/drop_contact.hpp"
#include "model/drop/flexible_orbit.hpp"
#include "model/drop/sensor_orbit.hpp"
#include "model/plant/plant_params.hpp"
#include "model/rig/rig_model.hpp"

namespace amb::host::residual {

class ContactView {
 public:
  /// `rig`: the board's plant (sensor and aux planes, sensor angles); `rig_model`: its rig
  /// model. Flexible when `use_bending`, the board's rotor keeps bending modes
  /// (modes_kept > 2) and the first bending mode can be inverted from the sensor planes
  /// (FlexibleOrbit::usable); otherwise the straight-line view.
  ContactView(const model::PlantParams& rig, const model::RigModel& rig_model, bool use_bending = true);
  ~ContactView();
  ContactView(const ContactView&) = delete;
  ContactView& operator=(const ContactView&) = delete;

  /// True when the view integrates the rotor's bending (see above).
  bool flexible() const { return flex_ != nullptr; }
  /// Frequency of the bending mode taken into account, Hz (0 when not flexible).
  double bending_hz() const;

  /// Readings [A1, A2, B1, B2] (m) from the trigger on, sampled at `fs_hz` (the first sample
  /// taken straight and at rest: the rotor is levitated there) -> the readings a straight
  /// rotor through the rotor's aux-plane centres would give. Unchanged when not flexible.
  std::vector<std::array<double, 4>> contact_readings(const std::vector<std::array<double, 4>>& sensor_m, double fs_hz) const;

  /// The same from known aux-plane centres per sample (x0, y0, x1, y1), m: a simulation's
  /// own rotor centre at the aux planes.
  std::vector<std::array<double, 4>> from_aux_planes(const std::vector<std::array<double, 4>>& aux_m) const;

 private:
  model::drop::SensorOrbit straight_;  // readings -> sensor-plane centres
  std::array<double, 2> sensor_z_m_{}, aux_z_m_{};
  std::array<std::array<double, 2>, 4> sensor_dir_{};  // unit measuring direction per sensor
  std::unique_ptr<model::drop::FlexibleOrbit> flex_;
};

}  // namespace amb::host::residual
