#include "host-tools/core/scenario/loop_rating.hpp"

#include <cmath>

#include "model/analysis/closed_loop.hpp"

namespace amb::host {

LoopRating rate_loop(const board::BoardConfig& b) {
  namespace an = model::analysis;
  an::ClosedLoopOptions o;
  o.sample_rate_hz = b.rate_hz;
  o.loop_delay_periods = b.loop_delay_periods;
  const an::ClosedLoopModel cl(b.plant, b.controller, o);
  LoopRating r;
  r.rate_hz = b.rate_hz;
  r.loop_delay_periods = b.loop_delay_periods;
  r.stable = cl.stable();
  for (int axis = 0; axis < 4; ++axis) {
    const an::SensitivityPeak p = cl.sensitivity_peak(axis, 0.1, 0.5 * b.rate_hz, 500);
    if (p.peak > r.sensitivity_peak) {
      r.sensitivity_peak = p.peak;
      r.peak_hz = p.frequency_hz;
      r.peak_axis = axis;
    }
  }
  r.sensitivity_peak_db = 20.0 * std::log10(r.sensitivity_peak);
  r.zone = an::to_string(an::iso14839_zone(r.sensitivity_peak));
  for (const an::ClosedLoopMode& m : cl.rotor_modes(0.3)) {
    r.rotor_mode_hz.push_back(m.natural_rad_s / (2.0 * M_PI));
    r.rotor_mode_zeta.push_back(m.damping_ratio);
  }
  return r;
}

}  // namespace amb::host
