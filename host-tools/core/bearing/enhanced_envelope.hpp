#pragma once
// Enhanced envelope spectrum (EES): the envelope spectra of several adjacent bands, each
// divided by its own floor, combined bin by bin. It is the band-integrated spectral coherence
// of Antoni's cyclostationary analysis (the squared envelope spectrum of a band around f at
// cyclic frequency alpha, over the band's power, is the spectral coherence at (alpha, f) for
// alpha below the bandwidth), which Smith & Randall's successors use where one band's
// envelope is too weak: a fault's modulation spread thinly over a broad resonance adds up
// over the bands, while noise does not.
//
// Combination: in band b, bin k's ratio r_bk = amplitude / local median; under Gaussian noise
// ln 2 x r_bk^2 is a unit exponential (P(r > x) = 2^-x^2, family_score.hpp), so over M disjoint
// bands T_k = ln 2 x sum_b r_bk^2 is Gamma(M, 1) and its upper tail is exact,
// P(T > t) = e^-t sum_{j<M} t^j / j!. The EES is that p-value written as the single-band
// ratio with the same tail, r_k = sqrt(-log2 P): the family scores and their nulls
// (family_score.hpp) read it as they read one band's spectrum.
#include <vector>

#include "host-tools/core/bearing/envelope.hpp"

namespace amb::host::bearing {

/// The disjoint bands the EES combines.
/// @param low_hz, high_hz  range covered, Hz (bands lie inside it)
/// @param width_hz         width of each band, Hz (> 0); the bands are laid from low_hz up and
///                         the last one that fits ends at or below high_hz
std::vector<Band> ees_bands(double low_hz, double high_hz, double width_hz);

/// Enhanced envelope spectrum of `bands` in `a`, up to f_max_hz. Returns an EnvelopeSpectrum
/// whose amplitude is the equivalent single-band ratio (dimensionless, see above) and whose
/// band spans the first band's low edge to the last band's high edge. Empty if `bands` is.
/// @param floor_halfwidth_hz  half width of each band's floor (median) window, Hz (> 0)
EnvelopeSpectrum enhanced_envelope_spectrum(const BandAnalyser& a, const std::vector<Band>& bands, double f_max_hz,
                                            double floor_halfwidth_hz);

/// log2 of P(T > t) for T ~ Gamma(m, 1), m >= 1 integer (<= 0).
double log2_gamma_tail(double t, int m);

}  // namespace amb::host::bearing
