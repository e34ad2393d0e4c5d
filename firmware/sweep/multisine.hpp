#pragma once
// One period of a low-crest multisine at exact bins of an N-sample period (leakage-free over
// whole periods): equal line amplitudes; phases from Schroeder's phi_l = -pi l (l - 1) / L,
// then lowered in crest factor by clipping iterations (clip the period at 0.8 of its peak,
// take the clipped signal's phases at the lines, repeat 150 times, keep the best). Designed at
// configure time (allocates); the loop only reads the table.
#include <cstdint>
#include <string>
#include <vector>

namespace amb::fw {

struct MultisineDesign {
  std::vector<uint32_t> bins;   ///< excited DFT bins of the period, ascending (frequency = bin * rate / N)
  std::vector<double> phases_rad;  ///< phase of each line's cosine, rad
  std::vector<float> table;     ///< one period, N samples, normalised to a peak |value| of 1
  double crest_factor = 0.0;    ///< peak / rms of the table (the excitation's crest factor)
};

/// The bins: `lines` log-spaced between ceil(f_min * N / rate) (at least 1) and
/// floor(f_max * N / rate) (below N / 2), rounded to integers, duplicates removed (fewer
/// lines when the band holds fewer bins). Empty when the band holds no bin.
std::vector<uint32_t> multisine_bins(double rate_hz, uint32_t samples_per_period, double f_min_hz, double f_max_hz,
                                     uint32_t lines);

/// Design the period. Returns "" or what is wrong (no bin in the band, N < 4).
std::string design_multisine(double rate_hz, uint32_t samples_per_period, double f_min_hz, double f_max_hz,
                             uint32_t lines, MultisineDesign& out);

}  // namespace amb::fw
