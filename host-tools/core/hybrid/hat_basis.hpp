#pragma once
// Partition-of-unity hat functions over a bin index, shared by the spectral map and the
// learned correction (both smooth a per-bin quantity through a few knots).
#include <algorithm>
#include <cmath>
#include <cstddef>

namespace amb::host::hybrid {

/// The hat weights at bin `k` of `bins` with `count` equally spaced knots: the first knot
/// index and that knot's weight (the next knot gets 1 - w). One knot, or one bin: {0, 1}.
struct Hat {
  size_t knot = 0;
  double w = 1.0;
};

inline Hat hat(size_t k, size_t bins, size_t count) {
  if (count <= 1 || bins <= 1) return {0, 1.0};
  const double pos = static_cast<double>(k) * static_cast<double>(count - 1) / static_cast<double>(bins - 1);
  const auto t = std::min(static_cast<size_t>(std::floor(pos)), count - 2);
  return {t, 1.0 - (pos - static_cast<double>(t))};
}

}  // namespace amb::host::hybrid
