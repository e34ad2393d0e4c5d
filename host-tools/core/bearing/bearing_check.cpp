#include "host-tools/core/bearing/bearing_check.hpp"

#include <algorithm>
#include <array>
#include <cstdio>
#include <cmath>
#include <stdexcept>

namespace amb::host::bearing {

bool BearingCheckOptions::valid() const {
  return speed_uncertainty >= 0 && slip_allowance >= 0 && false_alarm_probability > 0 && min_band_kurtosis > -2 &&
         family_false_alarm > 0 && family_false_alarm < 1 && line_p > 0 && line_p < 1 && dominance >= 1 &&
         impulsive_sigmas >= 0 &&
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

}  // namespace

namespace {

enum Fam { kOuter = 0, kInner = 1, kBall = 2, kCage = 3, kFamilies = 4 };

struct FamilyDef {
  double base_hz = 0.0;
  std::vector<FamilyLine> lines;
};

// Expected lines of each family. Harmonics m = 1..H of the base; inner race: +-f_r sidebands of
// its first two harmonics (the defect turns through the load zone once per revolution); ball:
// BSF and 2 BSF are both fundamentals (a defective ball strikes both races per spin), 4 BSF,
// and 2 BSF +- FTF (the ball goes round with the cage through the load zone).
std::array<FamilyDef, kFamilies> family_defs(const model::bearing::DefectFrequencies& p, const BearingCheckOptions& o) {
  std::array<FamilyDef, kFamilies> d;
  auto harmonics = [&](FamilyDef& f, double base, int h_max) {
    f.base_hz = base;
    for (int h = 1; h <= h_max; ++h) f.lines.push_back({static_cast<double>(h), 0.0, 0.0, h == 1, false, std::to_string(h) + "x"});
  };
  harmonics(d[kOuter], p.bpfo_hz, o.harmonics);
  harmonics(d[kInner], p.bpfi_hz, o.harmonics);
  for (int h = 1; h <= 2; ++h)
    for (int sgn : {-1, 1})
      d[kInner].lines.push_back({static_cast<double>(h), sgn * p.shaft_hz, o.speed_uncertainty, false, false,
                                 std::to_string(h) + (sgn < 0 ? "x-fr" : "x+fr")});
  d[kBall].base_hz = p.bsf_hz;
  for (int h : {1, 2, 4}) d[kBall].lines.push_back({static_cast<double>(h), 0.0, 0.0, h <= 2, false, std::to_string(h) + "x"});
  for (int sgn : {-1, 1})
    d[kBall].lines.push_back({2.0, sgn * p.ftf_hz, o.speed_uncertainty + o.slip_allowance, false, false,
                              sgn < 0 ? "2x-ftf" : "2x+ftf"});
  harmonics(d[kCage], p.ftf_hz, o.harmonics);
  return d;
}

// Lines of family `a` that share their search window with a harmonic line of another family
// are evidence for neither (6205: 3 BPFO ~ 2 BPFI). The cage family is not a competitor of the
// race families here: BPFO = Z x FTF by kinematics.
void mark_shared_lines(std::array<FamilyDef, kFamilies>& d, double tol, double shaft_hz, double shaft_tol) {
  for (int a = 0; a < kFamilies; ++a) {
    // A fundamental whose whole search range can hold a shaft harmonic is confounded with the
    // shaft (6203: BSF = 1.994 f_r): no delta can make it evidence.
    for (auto& l : d[static_cast<size_t>(a)].lines) {
      if (!l.fundamental || l.offset_hz != 0.0) continue;
      const double pos = l.multiple * d[static_cast<size_t>(a)].base_hz;
      const double k = std::round(pos / shaft_hz);
      if (k >= 1 && std::abs(pos - k * shaft_hz) < tol * pos + shaft_tol * k * shaft_hz) l.ambiguous = true;
    }
    for (auto& l : d[static_cast<size_t>(a)].lines) {
      const double pos = l.multiple * d[static_cast<size_t>(a)].base_hz + l.offset_hz;
      const double half = tol * l.multiple * d[static_cast<size_t>(a)].base_hz;
      for (int b = 0; b < kFamilies; ++b) {
        if (b == a || (a == kCage) != (b == kCage)) continue;
        for (const auto& m : d[static_cast<size_t>(b)].lines) {
          if (m.offset_hz != 0.0) continue;
          const double q = m.multiple * d[static_cast<size_t>(b)].base_hz;
          if (std::abs(pos - q) < half + tol * q) l.ambiguous = true;
        }
      }
    }
    // Sidebands of a shared harmonic are shared too (6205: 2 BPFI +- f_r = 3 BPFO +- f_r).
    auto& lines = d[static_cast<size_t>(a)].lines;
    for (auto& l : lines) {
      if (l.offset_hz == 0.0) continue;
      for (const auto& c : lines)
        if (c.offset_hz == 0.0 && c.multiple == l.multiple && c.ambiguous) l.ambiguous = true;
    }
  }
}

double strongest_fundamental(const FamilyTest& t, const std::vector<FamilyLine>& lines) {
  double r = 0.0;
  for (size_t i = 0; i < lines.size() && i < t.lines.size(); ++i)
    if (lines[i].fundamental && !t.lines[i].ambiguous) r = std::max(r, t.lines[i].ratio);
  return r;
}

// Fisher p-value of the counting lines (no delta re-search), corrected like the test.
double corrected_log10_p(const FamilyTest& t, double log10_tests) {
  double x = 0.0;
  int m = 0;
  for (const auto& l : t.lines) {
    if (l.ambiguous) continue;
    x += -2.0 * std::log(std::max(l.p_value, 1e-300));
    ++m;
  }
  const double lp = m > 0 ? log_chi2_sf_even(x, m) / std::log(10.0) : 0.0;
  return std::min(0.0, lp + std::log10(t.trials) + log10_tests);
}

bool detected(const FamilyResult& f, const BearingCheckOptions& o) {
  return f.log10_p_corrected < std::log10(o.family_false_alarm) && f.test.fundamental_present &&
         f.test.lines_present >= 2;
}

void recount(FamilyResult& f, const std::vector<FamilyLine>& lines, const BearingCheckOptions& o) {
  f.test.lines_present = 0;
  f.test.fundamental_present = false;
  for (size_t i = 0; i < lines.size(); ++i) {
    if (f.test.lines[i].ambiguous || !(f.test.lines[i].p_value < o.line_p)) continue;
    ++f.test.lines_present;
    if (lines[i].fundamental) f.test.fundamental_present = true;
  }
}

// Positions of the stronger family's pattern: harmonics 1..2H (+- k f_r, k <= 3, inner race;
// +- k FTF, k <= 2, ball), at its fitted delta.
std::vector<std::pair<double, double>> pattern(int fam, const FamilyResult& f, const model::bearing::DefectFrequencies& p,
                                               const BearingCheckOptions& o) {
  std::vector<std::pair<double, double>> out;  // position, extra tolerance Hz
  const double base = f.test.base_hz * (1.0 + f.test.delta);
  const int h_max = 2 * o.harmonics + 2;
  for (int h = 1; h <= h_max; ++h) {
    const double c = h * base;
    out.emplace_back(c, 0.0);
    if (fam == kInner)
      for (int k = 1; k <= 3; ++k)
        for (int sgn : {-1, 1}) out.emplace_back(c + sgn * k * p.shaft_hz, o.speed_uncertainty * k * p.shaft_hz);
    if (fam == kBall)
      for (int k = 1; k <= 2; ++k)
        for (int sgn : {-1, 1})
          out.emplace_back(c + sgn * k * p.ftf_hz, (o.speed_uncertainty + o.slip_allowance) * k * p.ftf_hz);
  }
  return out;
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
  // ask for the harmonics of BPFI plus their shaft sidebands with margin, i.e. B >= 4 BPFI
  // (and >= (harmonics + 2) BPFI when more harmonics are examined).
  bo.min_bandwidth_hz = std::max(bo.min_bandwidth_hz, std::max(4, o.harmonics + 2) * p.bpfi_hz);
  std::vector<Band> grid = analyser.band_grid(bo);
  if (grid.empty()) {  // every band tonal: analyse the whole guarded spectrum, say so by its SK
    const double hi = (1.0 - bo.top_guard_fraction) * 0.5 * fs_hz;
    grid.push_back(Band{0.0, hi, analyser.band_kurtosis(0.0, hi), 0});
  }
  r.bands_tried = grid.size();
  r.log10_tests = std::log10(static_cast<double>(grid.size()) * static_cast<double>(kFamilies));

  const double tol = o.speed_uncertainty + o.slip_allowance;
  auto defs = family_defs(p, o);
  mark_shared_lines(defs, tol, p.shaft_hz, o.speed_uncertainty);
  FamilyTestOptions to;
  to.tolerance = tol;
  to.line_p = o.line_p;
  to.floor_halfwidth_hz = o.floor_halfwidth_hz;
  to.shaft_hz = p.shaft_hz;
  to.shaft_tolerance = o.speed_uncertainty;

  // Per family: the most significant band among the impulsive ones (verdict) and among all
  // bands (to say "lines without impacts").
  std::array<FamilyResult, kFamilies> fam, any;
  std::array<bool, kFamilies> have{}, have_any{};
  for (const Band& b : grid) {
    const EnvelopeSpectrum s = analyser.envelope_spectrum(b);
    const bool impulsive = b.kurtosis > o.impulsive_sigmas * analyser.kurtosis_standard_error(b.high_hz - b.low_hz);
    for (int f = 0; f < kFamilies; ++f) {
      const auto& d = defs[static_cast<size_t>(f)];
      FamilyTest t = test_family(s, d.base_hz, d.lines, to);
      const auto k = static_cast<size_t>(f);
      if (!have_any[k] || t.log10_p < any[k].test.log10_p) {
        have_any[k] = true;
        any[k].test = t;
        any[k].band = b;
      }
      // The cage comb is an explanation, not a verdict: its best band need not be impulsive.
      if ((impulsive || f == kCage) && (!have[k] || t.log10_p < fam[k].test.log10_p)) {
        have[k] = true;
        fam[k].test = std::move(t);
        fam[k].band = b;
      }
    }
  }
  auto finish = [&](FamilyResult& cur, int f, bool had) {
    const auto& d = defs[static_cast<size_t>(f)];
    cur.line_labels.clear();
    for (const auto& l : d.lines) cur.line_labels.push_back(l.label);
    if (!had) {  // no impulsive band at all: nothing to test
      cur.test = FamilyTest{};
      cur.test.base_hz = d.base_hz;
      cur.test.lines.resize(d.lines.size());
      for (size_t i = 0; i < d.lines.size(); ++i) cur.test.lines[i].ambiguous = d.lines[i].ambiguous;
      cur.band = grid.front();
    }
    cur.log10_p_corrected = std::min(0.0, cur.test.log10_p + r.log10_tests);
    cur.score = -cur.log10_p_corrected;
    cur.strength = strongest_fundamental(cur.test, d.lines);
    cur.evidence = had && detected(cur, o);
  };
  for (int f = 0; f < kFamilies; ++f) {
    finish(fam[static_cast<size_t>(f)], f, have[static_cast<size_t>(f)]);
    finish(any[static_cast<size_t>(f)], f, have_any[static_cast<size_t>(f)]);
  }
  // Cage comb: inner-race and ball lines on its teeth are the comb's.
  const double df = static_cast<double>(fs_hz) / static_cast<double>(analyser.length());
  const bool cage = fam[kCage].evidence;
  if (cage) {
    const double ftf = fam[kCage].test.base_hz * (1.0 + fam[kCage].test.delta);
    for (auto* set : {&fam, &any})
      for (int f : {kInner, kBall}) {
        auto& cur = (*set)[static_cast<size_t>(f)];
        const auto& d = defs[static_cast<size_t>(f)];
        int n_explained = 0;
        for (auto& l : cur.test.lines) {
          if (l.ambiguous || !(l.ratio > 0)) continue;
          const double n = std::round(l.hz / ftf);
          // the fitted FTF is good to about a bin at its 3rd harmonic: n/3 bins at tooth n
          if (n >= 1 && std::abs(l.hz - n * ftf) <= (2.0 + n / 3.0) * df) {
            l.ambiguous = true;
            ++n_explained;
          }
        }
        if (n_explained == 0) continue;
        cur.explained_lines += n_explained;
        cur.log10_p_corrected = corrected_log10_p(cur.test, r.log10_tests);
        cur.score = -cur.log10_p_corrected;
        recount(cur, d.lines, o);
        cur.strength = strongest_fundamental(cur.test, d.lines);
        cur.evidence = detected(cur, o);
      }
  }
  // Outer race inside a cage comb: BPFO = Z x FTF, so cage modulation (a ball going round with
  // the cage, a cage fault) puts a tooth on BPFO too. An outer-race defect gives the teeth at
  // multiples of Z only: its fundamental must stand `dominance` x above the neighbouring teeth
  // (Z-2, Z-1, Z+1, Z+2) in its own band and above the comb's first teeth (1..3 FTF);
  // otherwise it is a tooth of the comb.
  if (cage && fam[kOuter].evidence) {
    const double ftf = fam[kCage].test.base_hz * (1.0 + fam[kCage].test.delta);
    const EnvelopeSpectrum s = analyser.envelope_spectrum(fam[kOuter].band);
    std::vector<FamilyLine> teeth;
    const int z = g.ball_count;
    for (int n : {z - 2, z - 1, z + 1, z + 2})
      if (n >= 1) teeth.push_back({static_cast<double>(n), 0.0, 0.0, false, false, std::to_string(n) + "ftf"});
    FamilyTestOptions ct = to;
    ct.shaft_hz = 0.0;
    ct.tolerance = 2.0 * df / (static_cast<double>(z + 2) * ftf);  // fitted FTF: a couple of bins
    const FamilyTest comb = test_family(s, ftf, teeth, ct);
    // ... and above the comb's own first teeth (1..3 FTF, in the cage family's band).
    double tooth = fam[kCage].strength;
    for (const auto& l : fam[kCage].test.lines) tooth = std::max(tooth, l.ambiguous ? 0.0 : l.ratio);
    for (const auto& l : comb.lines) tooth = std::max(tooth, l.ratio);
    r.cage_teeth_ratio = tooth;
    if (fam[kOuter].strength < o.dominance * tooth) {
      fam[kOuter].evidence = false;
      r.outer_in_cage_comb = true;
    }
  }
  for (int f : {kOuter, kInner, kBall}) {
    auto& cur = fam[static_cast<size_t>(f)];
    const auto& a = any[static_cast<size_t>(f)];
    cur.significant_without_impacts = !cur.evidence && detected(a, o) && !(f == kOuter && r.outer_in_cage_comb);
    if (cur.significant_without_impacts) {  // report where the lines are
      cur.band = a.band;
      cur.test = a.test;
      cur.score = a.score;
      cur.log10_p_corrected = a.log10_p_corrected;
      cur.strength = a.strength;
      cur.explained_lines = a.explained_lines;
    }
  }

  // Explain away: lines of a weaker detected family that sit on the stronger family's pattern.
  const int defects[] = {kOuter, kInner, kBall};
  std::vector<int> order(std::begin(defects), std::end(defects));
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return fam[static_cast<size_t>(a)].score > fam[static_cast<size_t>(b)].score;
  });
  for (size_t i = 0; i < order.size(); ++i) {
    const auto& strong = fam[static_cast<size_t>(order[i])];
    if (!strong.evidence) continue;
    const auto pat = pattern(order[i], strong, p, o);
    for (size_t j = i + 1; j < order.size(); ++j) {
      auto& weak = fam[static_cast<size_t>(order[j])];
      const auto& d = defs[static_cast<size_t>(order[j])];
      for (auto& l : weak.test.lines) {
        if (l.ambiguous || !(l.ratio > 0)) continue;
        for (const auto& [c, extra] : pat)
          if (std::abs(l.hz - c) <= 2.0 * df + extra) {
            l.ambiguous = true;
            ++weak.explained_lines;
            break;
          }
      }
      if (weak.explained_lines > 0) {
        weak.log10_p_corrected = corrected_log10_p(weak.test, r.log10_tests);
        weak.score = -weak.log10_p_corrected;
        recount(weak, d.lines, o);
        weak.strength = strongest_fundamental(weak.test, d.lines);
        weak.evidence = detected(weak, o);
      }
    }
  }

