#pragma once
// Robust local noise floor of a log-power spectrum: the median of blocks of bins,
// interpolated linearly between block centres. A spectral line (or a chirp smeared over
// less than half a block) does not lift the floor, so "line level minus floor" is the
// line's prominence in dB. No allocation: the caller provides the scratch buffer.
#include <cstddef>
#include <span>

namespace amb::model::signal {

/// Fill floor_db[0..n) with the block-median floor of level_db[0..n), dB.
/// `block_bins` >= 4; `scratch` must hold at least block_bins values;
/// `block_medians` at least ceil(n / block_bins) values.
void block_median_floor(std::span<const double> level_db, size_t block_bins,
                        std::span<double> scratch, std::span<double> block_medians,
                        std::span<double> floor_db);

}  // namespace amb::model::signal
