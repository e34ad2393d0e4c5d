#pragma once
// A report filled from the real producers (test support): a SIL drop captured and stored by
// the firmware (AMBE v1) and replayed, a drop-model Phase D record, a short Phase C fit of a
// drop-model measurement, and a wear record updated with the fitted event. The residual
// section is left to its "not available" box (its producer needs a steady-state record).
#include "host-tools/core/report/report_data.hpp"

namespace amb::test {

/// Built once per test binary.
const host::report::ReportData& full_report();

}  // namespace amb::test
