#include "host-tools/core/bearing/bearing_check.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace amb::host::bearing {

bool BearingCheckOptions::valid() const {
  return speed_uncertainty >= 0 && slip_allowance >= 0 && false_alarm_probability > 0 && min_band_kurtosis > -2 &&
         false_alarm_probability < 1 && harmonics >= 2 && floor_halfwidth_hz >= 0 && discrete_halfwidth_hz > 0 &&
         strongest_lines >= 0 && band.valid();
}

LineResult find_line(const EnvelopeSpectrum& s, double predicted_hz, double rel_tolerance,
                     const BearingCheckOptions& o) {
  LineResult r;
  r.predicted_hz = predicted_hz;
  const double df = s.df_hz;
  const auto n = static_cast<long>(s.amplitude.size());
  if (df <= 0 || n < 8) return r;
  const double half_hz = std::max(rel_tolerance * predicted_hz, 2.0 * df);
  const double floor_half_hz =
      o.floor_halfwidth_hz > 0 ? o.floor_halfwidth_hz : std::max(10.0 * half_hz, 5.0);
  const long c = std::lround(predicted_hz / df);
  const long w = std::lround(half_hz / df);
  const long fw = std::lround(floor_half_hz / df);
  if (c - w < 1 || c + w >= n) return r;
  long best = c;
  for (long k = c - w; k <= c + w; ++k)
    if (s.amplitude[static_cast<size_t>(k)] > s.amplitude[static_cast<size_t>(best)]) best = k;
  std::vector<double> floor_bins;
  floor_bins.reserve(static_cast<size_t>(2 * fw));
  for (long k = std::max(1L, c - fw); k <= std::min(n - 1, c + fw); ++k)
    if (k < c - w || k > c + w) floor_bins.push_back(s.amplitude[static_cast<size_t>(k)]);
  if (floor_bins.size() < 8) return r;
  auto mid = floor_bins.begin() + static_cast<long>(floor_bins.size() / 2);
  std::nth_element(floor_bins.begin(), mid, floor_bins.end());
  const double median = *mid;
  const double n_window = static_cast<double>(2 * w + 1);
  r.threshold = std::sqrt(std::log2(n_window / o.false_alarm_probability));
  r.peak_hz = static_cast<double>(best) * df;
  r.ratio = median > 0 ? s.amplitude[static_cast<size_t>(best)] / median : 0.0;
  if (r.ratio > r.threshold) r.found_hz = r.peak_hz;
  return r;
}

