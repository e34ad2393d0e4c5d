#pragma once
// The model beside the measured sweep: the board's predicted S, T and G at the sweep's lines,
// optionally with model elements (model/effects) the board file does not declare.
//  * The board's prediction: model::analysis::ClosedLoopModel, sampled at the board's rate with
//    its loop delay, the AMBs linearised at the static operating point (the weight-carrying
//    control currents raise the negative stiffness: amb_force.hpp) (the exact discretisation of the linearised rig and the firmware's PID),
//    injection at one axis' demand as the record's (sweep_record.hpp): S = u / e, the sensor
//    readings per e, G = y / u with y the axis' position in the controller frame, T = 1 - S.
//  * With elements: the exact prediction times the element's relative change from
//    model::effects::EffectLoopModel (the same rig in the frequency domain with a zero-order
//    hold, which carries amplifier_lag, pedestal_resonance, sensor_gain):
//      S_fx = S_exact S_eff(fx) / S_eff(none),  G_fx = G_exact G_eff(fx) / G_eff(none).
//    The ratio keeps the exact discretisation's accuracy for the board's own loop and takes
//    from the frequency-domain model only what the element changes.
#include <array>
#include <complex>
#include <memory>
#include <vector>

#include "firmware/board/board.hpp"
#include "model/analysis/closed_loop.hpp"
#include "model/effects/effect_set.hpp"
#include "model/rig/rig_model.hpp"

namespace amb::host::sweep {

/// Position of control axis `axis` (0..3) along its actuator direction, from the four sensor
/// readings [A1, A2, B1, B2] (the plane's two readings -> (x, y) -> the actuator direction), m.
/// The controller frame of SweepAxisRecord::sensor_m.
template <class T>
T axis_position(const model::PlantParams& rig, int axis, const std::array<T, 4>& sensors_m);

struct ModelResponse {
  std::complex<double> s, t, g;   ///< 1, 1, m/A
};

class SweepLoopModel {
 public:
  /// `b`: the board (rig, controller, rate, loop delay); `speed_hz`: rotor speed of the sweep;
  /// `axes` (0..3) and `f_hz` (> 0): where it is evaluated. Throws std::invalid_argument as
  /// ClosedLoopModel does.
  SweepLoopModel(const board::BoardConfig& b, double speed_hz, std::vector<int> axes, std::vector<double> f_hz);

  /// [axis index][line] without elements (the board's prediction).
  const std::vector<std::vector<ModelResponse>>& board() const { return board_; }
  /// [axis index][line] with the elements of `fx` (empty set: board()).
  std::vector<std::vector<ModelResponse>> with(const model::effects::EffectSet& fx) const;
  /// Largest |S| of axis index `a` over [f_lo, f_hi] on a 400-point log grid refined around the
  /// top (golden section), with `fx` (empty: the board's), and its frequency and zone.
  model::analysis::SensitivityPeak peak(size_t a, double f_lo_hz, double f_hi_hz, const model::effects::EffectSet& fx) const;

  const std::vector<int>& axes() const { return axes_; }
  /// Per bearing plane: the negative stiffness at the static operating point / the board's, 1.
  const std::array<double, 2>& operating_ks_ratio() const { return operating_ks_ratio_; }
  const std::vector<double>& f_hz() const { return f_; }

 private:
  std::vector<std::vector<ModelResponse>> effect_lines(const model::effects::EffectSet& fx, const std::vector<double>& f) const;
  ModelResponse exact(size_t a, double f) const;
  board::BoardConfig b_;
  double speed_hz_ = 0.0;
  std::vector<int> axes_;
  std::vector<double> f_;
  std::shared_ptr<const model::RigModel> rig_;
  std::unique_ptr<model::analysis::ClosedLoopModel> exact_;
  std::vector<std::vector<ModelResponse>> board_, eff0_;
  std::array<double, 2> operating_ks_ratio_{1.0, 1.0};
};

}  // namespace amb::host::sweep
