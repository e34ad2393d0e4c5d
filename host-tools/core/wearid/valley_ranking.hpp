#pragma once
// wear-id's choice of the best valley (issue 33, fifth round): valleys are chosen, ranked and
// compared by the chi-square the verdict uses, not by the equal-weight cost the polishes
// minimise. That chi-square's sigma includes the film's K/C error propagated to the residuals
// at the best valley, so the best depends on the sigma and the sigma on the best: the sigma is
// first taken at the valley of lowest cost, the valleys' chi2 computed, and when another
// valley has the lowest chi2 the sigma is taken there and the chi2 recomputed, until the
// valley of lowest chi2 is the one the sigma was taken at (a fixed point) or `max_passes`
// passes were made (then the last pass's lowest is the best; the caller takes the sigma there).
#include <cstddef>
#include <functional>
#include <vector>

namespace amb::host::wearid {

struct ValleyRanking {
  std::vector<size_t> order;  ///< valley indices, lowest chi2 first (non-finite chi2 last, in input order)
  std::vector<double> chi2;   ///< each valley's chi2 (input order) in the last pass
  size_t sigma_at = 0;        ///< valley the last pass's sigma was taken at
  int passes = 0;             ///< chi2 passes made (1: the lowest-cost valley was already the best)
  bool fixed_point = false;   ///< the best valley is the one the sigma was taken at
};

/// `count` valleys; `first`: the valley to take the sigma at first (the lowest cost);
/// `chi2_with_sigma_at(k)`: every valley's chi2 (count values, input order; non-finite where the
/// model cannot represent the wear) with the chi-square sigma taken at valley k.
/// Throws std::invalid_argument when count is 0, first >= count or max_passes < 1.
ValleyRanking rank_valleys_by_chi2(size_t count, size_t first,
                                   const std::function<std::vector<double>(size_t sigma_at)>& chi2_with_sigma_at,
                                   int max_passes = 3);

}  // namespace amb::host::wearid
