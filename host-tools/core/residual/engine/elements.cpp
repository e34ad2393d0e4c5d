#include "host-tools/core/residual/engine/elements.hpp"

namespace amb::host::residual::engine {

const char* record_kind_name(RecordKind k) {
  switch (k) {
    case RecordKind::steady: return "steady";
    case RecordKind::drop: return "drop";
    case RecordKind::sweep: return "sweep";
    case RecordKind::journal: return "journal";
  }
  return "?";
}

const std::vector<ElementSpec>& element_catalogue() {
  using K = RecordKind;
  static const std::vector<ElementSpec> table{
      {"sensor_runout",
       "speed-locked vectors in the sensor readings (target out of round, electrical runout), orders 1 and 2 per sensor plane",
       {{"a_1x_m", 0.0, 200e-6, "plane A 1x amplitude"}, {"b_1x_m", 0.0, 200e-6, "plane B 1x amplitude"},
        {"a_2x_m", 0.0, 200e-6, "plane A 2x amplitude"}, {"b_2x_m", 0.0, 200e-6, "plane B 2x amplitude"}},
       {"speed-locked 2x lines of the levitated readings", "spin-locked departure of the contact points from the clearance circles (drop)"},
       {K::steady, K::drop}},
      {"sensor_gain",
       "a probe's sensitivity off by a factor: the contact circle is read as an ellipse along that probe's axis",
       {{"gain_a1_over_a2", 0.5, 2.0, "probe A1's gain / probe A2's (a common gain of a plane is not identified)"},
        {"gain_b1_over_b2", 0.5, 2.0, "probe B1's gain / probe B2's"},
        {"gain_a1", 0.5, 2.0, "probe A1's own gain (sweep: the loop gain and the measured plant scale with it)"},
        {"gain_a2", 0.5, 2.0, "probe A2's own gain (sweep)"},
        {"gain_b1", 0.5, 2.0, "probe B1's own gain (sweep)"},
        {"gain_b2", 0.5, 2.0, "probe B2's own gain (sweep)"}},
       {"elliptic contact geometry: the contact radius depends on the direction, aligned with a probe axis (drop)",
        "loop gain and plant level of one axis off the model's (sweep)"},
       {K::drop, K::sweep}},
      {"aux_bearing_offset",
       "an auxiliary bearing's centre off the board's value",
       {{"x0_m", -500e-6, 500e-6, "bearing A centre x"}, {"y0_m", -500e-6, 500e-6, "bearing A centre y"},
        {"x1_m", -500e-6, 500e-6, "bearing B centre x"}, {"y1_m", -500e-6, 500e-6, "bearing B centre y"}},
       {"contact circles off the model's centres (drop)", "rest position off the model's (steady run with a rest segment)"},
       {K::steady, K::drop}},
      {"aux_support_compliance",
       "a spring under one auxiliary bearing in series with its contact",
       {{"stiffness_n_per_m", 1e5, 1e10, "support stiffness"}},
       {"contact deflection growing with the contact force at one bearing beyond the other (drop)"},
       {K::drop}},
      {"pedestal_resonance",
       "a mass-spring-damper between one AMB's stator and ground",
       {{"mass_kg", 0.1, 200.0, "pedestal mass"}, {"frequency_hz", 5.0, 2000.0, "pedestal natural frequency"},
        {"damping_ratio", 0.001, 0.5, "pedestal damping ratio"}},
       {"fixed-frequency excess of the levitated spectra", "FRF resonance the model lacks (sweep)"},
       {K::steady, K::drop, K::sweep}},
      {"amplifier_lag",
       "an extra first-order lag of the power amplifiers",
       {{"time_constant_s", 0.0, 2e-3, "extra lag"}},
       {"phase of the loop above the model's (levitated spectra, 1x current phase, FRF phase)"},
       {K::steady, K::drop, K::sweep}},
      {"rotor_mode",
       "the rotor's bending-mode frequencies scaled",
       {{"frequency_scale", 0.5, 2.0, "bending-mode frequencies / model's"}},
       {"model resonance peaks the data has elsewhere"},
       {K::steady, K::drop, K::sweep}},
      {"magnetic_saturation",
       "the coil flux saturating: force per ampere falls with the current",
       {{"saturation_current_a", 0.5, 1000.0, "i_sat of i_sat tanh(i / i_sat)"}},
       {"force per ampere varying over the recorded currents"},
       {K::steady, K::drop}},
      {"sensor_mass",
       "transducer or collar masses on the shaft at the sensor planes",
       {{"mass_kg", 0.0, 20.0, "added mass per sensor plane"}},
       {"bending modes and accelerometer FRF shifted (sweep)"},
       {K::sweep}},
      {"journal_bearing_wear",
       "a worn arc in the journal bearing's clearance (seed 002: depth d0, position gamma, span beta)",
       {{"depth_m", 0.0, 200e-6, "d0"}, {"position_rad", -3.1416, 6.2832, "gamma"}, {"span_rad", 0.0, 6.2832, "beta"}},
       {"forward/backward full-spectrum lines of the journal orbit off the unworn film's"},
       {K::journal}},
  };
  return table;
}

const ElementSpec* find_element(std::string_view name) {
  for (const auto& e : element_catalogue())
    if (e.name == name) return &e;
  return nullptr;
}

bool within_bounds(const ElementSpec& e, const std::string& parameter, double value) {
  for (const auto& p : e.parameters)
    if (p.name == parameter) return value >= p.lower && value <= p.upper;
  return true;
}

}  // namespace amb::host::residual::engine
