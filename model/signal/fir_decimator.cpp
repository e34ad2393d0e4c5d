#include "model/signal/fir_decimator.hpp"

#include <cmath>
#include <numbers>

namespace amb::model::signal {

std::string FirDecimatorOptions::validate() const {
  if (!(input_rate_hz > 0.0 && std::isfinite(input_rate_hz)))
    return "input_rate_hz must be > 0 Hz, got " + std::to_string(input_rate_hz);
  if (factor < 1 || factor > 4096) return "factor must be in [1, 4096], got " + std::to_string(factor);
  if (!(cutoff_fraction > 0.1 && cutoff_fraction <= 0.95))
    return "cutoff_fraction must be in (0.1, 0.95], got " + std::to_string(cutoff_fraction);
  if (taps_per_factor < 4 || taps_per_factor > 64)
    return "taps_per_factor must be in [4, 64], got " + std::to_string(taps_per_factor);
  return {};
}

std::string FirDecimator::configure(const FirDecimatorOptions& options) {
  if (std::string err = options.validate(); !err.empty()) return err;
  options_ = options;
  const size_t n = options.factor == 1 ? 1 : options.taps_per_factor * options.factor + 1;
  taps_.assign(n, 0.0);
  if (n == 1) {
    taps_[0] = 1.0;
  } else {
    // Cut-off in cycles per input sample.
    const double fc = 0.5 * options.cutoff_fraction / static_cast<double>(options.factor);
    const double mid = 0.5 * static_cast<double>(n - 1);
    double sum = 0.0;
    for (size_t i = 0; i < n; ++i) {
      const double m = static_cast<double>(i) - mid;
      const double sinc = m == 0.0 ? 2.0 * fc : std::sin(2.0 * std::numbers::pi * fc * m) / (std::numbers::pi * m);
      const double x = 2.0 * std::numbers::pi * static_cast<double>(i) / static_cast<double>(n - 1);
      const double w = 0.42 - 0.5 * std::cos(x) + 0.08 * std::cos(2.0 * x);
      taps_[i] = sinc * w;
      sum += taps_[i];
    }
    for (double& t : taps_) t /= sum;  // unit DC gain
  }
  history_.assign(2 * n, 0.0);
  reset();
  return {};
}

void FirDecimator::reset() {
  for (double& v : history_) v = 0.0;
  pos_ = 0;
  phase_ = 0;
}

double FirDecimator::delay_s() const {
  return 0.5 * static_cast<double>(taps_.size() - 1) / options_.input_rate_hz;
}

bool FirDecimator::push(double x, double& out) {
  const size_t n = taps_.size();
  if (n == 0) return false;
  // Write twice so that history_[pos_ .. pos_+n) is always the last n samples, oldest first.
  history_[pos_] = x;
  history_[pos_ + n] = x;
  pos_ = pos_ + 1 == n ? 0 : pos_ + 1;
  if (++phase_ < options_.factor) return false;
  phase_ = 0;
  const double* h = history_.data() + pos_;
  double acc = 0.0;
  for (size_t i = 0; i < n; ++i) acc += taps_[i] * h[i];
  out = acc;
  return true;
}

}  // namespace amb::model::signal
