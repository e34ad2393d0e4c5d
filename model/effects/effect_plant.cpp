#include "model/effects/effect_plant.hpp"

#include <cmath>

#include "model/amb/amb_force.hpp"

namespace amb::model::effects {

void apply_to_params(const EffectSet& e, PlantParams& rig) {
  if (e.aux_offset) {
    for (size_t p = 0; p < 2; ++p) {
      rig.aux[p].centre_offset_x_m += e.aux_offset->x_m[p];
      rig.aux[p].centre_offset_y_m += e.aux_offset->y_m[p];
    }
  }
  if (e.rotor_mode) {
    const double s2 = e.rotor_mode->frequency_scale * e.rotor_mode->frequency_scale;
    for (auto& el : rig.rotor.elements) el.youngs_modulus_pa *= s2;
  }
  if (e.aux_support) {
    // A massless support spring in series with the (linear penalty) contact.
    auto& a = rig.aux[static_cast<size_t>(e.aux_support->bearing == 0 ? 0 : 1)];
    const double kc = a.contact_stiffness_n_per_m, ks = e.aux_support->stiffness_n_per_m;
    if (kc > 0.0 && ks > 0.0) a.contact_stiffness_n_per_m = kc * ks / (kc + ks);
  }
}

EffectPlant::EffectPlant(std::unique_ptr<Plant> inner, const PlantParams& rig, const EffectSet& effects)
    : inner_(std::move(inner)), rig_(rig), fx_(effects) {}

void EffectPlant::reset(bool levitated, double spin_hz) {
  inner_->reset(levitated, spin_hz);
  lagged_demand_a_ = {};
  correction_a_ = {};
  ped_u_m_ = {};
  ped_v_m_s_ = {};
  ped_static_n_ = {};
  ped_static_valid_ = false;
}

void EffectPlant::step(double dt_s, const PlantInputs& in) {
  PlantInputs inner_in = in;
  for (size_t j = 0; j < 4; ++j) {
    double d = in.current_demand_a[j];
    if (fx_.amplifier_lag && fx_.amplifier_lag->time_constant_s > 0.0) {
      const double a = 1.0 - std::exp(-dt_s / fx_.amplifier_lag->time_constant_s);
      lagged_demand_a_[j] += a * (d - lagged_demand_a_[j]);
      d = lagged_demand_a_[j];
    }
    if (fx_.saturation) d = equivalent_current_a(*fx_.saturation, rig_.amb[j / 2].bias_current_a, d);
    inner_in.current_demand_a[j] = d;
  }
  if (fx_.pedestal) {
    // Pedestal under the reactions of its plane's AMB forces and of the auxiliary bearing
    // mounted on it (the touchdown bearing sits in the same housing: while the rotor rests
    // on it, the AMB pull and the contact push cancel on the pedestal). Semi-implicit Euler.
    const auto& p = *fx_.pedestal;
    const size_t b = static_cast<size_t>(p.plane);
    const PlantTruth tr = inner_->truth();
    double fx = 0.0, fy = 0.0;
    for (size_t a = 0; a < 2; ++a) {
      const auto u = magnet::axis_direction(rig_.amb[b].actuator_angle_deg[a]);
      fx += u[0] * tr.amb_force_n[2 * b + a];
      fy += u[1] * tr.amb_force_n[2 * b + a];
    }
    {
      const double ex = tr.aux_x_m[b] - rig_.aux[b].centre_offset_x_m, ey = tr.aux_y_m[b] - rig_.aux[b].centre_offset_y_m;
      const double r = std::hypot(ex, ey);
      if (r > 0.0 && tr.contact_force_n[b] > 0.0) {
        // Contact force on the rotor is -N e/|e|; on the housing +N e/|e|. The loop below
        // applies (-fx, -fy), so add the rotor-side force here.
        fx += -tr.contact_force_n[b] * ex / r;
        fy += -tr.contact_force_n[b] * ey / r;
      }
    }
    // The pedestal moves only while the rotor flies: with the rotor on its touchdown
    // bearings (amplifiers off, lifting or landing) the housing is held, because the inner
    // plant's touchdown bearings are fixed to ground and the sensors must keep reading the
    // rest position relative to the housing.
    const bool flying = in.amplifiers_enabled && tr.contact_force_n[0] <= 0.0 && tr.contact_force_n[1] <= 0.0;
    if (!flying) {
      ped_u_m_ = {};
      ped_v_m_s_ = {};
      fx = fy = 0.0;
      ped_static_valid_ = false;
    }
    // The pedestal sits at its equilibrium under the static bearing load (the housing is
    // installed loaded; the sensors are mounted in it): it moves under the dynamic part of
    // the reaction only. The static part is tracked with a 0.3 s time constant (0.5 Hz,
    // far below the analysed band), started at the lift-off force. Without this the static
    // sag (rotor weight share / k, ~0.1 mm for a 37 Hz, 20 kg pedestal) would move the
    // inner plant's rotor far from its stator and the linear gap correction below would
    // change the static currents by tens of per cent.
    if (flying) {
      if (!ped_static_valid_) {
        ped_static_n_ = {fx, fy};
        ped_static_valid_ = true;
      }
      const double a = 1.0 - std::exp(-dt_s / 0.3);
      ped_static_n_[0] += a * (fx - ped_static_n_[0]);
      ped_static_n_[1] += a * (fy - ped_static_n_[1]);
      fx -= ped_static_n_[0];
      fy -= ped_static_n_[1];
    }
    const double k = p.stiffness_n_per_m(), c = p.damping_n_s_per_m();
    const int sub = 8;
    const double h = dt_s / sub;
    for (int s = 0; s < sub && flying; ++s) {
      const std::array<double, 2> f{-fx, -fy};
      for (size_t d = 0; d < 2; ++d) {
        ped_v_m_s_[d] = (ped_v_m_s_[d] + h * (f[d] - k * ped_u_m_[d]) / p.mass_kg) / (1.0 + h * c / p.mass_kg);
        ped_u_m_[d] += h * ped_v_m_s_[d];
      }
    }
    // Gap correction: the inner plant's AMB law sees the rotor only; the gap is rotor minus
    // stator, so add -ks (u . dir) / ki, led by the amplifier's time constant.
    const double bw = rig_.amb[b].amplifier_bandwidth_hz;
    const double tau = bw > 0.0 ? 1.0 / (2.0 * M_PI * bw) : 0.0;
    for (size_t a = 0; a < 2; ++a) {
      const auto u = magnet::axis_direction(rig_.amb[b].actuator_angle_deg[a]);
      const double g = rig_.amb[b].ks_n_per_m / rig_.amb[b].ki_n_per_a;
      const double pos = u[0] * ped_u_m_[0] + u[1] * ped_u_m_[1];
      const double vel = u[0] * ped_v_m_s_[0] + u[1] * ped_v_m_s_[1];
      correction_a_[2 * b + a] = in.amplifiers_enabled ? -g * pos : 0.0;
      if (in.amplifiers_enabled) inner_in.current_demand_a[2 * b + a] += -g * (pos + tau * vel);
    }
  }
  inner_->step(dt_s, inner_in);
}

PlantOutputs EffectPlant::outputs() const {
  PlantOutputs o = inner_->outputs();
  for (size_t j = 0; j < 4; ++j) {
    double i = o.coil_current_a[j] - correction_a_[j];
    if (fx_.saturation) i = control_for_equivalent_a(*fx_.saturation, rig_.amb[j / 2].bias_current_a, i);
    o.coil_current_a[j] = i;
  }
  for (size_t k = 0; k < 4; ++k) {
    const auto d = magnet::axis_direction(rig_.sensor[k].angle_deg);
    const int plane = static_cast<int>(k / 2);
    if (fx_.pedestal && fx_.pedestal->plane == plane) o.displacement_m[k] -= d[0] * ped_u_m_[0] + d[1] * ped_u_m_[1];
    if (fx_.runout) {
      for (int h = 1; h <= k_runout_orders; ++h) {
        const std::complex<double> w =
            fx_.runout->r_m[static_cast<size_t>(plane)][static_cast<size_t>(h - 1)] *
            std::exp(std::complex<double>(0.0, h * o.spin_angle_rad));
        o.displacement_m[k] += d[0] * w.real() + d[1] * w.imag();
      }
    }
    if (fx_.sensor_gain) o.displacement_m[k] *= fx_.sensor_gain->gain[k];
  }
  return o;
}

}  // namespace amb::model::effects
