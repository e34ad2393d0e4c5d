#pragma once
// The residual loop's element catalogue: every model element the engine can add, with the
// parameters it brings (physical bounds, units), the evidence it can explain and the record
// kinds that can test it. The record kinds' code (steady_fit, drop_residual, sweep_frf,
// journal_residual) fits the parameters; criterion.hpp decides; this table says what each
// element is. `amb-host residual --elements` prints it.
#include <string>
#include <string_view>
#include <vector>

namespace amb::host::residual::engine {

enum class RecordKind { steady, drop, sweep, journal };
const char* record_kind_name(RecordKind k);

struct ParameterSpec {
  std::string name;      ///< as reported in `parameters` (SI unit in the name)
  double lower = 0.0;    ///< physical lower bound, in the name's unit
  double upper = 0.0;    ///< physical upper bound, in the name's unit
  std::string meaning;
};

struct ElementSpec {
  std::string name;                    ///< report name
  std::string what;                    ///< the physics, one line
  std::vector<ParameterSpec> parameters;
  std::vector<std::string> evidence;   ///< residual features it can explain
  std::vector<RecordKind> kinds;       ///< record kinds whose features can test it
};

/// Every element, in the order the engine tries them.
const std::vector<ElementSpec>& element_catalogue();

/// The element of that name, or nullptr.
const ElementSpec* find_element(std::string_view name);

/// Is `value` inside the named parameter's physical bounds? Parameters not in the spec pass.
bool within_bounds(const ElementSpec& e, const std::string& parameter, double value);

}  // namespace amb::host::residual::engine