namespace {

// Local maxima of s in [f_lo, f_hi] over the median of +-floor_hz (line +-2 bins excluded).
std::vector<EnvelopeLine> strongest_lines(const EnvelopeSpectrum& s, double f_lo, double f_hi, double floor_hz,
                                          const BearingCheckOptions& o) {
  std::vector<EnvelopeLine> out;
  const auto n = static_cast<long>(s.amplitude.size());
  if (s.df_hz <= 0 || n < 16 || o.strongest_lines == 0) return out;
  const long k0 = std::max(2L, std::lround(f_lo / s.df_hz));
  const long k1 = std::min(n - 2, std::lround(f_hi / s.df_hz));
  const long fw = std::max(8L, std::lround(floor_hz / s.df_hz));
  if (k1 <= k0) return out;
  const double k = std::sqrt(std::log2(static_cast<double>(k1 - k0 + 1) / o.false_alarm_probability));
  std::vector<double> floor_bins;
  for (long c = k0; c <= k1; ++c) {
    const double a = s.amplitude[static_cast<size_t>(c)];
    if (a < s.amplitude[static_cast<size_t>(c - 1)] || a < s.amplitude[static_cast<size_t>(c + 1)]) continue;
    floor_bins.clear();
    for (long j = std::max(1L, c - fw); j <= std::min(n - 1, c + fw); ++j)
      if (std::abs(j - c) > 2) floor_bins.push_back(s.amplitude[static_cast<size_t>(j)]);
    auto mid = floor_bins.begin() + static_cast<long>(floor_bins.size() / 2);
    std::nth_element(floor_bins.begin(), mid, floor_bins.end());
    if (*mid > 0 && a / *mid > k) out.push_back({static_cast<double>(c) * s.df_hz, a / *mid});
  }
  std::sort(out.begin(), out.end(), [](const EnvelopeLine& a, const EnvelopeLine& b) { return a.ratio > b.ratio; });
  if (out.size() > static_cast<size_t>(o.strongest_lines)) out.resize(static_cast<size_t>(o.strongest_lines));
  return out;
}

double line_score(const LineResult& l) { return l.counts() ? std::log2(l.ratio / l.threshold) : 0.0; }

FamilyResult search_family(const EnvelopeSpectrum& s, double f_hz, double tol, const BearingCheckOptions& o) {
  FamilyResult fam;
  for (int h = 1; h <= o.harmonics; ++h) fam.harmonics.push_back(find_line(s, h * f_hz, tol, o));
  return fam;
}

// A line of base frequency f_hz (harmonic h) is ambiguous if its window overlaps the window of
// any harmonic of the other base frequencies.
void mark_ambiguous(FamilyResult& fam, double f_hz, double tol, const std::vector<double>& others,
                    double other_tol, int other_harmonics) {
  for (size_t i = 0; i < fam.harmonics.size(); ++i) {
    const double fh = static_cast<double>(i + 1) * f_hz;
    for (double g : others) {
      if (std::abs(g - f_hz) < 1e-9 * f_hz) continue;
      for (int k = 1; k <= other_harmonics; ++k) {
        const double gk = k * g;
        if (std::abs(fh - gk) < tol * fh + other_tol * gk) fam.harmonics[i].ambiguous = true;
      }
    }
  }
}

void finish_family(FamilyResult& fam) {
  int count = 0;
  double log_sum = 0.0;
  fam.score = 0.0;
  for (const auto& l : fam.harmonics) {
    fam.score += line_score(l);
    count += l.counts() ? 1 : 0;
    log_sum += std::log(std::max(l.ratio, 1e-12));
  }
  fam.strength = std::exp(log_sum / static_cast<double>(fam.harmonics.size()));
  fam.evidence = fam.harmonics[0].counts() && count >= 2;
}

}  // namespace