  // Legacy per-line view (display, found_hz) in each family's band.
  auto legacy = [&](FamilyResult& f, double base) {
    const EnvelopeSpectrum s = analyser.envelope_spectrum(f.band);
    for (int h = 1; h <= o.harmonics; ++h) f.harmonics.push_back(find_line(s, h * base, tol, o));
  };
  r.bpfo = fam[kOuter];
  r.bpfi = fam[kInner];
  r.bsf = fam[kBall];
  r.ftf = fam[kCage];
  legacy(r.bpfo, p.bpfo_hz);
  legacy(r.bpfi, p.bpfi_hz);
  legacy(r.bsf, p.bsf_hz);
  legacy(r.ftf, p.ftf_hz);
  r.bsf2.band = r.bsf.band;
  legacy(r.bsf2, 2.0 * p.bsf_hz);
  {
    const EnvelopeSpectrum s = analyser.envelope_spectrum(r.bpfi.band);
    r.bpfi_lower_sideband = find_line(s, p.bpfi_hz - p.shaft_hz, tol, o);
    r.bpfi_upper_sideband = find_line(s, p.bpfi_hz + p.shaft_hz, tol, o);
    r.shaft.band = r.bpfi.band;
    for (int h = 1; h <= o.harmonics; ++h) r.shaft.harmonics.push_back(find_line(s, h * p.shaft_hz, o.speed_uncertainty, o));
  }
  // Found frequencies: the detected family's fitted fundamental, else a legacy line that stands out.
  auto fitted = [](const FamilyResult& f, size_t line) -> std::optional<double> {
    if (f.evidence && line < f.test.lines.size() && f.test.lines[line].p_value < 0.5) return f.test.lines[line].hz;
    return std::nullopt;
  };
  if (auto v = fitted(r.bpfo, 0)) r.bpfo.harmonics[0].found_hz = v;
  if (auto v = fitted(r.bpfi, 0)) r.bpfi.harmonics[0].found_hz = v;
  if (auto v = fitted(r.ftf, 0)) r.ftf.harmonics[0].found_hz = v;
  if (r.bsf.evidence) {
    r.found_bsf_hz = r.bsf.test.base_hz * (1.0 + r.bsf.test.delta);
  } else if (r.bsf.harmonics[0].stands_out()) {
    r.found_bsf_hz = r.bsf.harmonics[0].found_hz;
  } else if (r.bsf2.harmonics[0].stands_out()) {
    r.found_bsf_hz = *r.bsf2.harmonics[0].found_hz / 2.0;
  }
  const auto strongest_band = [&]() {
    const FamilyResult* b = &r.bpfo;
    for (const FamilyResult* f : {&r.bpfi, &r.bsf}) if (f->score > b->score) b = f;
    return b->band;
  };

