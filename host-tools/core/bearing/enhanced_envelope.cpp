#include "host-tools/core/bearing/enhanced_envelope.hpp"

#include <algorithm>
#include <cmath>

#include "host-tools/core/bearing/family_score.hpp"

namespace amb::host::bearing {

std::vector<Band> ees_bands(double low_hz, double high_hz, double width_hz) {
  std::vector<Band> out;
  if (!(width_hz > 0) || !(high_hz > low_hz)) return out;
  for (double lo = low_hz; lo + width_hz <= high_hz * (1.0 + 1e-12); lo += width_hz) out.push_back(Band{lo, lo + width_hz, 0.0, 0});
  return out;
}

double log2_gamma_tail(double t, int m) {
  if (!(t > 0)) return 0.0;
  // e^-t sum_{j<m} t^j / j!, summed in logs (t can reach thousands on a strong line).
  double log_term = 0.0, log_sum = 0.0;
  for (int j = 1; j < m; ++j) {
    log_term += std::log(t / j);
    log_sum = std::max(log_sum, log_term) + std::log1p(std::exp(-std::abs(log_sum - log_term)));
  }
  return std::min(0.0, (log_sum - t) / std::log(2.0));
}

EnvelopeSpectrum enhanced_envelope_spectrum(const BandAnalyser& a, const std::vector<Band>& bands, double f_max_hz,
                                            double floor_halfwidth_hz) {
  EnvelopeSpectrum out;
  if (bands.empty()) return out;
  std::vector<double> sum_r2;
  for (const Band& b : bands) {
    const EnvelopeSpectrum s = a.envelope_spectrum(b);
    const NormalisedSpectrum ns = normalise_spectrum(s, f_max_hz, floor_halfwidth_hz, 0.0, 0);
    if (sum_r2.empty()) {
      sum_r2.assign(ns.ratio.size(), 0.0);
      out.df_hz = ns.df_hz;
    }
    for (size_t k = 0; k < sum_r2.size() && k < ns.ratio.size(); ++k) sum_r2[k] += ns.ratio[k] * ns.ratio[k];
  }
  const int m = static_cast<int>(bands.size());
  out.amplitude.resize(sum_r2.size());
  for (size_t k = 0; k < sum_r2.size(); ++k) out.amplitude[k] = std::sqrt(-log2_gamma_tail(std::log(2.0) * sum_r2[k], m));
  out.band = Band{bands.front().low_hz, bands.back().high_hz, 0.0, 0};
  return out;
}

}  // namespace amb::host::bearing