BearingCheckResult check_bearing(const std::vector<double>& x, double fs_hz, double shaft_speed_hz,
                                 const model::bearing::BearingGeometry& g, const BearingCheckOptions& o) {
  if (!(fs_hz > 0)) throw std::invalid_argument("sample rate must be > 0 Hz");
  if (!(shaft_speed_hz > 0)) throw std::invalid_argument("shaft speed must be > 0");
  if (!g.valid()) throw std::invalid_argument("invalid bearing geometry");
  if (!o.valid()) throw std::invalid_argument("invalid bearing-check options");
  BearingCheckResult r;
  r.predicted = model::bearing::defect_frequencies(g, shaft_speed_hz);
  const auto& p = r.predicted;

  BandAnalyser analyser(x, fs_hz);
  if (o.remove_discrete) r.discrete = analyser.remove_discrete_components(o.discrete_halfwidth_hz, o.false_alarm_probability);
  BandSelectionOptions bo = o.band;
  // The squared envelope of a band B wide holds modulation up to B, with SNR falling towards B:
  // ask for 2 harmonics of BPFI plus their shaft sidebands with margin, i.e. B >= 4 BPFI
  // (and >= (harmonics + 2) BPFI when more harmonics are examined).
  bo.min_bandwidth_hz = std::max(bo.min_bandwidth_hz, std::max(4, o.harmonics + 2) * p.bpfi_hz);
  r.band = analyser.select_band(bo);
  const EnvelopeSpectrum s = analyser.envelope_spectrum(r.band);

  const double tol = o.speed_uncertainty + o.slip_allowance;
  r.strongest_lines = strongest_lines(s, 1.0, 2.0 * (p.bpfi_hz + p.shaft_hz), 5.0, o);
  r.bpfo = search_family(s, p.bpfo_hz, tol, o);
  r.bpfi = search_family(s, p.bpfi_hz, tol, o);
  r.ftf = search_family(s, p.ftf_hz, tol, o);
  r.bsf = search_family(s, p.bsf_hz, tol, o);
  r.bsf2 = search_family(s, 2.0 * p.bsf_hz, tol, o);
  r.shaft = search_family(s, p.shaft_hz, o.speed_uncertainty, o);
  // Lines shared between families are evidence for none of them. The ball families are
  // checked against the race families but not against each other (2*BSF is BSF's 2nd harmonic).
  const int hmax = 8 * o.harmonics;  // shaft harmonics reach past the highest line searched
  const std::vector<double> races{p.bpfo_hz, p.bpfi_hz};
  mark_ambiguous(r.bpfo, p.bpfo_hz, tol, {p.bpfi_hz, p.bsf_hz, 2.0 * p.bsf_hz}, tol, o.harmonics);
  mark_ambiguous(r.bpfi, p.bpfi_hz, tol, {p.bpfo_hz, p.bsf_hz, 2.0 * p.bsf_hz}, tol, o.harmonics);
  mark_ambiguous(r.bsf, p.bsf_hz, tol, races, tol, o.harmonics);
  mark_ambiguous(r.bsf2, 2.0 * p.bsf_hz, tol, races, tol, o.harmonics);
  for (FamilyResult* f : {&r.bpfo, &r.bpfi, &r.bsf, &r.bsf2, &r.ftf}) {
    const double base = f->harmonics[0].predicted_hz;
    mark_ambiguous(*f, base, tol, {p.shaft_hz}, o.speed_uncertainty, hmax);
  }
  for (FamilyResult* f : {&r.bpfo, &r.bpfi, &r.bsf, &r.bsf2, &r.ftf, &r.shaft}) finish_family(*f);
  // Inner-race lines are amplitude-modulated by the shaft (the defect turns through the load
  // zone): sidebands at BPFI +- f_r count as a further confirming line.
  r.bpfi_lower_sideband = find_line(s, p.bpfi_hz - p.shaft_hz, tol, o);
  r.bpfi_upper_sideband = find_line(s, p.bpfi_hz + p.shaft_hz, tol, o);
  if (r.bpfi.harmonics[0].stands_out() && !r.bpfi.evidence &&
      (r.bpfi_lower_sideband.stands_out() || r.bpfi_upper_sideband.stands_out()))
    r.bpfi.evidence = true;
  r.bpfi.score += 0.5 * (line_score(r.bpfi_lower_sideband) + line_score(r.bpfi_upper_sideband));

  if (r.bsf.harmonics[0].stands_out()) r.found_bsf_hz = r.bsf.harmonics[0].found_hz;
  else if (r.bsf2.harmonics[0].stands_out()) r.found_bsf_hz = *r.bsf2.harmonics[0].found_hz / 2.0;
  const bool ball_evidence = r.bsf.evidence || r.bsf2.evidence;
  const double ball_score = std::max(r.bsf.score, r.bsf2.score);

  struct Candidate {
    const char* name;
    bool evidence;
    double score;
    double strength;
  };
  const double ball_strength = std::max(r.bsf.strength, r.bsf2.strength);
  const Candidate cands[] = {{"outer_race", r.bpfo.evidence, r.bpfo.score, r.bpfo.strength},
                             {"inner_race", r.bpfi.evidence, r.bpfi.score, r.bpfi.strength},
                             {"ball", ball_evidence, ball_score, ball_strength}};
  const Candidate* best = nullptr;
  const Candidate* second = nullptr;
  for (const auto& c : cands) {
    if (!c.evidence) continue;
    if (!best || c.score > best->score) {
      second = best;
      best = &c;
    } else if (!second || c.score > second->score) {
      second = &c;
    }
  }
  if (!best) {
    if (r.ftf.evidence) {
      r.verdict = "unclear";
      r.reason = "only a cage (FTF) line family stands out";
    } else {
      r.verdict = "healthy";
      r.reason = "no defect line family stands out of the envelope-spectrum floor";
    }
  } else if (second && best->score < 2.0 * second->score) {
    r.verdict = "unclear";
    r.reason = std::string("both ") + best->name + " and " + second->name + " lines stand out with similar strength";
  } else if (r.band.kurtosis < o.min_band_kurtosis) {
    r.verdict = "unclear";
    r.reason = std::string(best->name) + " lines stand out but the band is not impulsive (spectral kurtosis " +
               std::to_string(r.band.kurtosis) + " < " + std::to_string(o.min_band_kurtosis) + ")";
  } else if (best->strength <= r.shaft.strength) {
    r.verdict = "unclear";
    r.reason = std::string(best->name) +
               " lines stand out but are not stronger than the shaft-synchronous lines "
               "(envelope dominated by non-bearing modulation)";
  } else {
    r.verdict = best->name;
    r.reason = std::string(best->name) + " line family stands out (fundamental and a confirming line)";
  }
  return r;
}

}  // namespace amb::host::bearing
