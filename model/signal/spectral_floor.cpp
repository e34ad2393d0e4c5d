#include "model/signal/spectral_floor.hpp"

#include <algorithm>

namespace amb::model::signal {

void block_median_floor(std::span<const double> level_db, size_t block_bins,
                        std::span<double> scratch, std::span<double> block_medians,
                        std::span<double> floor_db) {
  const size_t n = level_db.size();
  if (n == 0 || block_bins < 4) return;
  const size_t blocks = (n + block_bins - 1) / block_bins;
  for (size_t b = 0; b < blocks; ++b) {
    const size_t lo = b * block_bins;
    const size_t hi = std::min(n, lo + block_bins);
    const size_t m = hi - lo;
    std::copy(level_db.begin() + static_cast<std::ptrdiff_t>(lo),
              level_db.begin() + static_cast<std::ptrdiff_t>(hi), scratch.begin());
    auto mid = scratch.begin() + static_cast<std::ptrdiff_t>(m / 2);
    std::nth_element(scratch.begin(), mid, scratch.begin() + static_cast<std::ptrdiff_t>(m));
    block_medians[b] = *mid;
  }
  // Linear interpolation between block centres; flat beyond the first/last centre.
  const double half = 0.5 * static_cast<double>(block_bins);
  for (size_t k = 0; k < n; ++k) {
    const double pos = (static_cast<double>(k) + 0.5 - half) / static_cast<double>(block_bins);
    if (pos <= 0.0 || blocks == 1) {
      floor_db[k] = block_medians[0];
    } else if (pos >= static_cast<double>(blocks - 1)) {
      floor_db[k] = block_medians[blocks - 1];
    } else {
      const size_t i = static_cast<size_t>(pos);
      const double a = pos - static_cast<double>(i);
      floor_db[k] = (1.0 - a) * block_medians[i] + a * block_medians[i + 1];
    }
  }
}

}  // namespace amb::model::signal
