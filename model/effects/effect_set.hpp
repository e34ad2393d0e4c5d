#pragma once
// Model elements that a rotor-AMB model may lack, each a small parameterised piece of
// physics that both the host's linearised loop model (effect_loop_model.hpp) and the
// test-data generators (effect_plant.hpp) apply. Pure data and small pure functions; no I/O.
//
// The names are the ones `amb-host residual` reports (DESIGN.md): pedestal_resonance,
// sensor_runout, aux_bearing_offset, amplifier_lag, rotor_mode, magnetic_saturation,
// sensor_mass (added transducer mass, used for accelerometer-instrumented rigs), and
// aux_support_compliance (a compliant support under an auxiliary bearing; acts in drops only).
#include <array>
#include <complex>
#include <optional>
#include <string>
#include <vector>

namespace amb::model::effects {

enum class EffectKind {
  pedestal_resonance,
  sensor_runout,
  aux_bearing_offset,
  amplifier_lag,
  rotor_mode,
  magnetic_saturation,
  sensor_mass,
  aux_support_compliance,
  sensor_gain,
};
inline constexpr int k_effect_kinds = 9;

/// The report name of a kind ("pedestal_resonance", ...).
const char* effect_name(EffectKind k);
/// Inverse of effect_name; std::nullopt for an unknown name.
std::optional<EffectKind> effect_from_name(const std::string& name);

/// A support/base-plate mode: the AMB stator of bearing plane `plane` sits on a pedestal of
/// mass `mass_kg` tied to ground by a spring and damper (isotropic in x and y), so that the
/// AMB reaction force moves it. The sensors of that plane are mounted on the stator and
/// read the rotor relative to it; the AMB gap is rotor minus stator.
struct PedestalResonance {
  int plane = 0;                 ///< bearing plane 0 (AMB A) or 1 (AMB B)
  double mass_kg = 10.0;         ///< moving pedestal mass, kg
  double frequency_hz = 40.0;    ///< pedestal natural frequency on its ground spring sqrt(k/m)/2pi, Hz
  double damping_ratio = 0.05;   ///< viscous damping ratio of the pedestal on its spring, 1
  double stiffness_n_per_m() const;  ///< k = m (2 pi f)^2, N/m
  double damping_n_s_per_m() const;  ///< c = 2 zeta sqrt(k m), N s/m
};

inline constexpr int k_runout_orders = 2;  ///< speed orders 1 and 2
/// Speed-locked additive signal at the sensors (mechanical target runout or electrical
/// runout), per sensor plane and speed order h: a vector rotating with the rotor,
///   (rx, ry)(t) = Re( R_{plane,h} e^{j h theta(t)} ) (1, -j),
/// theta the rotor angle (rad). Each sensor reads the projection on its axis.
struct SensorRunout {
  std::array<std::array<std::complex<double>, k_runout_orders>, 2> r_m{};  ///< [plane][h-1] phasor, m
};

/// Auxiliary-bearing centres not at the sensor zero (both planes), m.
struct AuxBearingOffset {
  std::array<double, 2> x_m{};   ///< centre offset along x per aux bearing, m
  std::array<double, 2> y_m{};   ///< centre offset along y (up) per aux bearing, m
};

/// An extra first-order lag in every current amplifier (a slower current loop than the
/// board states, or a delay of about `time_constant_s`).
struct AmplifierLag {
  double time_constant_s = 0.0;  ///< extra lag time constant, s
};

/// The rotor's flexible (bending) modes are mistuned: every free-free mode with a nonzero
/// frequency has its frequency scaled by `frequency_scale` (stiffness scaled by its square),
/// as a wrong Young's modulus or wrong section would do.
struct RotorMode {
  double frequency_scale = 1.0;  ///< measured / modelled bending-mode frequency, 1
};

/// Force-law saturation: the flux of each coil follows s(i) = i_sat tanh(i / i_sat) of its
/// total current i (bias +- control), so one actuator axis pulls with
///   F = k [ s(i0 + ic)^2 / (g0 - z)^2 - s(i0 - ic)^2 / (g0 + z)^2 ].
/// At z = 0 this is the unsaturated law driven by the equivalent current
///   ic_eq = ( s(i0 + ic)^2 - s(i0 - ic)^2 ) / (4 i0)                  (see equivalent_current_a)
/// which is how both the generator and the loop model apply it (the bias stiffness ks is
/// left as the board states it).
struct MagneticSaturation {
  double saturation_current_a = 1e9;  ///< i_sat, A (large: no saturation)
};

/// Added point mass on the rotor at given axial positions (transducers glued to the shaft).
struct SensorMass {
  double mass_kg = 0.0;             ///< mass of each transducer, kg
  std::vector<double> axial_m;      ///< where they sit, m from the rotor's left end
};

/// A compliant support (pedestal, housing) under one auxiliary bearing: a massless spring of
/// `stiffness_n_per_m` in series with that bearing's contact, so the contact deflection grows by
/// F / k_s. Acts only while the rotor touches the bearing (drops, rest); the generator applies
/// it to the rig (apply_to_params: the series stiffness of the plant's linear penalty contact).
struct AuxSupportCompliance {
  int bearing = 0;                    ///< aux bearing 0 (A side) or 1 (B side)
  double stiffness_n_per_m = 1e12;    ///< support stiffness k_s, N/m
};

/// The base model's own uncertain parameters (model updating, not a model element: never
/// named as an effect). A real rig differs from its board file in ways no element names; the
/// residual loop fits these first, so that an element is not used to cover them.
struct ModelUpdate {
  double loop_delay_s = 0.0;  ///< extra delay between a sensor sample and the current it commands (computation delay), s
  double force_scale = 1.0;   ///< actual / board actuator force constant: scales ki and ks together (pole area, gap), 1
};

/// Probe sensitivities off the board's value (the reading is gain x the displacement along the
/// probe's axis), per channel [A1, A2, B1, B2], 1.
struct SensorGain {
  std::array<double, 4> gain{1.0, 1.0, 1.0, 1.0};
};

/// The effects a model (or a generator) includes; unset = absent.
struct EffectSet {
  ModelUpdate update;  ///< the base model's uncertain parameters (defaults: the board's values)
  std::optional<PedestalResonance> pedestal;
  std::optional<SensorRunout> runout;
  std::optional<AuxBearingOffset> aux_offset;
  std::optional<AmplifierLag> amplifier_lag;
  std::optional<RotorMode> rotor_mode;
  std::optional<MagneticSaturation> saturation;
  std::optional<SensorMass> sensor_mass;
  std::optional<AuxSupportCompliance> aux_support;
  std::optional<SensorGain> sensor_gain;

  bool has(EffectKind k) const;
  /// Names of the effects present, in EffectKind order.
  std::vector<std::string> names() const;
};

/// Equivalent control current ic_eq of MagneticSaturation for bias i0 and control ic, A.
double equivalent_current_a(const MagneticSaturation& s, double bias_a, double control_a);
/// d ic_eq / d ic at (i0, ic), 1 (the local current-gain ratio ki_eff / ki).
double equivalent_current_slope(const MagneticSaturation& s, double bias_a, double control_a);
/// Inverse of equivalent_current_a in ic (monotonic; bisection), A. Equivalent currents
/// beyond what saturation can deliver are clamped to the largest deliverable.
double control_for_equivalent_a(const MagneticSaturation& s, double bias_a, double equivalent_a);

}  // namespace amb::model::effects
