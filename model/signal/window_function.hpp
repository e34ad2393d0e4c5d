#pragma once
// Analysis windows for the short-time Fourier transform.
#include <span>
#include <string_view>

namespace amb::model::signal {

/// Window shape applied to each STFT frame.
enum class WindowType {
  kRectangular,
  kHann,
  kHamming,   ///< seed 003 default (0.54 - 0.46 cos)
  kBlackman,
};

/// Name of the window ("rectangular", "hann", "hamming", "blackman").
std::string_view window_name(WindowType type);

/// Parse a window name (as returned by window_name). Returns false if unknown.
bool parse_window(std::string_view name, WindowType& type);

/// Fill `w` (length L >= 2, samples) with the symmetric window of the given type.
/// Does not allocate.
void fill_window(WindowType type, std::span<double> w);

/// Half-width of the window's main lobe, in multiples of 1/T (T = window duration, s):
/// 1 rectangular, 2 Hann/Hamming, 3 Blackman. A line closer than this to DC (after
/// demeaning) or to another line cannot be resolved.
double main_lobe_half_width_bins(WindowType type);

}  // namespace amb::model::signal
