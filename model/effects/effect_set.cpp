#include "model/effects/effect_set.hpp"

#include <algorithm>
#include <cmath>

namespace amb::model::effects {

const char* effect_name(EffectKind k) {
  switch (k) {
    case EffectKind::pedestal_resonance: return "pedestal_resonance";
    case EffectKind::sensor_runout: return "sensor_runout";
    case EffectKind::aux_bearing_offset: return "aux_bearing_offset";
    case EffectKind::amplifier_lag: return "amplifier_lag";
    case EffectKind::rotor_mode: return "rotor_mode";
    case EffectKind::magnetic_saturation: return "magnetic_saturation";
    case EffectKind::sensor_mass: return "sensor_mass";
    case EffectKind::aux_support_compliance: return "aux_support_compliance";
    case EffectKind::sensor_gain: return "sensor_gain";
  }
  return "unknown";
}

std::optional<EffectKind> effect_from_name(const std::string& name) {
  for (int i = 0; i < k_effect_kinds; ++i) {
    const auto k = static_cast<EffectKind>(i);
    if (name == effect_name(k)) return k;
  }
  return std::nullopt;
}

double PedestalResonance::stiffness_n_per_m() const {
  const double w = 2.0 * M_PI * frequency_hz;
  return mass_kg * w * w;
}

double PedestalResonance::damping_n_s_per_m() const {
  return 2.0 * damping_ratio * std::sqrt(stiffness_n_per_m() * mass_kg);
}

bool EffectSet::has(EffectKind k) const {
  switch (k) {
    case EffectKind::pedestal_resonance: return pedestal.has_value();
    case EffectKind::sensor_runout: return runout.has_value();
    case EffectKind::aux_bearing_offset: return aux_offset.has_value();
    case EffectKind::amplifier_lag: return amplifier_lag.has_value();
    case EffectKind::rotor_mode: return rotor_mode.has_value();
    case EffectKind::magnetic_saturation: return saturation.has_value();
    case EffectKind::sensor_mass: return sensor_mass.has_value();
    case EffectKind::aux_support_compliance: return aux_support.has_value();
    case EffectKind::sensor_gain: return sensor_gain.has_value();
  }
  return false;
}

std::vector<std::string> EffectSet::names() const {
  std::vector<std::string> out;
  for (int i = 0; i < k_effect_kinds; ++i)
    if (has(static_cast<EffectKind>(i))) out.emplace_back(effect_name(static_cast<EffectKind>(i)));
  return out;
}

namespace {
double flux_current(double i_sat, double i) { return i_sat * std::tanh(i / i_sat); }
double flux_slope(double i_sat, double i) {
  const double t = std::tanh(i / i_sat);
  return 1.0 - t * t;
}
}  // namespace

double equivalent_current_a(const MagneticSaturation& s, double i0, double ic) {
  // A coil cannot carry negative current: its total current is clamped at 0 (as the plant does).
  const double ip = std::max(0.0, i0 + ic), im = std::max(0.0, i0 - ic);
  const double sp = flux_current(s.saturation_current_a, ip), sm = flux_current(s.saturation_current_a, im);
  return (sp * sp - sm * sm) / (4.0 * i0);
}

double equivalent_current_slope(const MagneticSaturation& s, double i0, double ic) {
  const double ip = std::max(0.0, i0 + ic), im = std::max(0.0, i0 - ic);
  const double is = s.saturation_current_a;
  return (flux_current(is, ip) * flux_slope(is, ip) + flux_current(is, im) * flux_slope(is, im)) / (2.0 * i0);
}

double control_for_equivalent_a(const MagneticSaturation& s, double i0, double eq) {
  // ic_eq is odd and increasing in ic on [-i0 - span, i0 + span]; bisection on a wide bracket.
  double lo = -i0 - 10.0 * s.saturation_current_a, hi = -lo;
  lo = std::max(lo, -1e3);
  hi = std::min(hi, 1e3);
  for (int it = 0; it < 100; ++it) {
    const double mid = 0.5 * (lo + hi);
    if (equivalent_current_a(s, i0, mid) < eq) lo = mid;
    else hi = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace amb::model::effects
