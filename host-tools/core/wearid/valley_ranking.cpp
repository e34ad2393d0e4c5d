#include "host-tools/core/wearid/valley_ranking.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace amb::host::wearid {

ValleyRanking rank_valleys_by_chi2(size_t count, size_t first,
                                   const std::function<std::vector<double>(size_t sigma_at)>& chi2_with_sigma_at,
                                   int max_passes) {
  if (count == 0) throw std::invalid_argument("rank_valleys_by_chi2: no valley");
  if (first >= count) throw std::invalid_argument("rank_valleys_by_chi2: first valley out of range");
  if (max_passes < 1) throw std::invalid_argument("rank_valleys_by_chi2: max_passes must be >= 1");
  ValleyRanking r;
  r.sigma_at = first;
  auto key = [&](size_t k) { return std::isfinite(r.chi2[k]) ? r.chi2[k] : INFINITY; };
  for (r.passes = 1;; ++r.passes) {
    r.chi2 = chi2_with_sigma_at(r.sigma_at);
    if (r.chi2.size() != count) throw std::invalid_argument("rank_valleys_by_chi2: one chi2 per valley expected");
    size_t best = r.sigma_at;
    for (size_t k = 0; k < count; ++k)
      if (key(k) < key(best)) best = k;
    r.fixed_point = best == r.sigma_at;
    if (r.fixed_point || r.passes >= max_passes) break;
    r.sigma_at = best;
  }
  r.order.resize(count);
  for (size_t k = 0; k < count; ++k) r.order[k] = k;
  std::stable_sort(r.order.begin(), r.order.end(), [&](size_t a, size_t b) { return key(a) < key(b); });
  return r;
}

}  // namespace amb::host::wearid
