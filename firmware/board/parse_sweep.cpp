#include "firmware/board/parse_sweep.hpp"

#include <algorithm>
#include <string>

#include "firmware/board/board.hpp"

namespace amb::board {

fw::SweepParams sweep_defaults(double rate_hz, double aux_clearance_m, double max_orbit_fault_m) {
  fw::SweepParams s;
  s.samples_per_period = static_cast<uint32_t>(std::clamp(std::lround(rate_hz), 16L, 65536L));
  s.f_max_hz = std::min(s.f_max_hz, 0.4 * rate_hz);
  s.f_min_hz = std::min(s.f_min_hz, 0.1 * s.f_max_hz);
  if (aux_clearance_m > 0.0) s.abort_clearance_fraction = std::min(s.abort_clearance_fraction, 0.8 * max_orbit_fault_m / aux_clearance_m);
  return s;
}

void parse_sweep(TableReader r, fw::SweepParams& s, double rate_hz) {
  s.enabled = r.boolean_or("enabled", s.enabled);
  s.samples_per_period = static_cast<uint32_t>(r.integer_or("samples_per_period", s.samples_per_period, 16, 65536));
  const double nyquist = 0.5 * rate_hz;
  s.f_min_hz = r.number_or("f_min_hz", std::min(s.f_min_hz, 0.4 * nyquist), 1e-3, nyquist);
  s.f_max_hz = r.number_or("f_max_hz", std::min(s.f_max_hz, 0.8 * nyquist), s.f_min_hz, nyquist);
  s.lines = static_cast<uint32_t>(r.integer_or("lines", s.lines, 1, 1000));
  s.settle_periods = static_cast<uint32_t>(r.integer_or("settle_periods", s.settle_periods, 0, 1000));
  s.recorded_periods = static_cast<uint32_t>(r.integer_or("recorded_periods", s.recorded_periods, 1, 1000));
  s.amplitude_limit_fraction = r.number_or("amplitude_limit_fraction", s.amplitude_limit_fraction, 1e-4, 1.0);
  s.amplitude_fraction = r.number_or("amplitude_fraction", s.amplitude_fraction, 1e-4, s.amplitude_limit_fraction);
  s.abort_clearance_fraction = r.number_or("abort_clearance_fraction", s.abort_clearance_fraction, 0.01, 0.95);
  if (r.has("axes")) {
    const std::vector<double> a = r.numbers("axes", -1, 0.0, 3.0);
    if (a.empty()) r.fail("axes", "must name at least one control axis (0..3)");
    s.axes = {false, false, false, false};
    for (double v : a) {
      if (v != static_cast<double>(static_cast<int>(v))) r.fail("axes", "must hold integers 0..3");
      if (s.axes[static_cast<size_t>(v)]) r.fail("axes", "names axis " + std::to_string(static_cast<int>(v)) + " twice");
      s.axes[static_cast<size_t>(v)] = true;
    }
  }
  // The record buffer: 4 channels x axes x P x N floats, at most 64 MiB.
  const double bytes = 16.0 * s.axis_count() * s.recorded_periods * s.samples_per_period;
  if (bytes > 64.0 * 1024 * 1024)
    r.fail("recorded_periods", "the record buffer (16 B x axes x recorded_periods x samples_per_period = " +
                                   std::to_string(static_cast<long long>(bytes)) + " B) exceeds 64 MiB");
  r.finish();
}

void check_sweep(const fw::SweepParams& s, double rate_hz, double aux_clearance_m, double max_orbit_fault_m,
                 const std::string& source) {
  if (!s.enabled) return;
  const fw::BinRange bins = fw::sweep_bin_range(rate_hz, s.samples_per_period, s.f_min_hz, s.f_max_hz);
  if (bins.hi < bins.lo)
    throw BoardError(source, "sweep.f_max_hz",
                     "the band [f_min_hz, f_max_hz] holds no bin of the period (bin spacing rate_hz / samples_per_period = " +
                         std::to_string(rate_hz / s.samples_per_period) + " Hz)");
  const double abort_m = s.abort_clearance_fraction * aux_clearance_m;
  if (abort_m >= max_orbit_fault_m)
    throw BoardError(source, "sweep.abort_clearance_fraction",
                     "value " + std::to_string(s.abort_clearance_fraction) + " puts the abort radius (" +
                         std::to_string(abort_m * 1e6) + " um) at or beyond lifecycle.max_orbit_fault_m (" +
                         std::to_string(max_orbit_fault_m * 1e6) +
                         " um): the sweep must abort before the fault latches; allowed below " +
                         std::to_string(max_orbit_fault_m / aux_clearance_m));
}

}  // namespace amb::board
