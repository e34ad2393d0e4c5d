#pragma once
// Scoring a tracker run against a known speed (test helper).
#include <cmath>
#include <cstddef>
#include <functional>
#include <vector>

#include "model/signal/speed_ridge_tracker.hpp"

namespace amb::test {

/// Error figures of a tracker run over the scored updates.
struct TrackScore {
  size_t scored = 0;          ///< updates whose true speed >= the tracker's stated minimum
  size_t lost = 0;            ///< scored updates without a speed (counted as 100 % error)
  double mean_rel_error = 0;  ///< mean |est - true| / true over the scored updates
  double max_rel_error = 0;   ///< largest relative error among the scored, non-lost updates
  double mae_hz = 0;          ///< mean absolute error over the scored, non-lost updates, Hz
  double duration_s = 0;      ///< time spanned by all updates, s
  size_t updates = 0;         ///< all updates
};

/// Scores every update whose true speed at the window centre is at or above `min_hz`.
/// Criterion: no update is dropped for being hard; a lost update counts as 100 % error.
inline TrackScore score_track(const std::vector<model::signal::SpeedEstimate>& est,
                              const std::function<double(double)>& truth_hz, double min_hz) {
  TrackScore s;
  s.updates = est.size();
  if (!est.empty()) s.duration_s = est.back().t_s - est.front().t_s;
  double sum_rel = 0.0, sum_abs = 0.0;
  size_t n_valid = 0;
  for (const auto& e : est) {
    const double f = truth_hz(e.t_s);
    if (!(f >= min_hz)) continue;
    ++s.scored;
    if (e.lost || !std::isfinite(e.speed_hz)) {
      ++s.lost;
      sum_rel += 1.0;
      continue;
    }
    const double rel = std::abs(e.speed_hz - f) / f;
    sum_rel += rel;
    sum_abs += std::abs(e.speed_hz - f);
    s.max_rel_error = std::max(s.max_rel_error, rel);
    ++n_valid;
  }
  if (s.scored > 0) s.mean_rel_error = sum_rel / static_cast<double>(s.scored);
  if (n_valid > 0) s.mae_hz = sum_abs / static_cast<double>(n_valid);
  return s;
}

}  // namespace amb::test
