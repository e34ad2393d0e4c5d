#pragma once
// Loop-sensitivity sweep estimation (ISO 14839-3) from a SweepRecord (sweep_record.hpp), per
// excited axis and excited line:
//   S = u / e          sensitivity (e: injected, u: demand sent to the amplifier)
//   T = -u_c / e       complementary sensitivity (u_c: controller demand before the summing point)
//   G = y / u          plant (y: this axis' position reading, controller frame)
// Multisine periods are leakage-free (every line an exact bin of the period), so each recorded
// period gives one DFT value per line, X_p and Y_p (p = 1..P), with no window. Per pair (x, y):
//   H1 = sum conj(X_p) Y_p / sum |X_p|^2       (unbiased with noise on y only)
//   H2 = sum |Y_p|^2 / sum conj(Y_p) X_p       (unbiased with noise on x only)
//   coherence = |sum conj(X_p) Y_p|^2 / (sum |X_p|^2 sum |Y_p|^2)
// The reported estimate:
//   S and T: H1 with x = e (the injected signal is known exactly: no input noise);
//   G: the e-referenced ("indirect") estimate sum conj(E_p) Y_p / sum conj(E_p) U_p. In the
//      closed loop the sensor noise reaches u through the controller, so u and y carry
//      correlated noise and both H1 and H2 of y/u are biased; referencing both to the injected
//      e removes every noise uncorrelated with e. H1 and H2 of y/u are reported beside it.
// Confidence band (stated): from the period-to-period scatter. With the reported estimate h
// and the residuals r_p = Y_p - h X_p (X_p = E_p for S, T; U_p for G),
//   var(h) = sum |r_p|^2 / (P - 1) / sum |X_p|^2      (S, T; e identical every period)
//   var(h) = sum |r_p|^2 / (P - 1) / (P |mean U_p|^2)  (G, linearised ratio of means)
// and the band on |h| is |h| -+ t sqrt(var / 2) with t the Student quantile for 2 (P - 1)
// degrees of freedom at the stated level (the magnitude takes the in-phase half of a circular
// complex error). Stepped-sine records: one line per step, the same estimators over the step's
// periods. Plain computation, no I/O.
#include <complex>
#include <string>
#include <vector>

#include "host-tools/core/sweep/sweep_record.hpp"

namespace amb::host::sweep {

/// Per-period DFT values of a pair of signals at one line.
struct PeriodSpectra {
  std::vector<std::complex<double>> x, y;  ///< one value per recorded period
};

/// One transfer function at one line.
struct TransferEstimate {
  std::complex<double> h;       ///< reported estimate (see the header comment), unit of y per unit of x
  std::complex<double> h1, h2;  ///< H1 and H2 of the pair (G: of y/u)
  double coherence = 0.0;       ///< ordinary coherence of the pair (S, T: e vs u; G: u vs y), 0..1
  double sigma = 0.0;           ///< standard deviation of h (complex, E|dh|^2 = sigma^2), unit of h
  double mag_lo = 0.0, mag_hi = 0.0;  ///< confidence band on |h| at EstimateOptions::band_level
};

/// H1, H2 and the coherence of y over x from per-period spectra (at least two periods); h = H1
/// with its band (residual scatter about H1 x, noise on y) at `band_level`.
TransferEstimate h1_h2(const PeriodSpectra& s, double band_level = 0.95);

struct LineEstimate {
  double f_hz = 0.0;
  TransferEstimate s, t, g;
};

/// The sensitivity peak of one axis and its ISO 14839-3 zone.
struct PeakEstimate {
  bool found = false;           ///< false: no line reached the coherence floor
  double peak = 0.0;            ///< largest |S| over lines with S coherence >= the floor, 1
  double lo = 0.0, hi = 0.0;    ///< its confidence band, 1
  double frequency_hz = 0.0;    ///< line of the peak, Hz
  std::string zone;             ///< "A".."D" of the peak (model/analysis/closed_loop.hpp iso14839_zone)
  std::string zone_lo, zone_hi; ///< zones of the band's ends
  /// e.g. "B, 3.21 [3.15, 3.27]" (the band's zones added when they differ: "B (band B-C), ...").
  std::string statement;
};

struct AxisEstimate {
  int axis = 0;
  std::vector<LineEstimate> lines;  ///< ascending frequency
  PeakEstimate peak;
  double min_coherence_s = 0.0;     ///< lowest S coherence over the lines
};

struct EstimateOptions {
  double band_level = 0.95;         ///< two-sided confidence level of the band, 0..1
  double peak_min_coherence = 0.9;  ///< lines below this S coherence are not peak candidates
};

struct SweepEstimate {
  std::vector<AxisEstimate> axes;   ///< in the record's order
  int periods = 0;                  ///< averages per line
  std::string band_basis;           ///< how the band is computed, in words
};

/// Line frequencies of the record's plan, checked against the period: each must be an exact
/// bin k rate / N (|k - f N / rate| < 1e-6), 0 < k < N / 2. Throws std::invalid_argument naming
/// what is wrong (also for vectors of the wrong length: multisine P N samples per signal;
/// stepped sine F P N, the steps one after the other in frequencies_hz order).
std::vector<int> line_bins(const SweepRecord& r);

/// The estimates of every axis. Throws std::invalid_argument on a malformed record.
SweepEstimate estimate_sweep(const SweepRecord& r, const EstimateOptions& o = {});

/// Two-sided Student-t quantile t such that P(|T| <= t) = level for `dof` degrees of freedom
/// (Cornish-Fisher expansion about the normal quantile; dof >= 2).
double student_t_quantile(double level, double dof);

}  // namespace amb::host::sweep
