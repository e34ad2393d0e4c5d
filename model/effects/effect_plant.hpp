#pragma once
// A Plant decorator that adds model elements of effect_set.hpp to any plant in the time
// domain: what a test-data generator uses to produce "measurements" with an effect the
// host's model is not told about. Applied at the plant's boundary:
//   amplifier_lag        first-order lag on every current demand (exact ZOH update)
//   magnetic_saturation  demand -> equivalent current (effect_set.hpp); the reported coil
//                        current is mapped back, so the sensors see the actual current
//   pedestal_resonance   a pedestal mass-spring-damper per the plane, driven by the reaction
//                        of that plane's AMB forces; its sensors read rotor minus pedestal;
//                        the gap term ks (z - u) is applied as a current correction
//                        -ks u / ki, pre-compensated for the board's first-order amplifier;
//                        the pedestal is held while the rotor touches its aux bearings
//   sensor_runout        speed-locked vectors added to the sensor readings
// aux_bearing_offset, rotor_mode and aux_support_compliance change the rig itself:
// apply_to_params() before the inner plant is built. sensor_mass is not applied in the time
// domain.
// Real time: step() and outputs() do not allocate.
#include <memory>

#include "model/effects/effect_set.hpp"
#include "model/plant/plant.hpp"

namespace amb::model::effects {

/// Put the rig-changing effects (aux_bearing_offset: added to the aux-bearing centre
/// offsets; rotor_mode: Young's modulus scaled by frequency_scale^2; aux_support_compliance:
/// that bearing's contact stiffness in series with the support) into `rig`.
void apply_to_params(const EffectSet& e, PlantParams& rig);

class EffectPlant final : public Plant {
 public:
  /// `rig`: the parameters `inner` was built from (bias, gains, angles are read from it).
  EffectPlant(std::unique_ptr<Plant> inner, const PlantParams& rig, const EffectSet& effects);

  void reset(bool levitated, double spin_hz) override;
  void step(double dt_s, const PlantInputs& in) override;
  PlantOutputs outputs() const override;
  PlantTruth truth() const override { return inner_->truth(); }
  void set_faults(const PlantFaults& faults) override { inner_->set_faults(faults); }

 private:
  std::unique_ptr<Plant> inner_;
  PlantParams rig_;
  EffectSet fx_;
  std::array<double, 4> lagged_demand_a_{};   // after the extra amplifier lag, A
  std::array<double, 4> correction_a_{};      // pedestal gap correction now, A
  std::array<double, 2> ped_u_m_{}, ped_v_m_s_{};  // pedestal displacement and velocity (x, y), from its loaded equilibrium
  std::array<double, 2> ped_static_n_{};           // static part of the reaction on the pedestal (tracked), N
  bool ped_static_valid_ = false;
};

}  // namespace amb::model::effects
