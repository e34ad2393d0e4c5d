#pragma once
// The specification of a drop-envelope study (amb-host envelope SPEC.toml): which board,
// how long each drop is simulated, and the parameter space — speed, friction, unbalance,
// clearance, aux-bearing centre offsets and failed amplifier channels — sampled on a grid
// or by a seeded Latin hypercube. Parsed strictly: unknown keys and out-of-range values are
// refused with a message naming the key (docs/envelope.md lists every key).
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace amb::host::envelope {

/// A refused spec. what() is "SPEC: KEY: what is wrong".
class SpecError : public std::runtime_error {
 public:
  SpecError(const std::string& source, const std::string& key, const std::string& message);
  const std::string& key() const { return key_; }

 private:
  std::string key_;
};

/// One numeric parameter of the study.
///  fixed:  one value (a bare number in the spec);
///  levels: the listed values (an array); a grid takes each, the hypercube picks per stratum;
///  range:  {min, max, points}: a grid takes `points` evenly spaced values (ends included),
///          the hypercube samples [min, max] continuously (points unused).
struct NumericAxis {
  enum class Kind { fixed, levels, range } kind = Kind::fixed;
  std::vector<double> levels;  ///< fixed: one entry; levels: the values (unit of the parameter)
  double min = 0.0, max = 0.0; ///< range ends (unit of the parameter)
  int points = 2;              ///< range: grid points, >= 2
  bool varies() const { return kind == Kind::range || levels.size() > 1; }
};

/// Failed amplifier channels of one case: bit i = actuator axis i of the board
/// [A axis 1, A axis 2, B axis 1, B axis 2] has its output cut at the trigger.
/// k_all_channels (every axis) is the classic drop: all amplifiers off.
inline constexpr std::uint8_t k_all_channels = 0x0F;

/// "all", or channel names joined by '+' ("A1", "A1+B2"). Throws std::invalid_argument.
std::uint8_t parse_channels(const std::string& text);
/// Inverse of parse_channels ("all" for k_all_channels).
std::string channels_name(std::uint8_t mask);

/// How each drop is simulated (the same for every case of the study).
struct StudySettings {
  std::string board = "bath-amb-rig";  ///< board name or path to a board file
  double settle_s = 0.05;              ///< levitated time at speed before the drop, s
  double window_s = 0.2;               ///< simulated time after the drop, s
  double sample_rate_hz = 10000.0;     ///< record rate (whirl classification), Hz
  double step_s = 2.0e-5;              ///< drop-model time step, s
  std::string contact_law = "board";   ///< "board", "rigid", "hertz" or "linear"
  double friction_energy_budget_j = 20000.0;  ///< life model budget per aux bearing, J (host-tools/core/wear)
};

struct StudySpec {
  std::string source;                  ///< where the spec came from (for messages)
  StudySettings settings;
  std::string method = "grid";         ///< "grid" or "lhs"
  int lhs_cases = 0;                   ///< hypercube: number of cases
  std::uint64_t seed = 1;              ///< hypercube: seed of the sampling (deterministic)
  int worst_count = 10;                ///< how many worst cases the summary lists
  NumericAxis speed_hz;                ///< drive speed before the drop, Hz
  NumericAxis friction;                ///< Coulomb friction collar / inner ring, 1
  NumericAxis unbalance_factor;        ///< factor on the board's disk unbalances, 1
  NumericAxis clearance_m;             ///< radial clearance of both aux bearings, m
  NumericAxis offset_x_m, offset_y_m;  ///< centre offset of both aux bearings from the sensor zero, m
  std::vector<std::uint8_t> failed_channels{k_all_channels};  ///< sets of failed channels (categorical)
};

/// Parameters of one case (what a case's hash is made of, with the study settings).
struct CaseParams {
  double speed_hz = 0.0;
  double friction = 0.0;
  double unbalance_factor = 1.0;
  double clearance_m = 0.0;
  double offset_x_m = 0.0, offset_y_m = 0.0;
  std::uint8_t failed_channels = k_all_channels;
};

/// Parse spec text; `source` names it in errors. Throws SpecError.
StudySpec parse_spec(const std::string& toml_text, const std::string& source);
/// Read and parse a spec file. Throws SpecError (also for an unreadable file).
StudySpec load_spec(const std::string& path);

/// The cases of the study in a fixed order (grid: last parameter fastest; hypercube: the
/// seeded sample). Same spec -> same list.
std::vector<CaseParams> expand_cases(const StudySpec& spec);

/// Names of the numeric parameters that vary in the study (for maps), in spec order.
std::vector<std::string> varying_parameters(const StudySpec& spec);
/// Value of a named parameter of a case ("speed_hz", "friction", ...; "failed_channels": the mask).
double parameter_value(const CaseParams& c, const std::string& name);

}  // namespace amb::host::envelope