  struct Candidate {
    const char* name;
    const FamilyResult* f;
  };
  const Candidate cands[] = {{"outer_race", &r.bpfo}, {"inner_race", &r.bpfi}, {"ball", &r.bsf}};
  const Candidate* best = nullptr;
  const Candidate* second = nullptr;
  for (const auto& c : cands) {
    if (!c.f->evidence) continue;
    if (!best || c.f->score > best->f->score) {
      second = best;
      best = &c;
    } else if (!second || c.f->score > second->f->score) {
      second = &c;
    }
  }
  char buf[640];
  const FamilyResult* silent = nullptr;  // significant, but only without impacts
  const char* silent_name = "";
  for (const auto& c : cands)
    if (c.f->significant_without_impacts && (!silent || c.f->score > silent->score)) {
      silent = c.f;
      silent_name = c.name;
    }
  if (!best) {
    r.band = strongest_band();
    if (r.outer_in_cage_comb) {
      r.verdict = "unclear";
      r.band = r.bpfo.band;
      std::snprintf(buf, sizeof buf,
                    "BPFO lines are significant (fundamental %.1fx floor) but are teeth of a cage comb n x FTF "
                    "(neighbouring teeth up to %.1fx): cage modulation (a ball fault going round with the cage, or "
                    "the cage) and an outer-race defect cannot be told apart; the ball lines BSF, 2 BSF sit on "
                    "cage teeth too",
                    r.bpfo.strength, r.cage_teeth_ratio);
      r.reason = buf;
    } else if (silent) {
      r.verdict = "unclear";
      r.band = silent->band;
      std::snprintf(buf, sizeof buf,
                    "%s lines are significant (p = 1e-%.1f, fundamental %.1fx floor) but only in bands that are not "
                    "impulsive (best %.0f-%.0f Hz, spectral kurtosis %.3f <= %.1f standard errors): periodic "
                    "modulation without impacts is not claimed as a localised defect",
                    silent_name, silent->score, silent->strength, silent->band.low_hz, silent->band.high_hz,
                    silent->band.kurtosis, o.impulsive_sigmas);
      r.reason = buf;
    } else if (r.ftf.evidence) {
      r.verdict = "unclear";
      r.band = r.ftf.band;
      r.reason = "only a cage (FTF) line family stands out";
    } else {
      r.verdict = "healthy";
      std::snprintf(buf, sizeof buf,
                    "no defect line family is significant at the record's false-alarm rate %.0e (%zu bands x %d families tried)",
                    o.family_false_alarm, r.bands_tried, static_cast<int>(kFamilies));
      r.reason = buf;
    }
  } else {
    r.band = best->f->band;
    const bool dominant = !second || best->f->score >= o.dominance * second->f->score ||
                          best->f->strength >= o.dominance * second->f->strength;
    if (!dominant) {
      r.verdict = "unclear";
      std::snprintf(buf, sizeof buf,
                    "both %s (significance %.1f, fundamental %.1fx floor) and %s (%.1f, %.1fx) families are detected; "
                    "neither dominates by %.1fx",
                    best->name, best->f->score, best->f->strength, second->name, second->f->score, second->f->strength,
                    o.dominance);
      r.reason = buf;
    } else {
      r.verdict = best->name;
      std::snprintf(buf, sizeof buf,
                    "%s family detected: p = 1e-%.1f after correction for %zu bands x %d families (false-alarm rate %.0e), "
                    "%d lines present, fundamental %.1fx floor%s",
                    best->name, best->f->score, r.bands_tried, static_cast<int>(kFamilies), o.family_false_alarm,
                    best->f->test.lines_present, best->f->strength,
                    second ? (std::string("; dominates ") + second->name).c_str() : "");
      r.reason = buf;
    }
  }
  r.strongest_lines = strongest_lines(analyser.envelope_spectrum(r.band), 1.0, 2.0 * (p.bpfi_hz + p.shaft_hz), 5.0, o);
  return r;
}

}  // namespace amb::host::bearing
