#include "host-tools/core/bearing/bearing_check.hpp"

#include "host-tools/core/bearing/enhanced_envelope.hpp"
#include "host-tools/core/bearing/line_family.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace amb::host::bearing {

bool BearingCheckOptions::valid() const {
  return slip_tolerance > 0 && slip_tolerance <= 0.1 && speed_range > 0 && speed_range <= 0.2 && harmonics >= 2 &&
         record_false_alarm > 0 && record_false_alarm < 1 && line_p > 0 && line_p < 1 && floor_halfwidth_hz > 0 &&
         shaft_exclude_bins >= 0 && comb_dominance >= 1 && false_alarm_probability > 0 && false_alarm_probability < 1 && band.valid() &&
         discrete_halfwidth_hz > 0 && discrete_false_alarm > 0 && discrete_false_alarm < 1 &&
         std::all_of(null.begin(), null.end(), [](const NullFit& f) { return f.scale > 0 && std::isfinite(f.median); }) &&
         raw_cage_min_surrogates >= 8;
}

std::array<NullFit, 4> BearingCheckOptions::default_nulls() {
  // Measured: tests/bearing/null_calibration.cpp (docs/bearing.md "Calibration").
  std::array<NullFit, 4> n;
  // {draws, median, q90, q99, scale} of each family's score (bpfo, bpfi, ball, ftf).
  n[0] = {498, 1.710, 3.013, 5.712, 1.023};
  n[1] = {284, 1.852, 3.150, 4.077, 0.806};
  n[2] = {394, 1.248, 2.578, 4.252, 0.826};
  n[3] = {1544, 0.709, 1.701, 2.960, 0.753};
  return n;
}

const FamilyResult& BearingCheckResult::family(const std::string& name) const {
  for (const auto& f : families)
    if (f.name == name) return f;
  throw std::invalid_argument("no family '" + name + "'");
}

LineResult find_line(const EnvelopeSpectrum& s, double predicted_hz, double rel_tolerance,
                     const BearingCheckOptions& o) {
  LineResult r;
  r.predicted_hz = predicted_hz;
  const double df = s.df_hz;
  const auto n = static_cast<long>(s.amplitude.size());
  if (df <= 0 || n < 8) return r;
  const double half_hz = std::max(rel_tolerance * predicted_hz, 2.0 * df);
  const double floor_half_hz = std::max(10.0 * half_hz, o.floor_halfwidth_hz);
  const long c = std::lround(predicted_hz / df);
  const long w = std::lround(half_hz / df);
  const long fw = std::lround(floor_half_hz / df);
  if (c - w < 1 || c + w >= n) return r;
  long best = c;
  for (long k = c - w; k <= c + w; ++k)
    if (s.amplitude[static_cast<size_t>(k)] > s.amplitude[static_cast<size_t>(best)]) best = k;
  std::vector<double> floor_bins;
  for (long k = std::max(1L, c - fw); k <= std::min(n - 1, c + fw); ++k)
    if (k < c - w || k > c + w) floor_bins.push_back(s.amplitude[static_cast<size_t>(k)]);
  if (floor_bins.size() < 8) return r;
  auto mid = floor_bins.begin() + static_cast<long>(floor_bins.size() / 2);
  std::nth_element(floor_bins.begin(), mid, floor_bins.end());
  const double median = *mid;
  r.threshold = std::sqrt(std::log2(static_cast<double>(2 * w + 1) / o.false_alarm_probability));
  r.peak_hz = static_cast<double>(best) * df;
  r.ratio = median > 0 ? s.amplitude[static_cast<size_t>(best)] / median : 0.0;
  if (r.ratio > r.threshold) r.found_hz = r.peak_hz;
  return r;
}

namespace {

enum Fam { kOuter = 0, kInner = 1, kBall = 2, kCage = 3, kFamilies = 4 };
constexpr const char* k_names[kFamilies] = {"bpfo", "bpfi", "ball", "ftf"};
constexpr const char* k_verdicts[kFamilies] = {"outer_race", "inner_race", "ball", "unclear"};

struct Template {
  double base_hz = 0.0;
  std::vector<TemplateLine> lines;
};

// Step 4's templates at the refined speed. Sideband offsets are exact multiples of the refined
// shaft frequency (inner race: the defect turns through the load zone once per revolution); the
// ball's FTF sidebands allow the cage's own slip (slip_tolerance of FTF).
std::array<Template, kFamilies> templates(const model::bearing::DefectFrequencies& p, double df_hz,
                                          const BearingCheckOptions& o) {
  std::array<Template, kFamilies> t;
  auto harmonics = [&](Template& f, double base) {
    f.base_hz = base;
    for (int h = 1; h <= o.harmonics; ++h) f.lines.push_back({double(h), 0.0, 1, h == 1, std::to_string(h) + "x"});
  };
  harmonics(t[kOuter], p.bpfo_hz);
  harmonics(t[kInner], p.bpfi_hz);
  for (int h = 1; h <= 2; ++h)
    for (int sgn : {-1, 1})
      t[kInner].lines.push_back({double(h), sgn * p.shaft_hz, 1, false, std::to_string(h) + (sgn < 0 ? "x-fr" : "x+fr")});
  t[kBall].base_hz = p.bsf_hz;
  // The ball defect strikes both races once per ball spin: 2 BSF is its fundamental (Smith &
  // Randall); BSF itself is scored but does not stand for the family (6200/6203: BSF ~ 2 f_r).
  for (int h : {1, 2, 4}) t[kBall].lines.push_back({double(h), 0.0, 1, h == 2, std::to_string(h) + "x"});
  const int cage_jitter = 1 + static_cast<int>(std::lround(o.slip_tolerance * p.ftf_hz / df_hz));
  for (int sgn : {-1, 1})
    t[kBall].lines.push_back({2.0, sgn * p.ftf_hz, cage_jitter, false, sgn < 0 ? "2x-ftf" : "2x+ftf"});
  harmonics(t[kCage], p.ftf_hz);
  return t;
}

// Kinematic lines of every family with the modulation sidebands a defect puts around them
// (races: +-k f_r, k <= 5; ball: 2h BSF +- k FTF, k <= 3): surrogate bases must not sit on
// them, or the null would be measured on the defect's own pattern.
std::vector<double> kinematic_lines(const model::bearing::DefectFrequencies& p) {
  std::vector<double> out;
  for (int h = 1; h <= 6; ++h)
    for (double b : {p.bsf_hz, p.ftf_hz}) out.push_back(h * b);
  for (int h = 1; h <= 4; ++h)
    for (double b : {p.bpfo_hz, p.bpfi_hz})
      for (int k = -5; k <= 5; ++k) out.push_back(h * b + k * p.shaft_hz);
  for (int h = 1; h <= 2; ++h)
    for (int k = -3; k <= 3; ++k) out.push_back(2.0 * h * p.bsf_hz + k * p.ftf_hz);
  return out;
}

// The cage family in the raw signal's envelope over the two narrowest levels of the kurtogram
// grid (BearingCheckOptions::cage_modulation_as_ball (b)). Tonal bands are kept: a discrete
// carrier modulated at FTF is what is looked for. Raw envelopes hold the beats of the record's
// own tones, which no calibration record shares, so the null is the record's own: the cage
// template at surrogate bases in every scanned band, its tail fitted (fit_null).
void scan_raw_cage(const BandAnalyser& raw, BandSelectionOptions bo, const Template& t, double f_max, double shaft_hz,
                   double tol, const std::vector<double>& forbidden, const BearingCheckOptions& o, RawCageScan& out) {
  bo.tonal_sigmas = 0.0;
  const auto grid = raw.band_grid(bo);
  int finest = -1;
  for (const auto& b : grid) finest = std::max(finest, b.level);
  out.run = true;
  std::vector<TemplateScore> scores;
  std::vector<Band> bands;
  for (const auto& b : grid) {
    if (b.level < finest - 1) continue;
    const NormalisedSpectrum ns =
        normalise_spectrum(raw.envelope_spectrum(b), f_max, o.floor_halfwidth_hz, shaft_hz, o.shaft_exclude_bins);
    scores.push_back(score_template(ns, t.base_hz, t.lines, tol, o.line_p));
    bands.push_back(b);
    const auto d = surrogate_scores(ns, t.base_hz, t.lines, tol, forbidden, true);
    out.surrogates.insert(out.surrogates.end(), d.begin(), d.end());
  }
  out.bands = bands.size();
  out.null = fit_null(out.surrogates);
  if (out.bands == 0 || out.null.samples < o.raw_cage_min_surrogates) return;
  size_t best = 0;
  for (size_t i = 1; i < scores.size(); ++i)
    if (scores[i].score > scores[best].score) best = i;
  out.score = scores[best].score;
  out.band = bands[best];
  out.lines = std::move(scores[best]);
  out.log10_p = out.null.log10_p(out.score);
  out.threshold_log10_p = std::log10(o.record_false_alarm / static_cast<double>(out.bands));
  out.threshold_score = out.null.score_at(out.threshold_log10_p);
  out.detected = out.log10_p < out.threshold_log10_p && out.lines.fundamental_present;
}

char buf[512];
std::string fmt_p(double log10_p) {
  std::snprintf(buf, sizeof buf, "%.1f", log10_p);
  return buf;
}

}  // namespace

BearingCheckResult check_bearing(const std::vector<double>& x, double fs_hz, double shaft_speed_hz,
                                 const model::bearing::BearingGeometry& g, const BearingCheckOptions& o) {
  if (!std::isfinite(fs_hz) || !(fs_hz > 0)) throw std::invalid_argument("sample rate must be a finite number > 0 Hz");
  if (!std::isfinite(shaft_speed_hz) || !(shaft_speed_hz > 0))
    throw std::invalid_argument("shaft speed must be a finite number > 0 Hz");
  if (!g.valid()) throw std::invalid_argument("invalid bearing geometry");
  if (!o.valid()) throw std::invalid_argument("invalid bearing-check options");
  for (double v : x)
    if (!std::isfinite(v)) throw std::invalid_argument("record holds a non-finite sample");
  BearingCheckResult r;
  r.predicted = model::bearing::defect_frequencies(g, shaft_speed_hz);
  const double top_hz = (1.0 - o.band.top_guard_fraction) * 0.5 * fs_hz;
  const double need_hz = (o.harmonics + 2) * r.predicted.bpfi_hz * (1.0 + o.speed_range);
  if (need_hz > top_hz) {
    std::snprintf(buf, sizeof buf,
                  "shaft speed %.4g Hz puts the bearing's lines (%d x BPFI = %.4g Hz) above the usable band of a "
                  "record sampled at %.4g Hz (%.4g Hz)",
                  shaft_speed_hz, o.harmonics + 2, need_hz, fs_hz, top_hz);
    throw std::invalid_argument(buf);
  }
  const double duration_s = static_cast<double>(x.size()) / fs_hz;
  if (duration_s * r.predicted.ftf_hz < 10.0) {
    std::snprintf(buf, sizeof buf, "record too short: %.3g s holds %.3g cage periods, at least 10 needed", duration_s,
                  duration_s * r.predicted.ftf_hz);
    throw std::invalid_argument(buf);
  }

  // 1-2. pre-whitening and band selection (band widths from the nominal speed).
  BandAnalyser raw(x, fs_hz);
  const double df = fs_hz / static_cast<double>(raw.length());
  BandAnalyser white = raw;
  white.prewhiten();
  r.whitening = "cepstrum pre-whitening (unit spectral magnitude, phase kept)";
  BandSelectionOptions bo = o.band;
  const double bpfi_max = r.predicted.bpfi_hz * (1.0 + o.speed_range);
  bo.min_bandwidth_hz = std::max(bo.min_bandwidth_hz, (o.harmonics + 2) * bpfi_max);
  // A demodulation band must lie above the lines it is to reveal: a band that holds them holds
  // the (whitened) lines themselves, not a resonance they modulate.
  bo.min_low_edge_hz = std::max(bo.min_low_edge_hz, o.harmonics * bpfi_max + r.predicted.shaft_hz);
  r.bands.push_back({"whitened_full", Band{0.0, top_hz, white.band_kurtosis(0.0, top_hz), 0}});
  r.bands.push_back({"whitened_sk", white.select_band(bo)});
  if (o.raw_sk_band) r.bands.push_back({"raw_sk", raw.select_band(bo)});
  BandAnalyser discrete_removed = raw;
  if (o.discrete_removed_band) {
    const DiscreteRemoval dr = discrete_removed.remove_discrete_components(o.discrete_halfwidth_hz, o.discrete_false_alarm);
    r.bands.push_back({"discrete_removed_sk", discrete_removed.select_band(bo)});
    char dbuf[200];
    std::snprintf(dbuf, sizeof dbuf, "; discrete removal (%zu bins edited, %.1f %% of the energy) for the discrete_removed_sk band",
                  dr.bins, 100.0 * dr.energy_fraction);
    r.whitening += dbuf;
  }
  std::vector<Band> ees_sub;
  if (o.enhanced_envelope_band) {
    ees_sub = ees_bands(bo.min_low_edge_hz, top_hz, bo.min_bandwidth_hz);
    if (!ees_sub.empty())
      r.bands.push_back({"whitened_ees", Band{ees_sub.front().low_hz, ees_sub.back().high_hz, 0.0, 0}, ees_sub.size()});
  }
  auto analyser = [&](const AnalysisBand& band) -> const BandAnalyser& {
    if (band.name == "raw_sk") return raw;
    if (band.name == "discrete_removed_sk") return discrete_removed;
    return white;
  };
  // The envelope spectrum of an analysis band (f_max: the highest frequency scored, set below
  // before the first call).
  double f_max = 0.0;
  auto band_spectrum = [&](const AnalysisBand& band) {
    if (band.name == "whitened_ees")
      return enhanced_envelope_spectrum(white, ees_sub, f_max + 2.0 * o.floor_halfwidth_hz, o.floor_halfwidth_hz);
    return analyser(band).envelope_spectrum(band.band);
  };

  // 5. speed: the shaft-harmonic comb of the spectrum, else of the whitened envelope spectrum
  // (an inner-race defect or an unbalance modulates at f_r even where the spectrum has no comb).
  // In the envelope spectrum the defect families' lines are the strongest lines there are: a
  // shaft harmonic that lies on one (its first three multiples, within the speed and slip
  // tolerances) cannot tell the shaft from the defect and is not a comb tooth there (an 8-DOF
  // 6200 outer-race record refined to BPFO / 3, 1.6 % off, on 3x = BPFO and 6x = 2 BPFO). In the
  // raw spectrum the shaft comb (unbalance, alignment) stands on its own and every harmonic counts.
  std::vector<double> defect_orders;
  for (double hz : {r.predicted.bpfo_hz, r.predicted.bpfi_hz, 2.0 * r.predicted.bsf_hz})
    for (int k = 1; k <= 3; ++k) defect_orders.push_back(k * hz / r.predicted.shaft_hz);
  const double order_tol = o.speed_range + o.slip_tolerance;
  r.speed = refine_speed(raw.magnitude(), df, shaft_speed_hz, o.speed_range);
  r.speed_source = r.speed.refined ? "spectrum" : "nominal";
  if (!r.speed.refined) {
    const EnvelopeSpectrum e = white.envelope_spectrum(r.bands[0].band);
    const SpeedRefinement se = refine_speed(e.amplitude, e.df_hz, shaft_speed_hz, o.speed_range, 8, 1e-3, defect_orders, order_tol);
    if (se.refined) {
      r.speed = se;
      r.speed_source = "envelope spectrum";
    }
  }
  r.refined = model::bearing::defect_frequencies(g, r.speed.speed_hz);
  const auto& p = r.refined;
  // Not refined: the nominal speed's uncertainty adds to the slip.
  const double tol = o.slip_tolerance + (r.speed.refined ? 0.0 : o.speed_range);

  // 3-4. envelope spectra, family scores and their surrogate nulls.
  const auto tmpl = templates(p, df, o);
  const auto forbidden = kinematic_lines(p);
  for (const auto& t : tmpl)
    for (const auto& l : t.lines) f_max = std::max(f_max, 1.8 * (l.multiple * t.base_hz + std::abs(l.offset_hz)));
  f_max += o.floor_halfwidth_hz;
  const double shaft_for_exclusion = r.speed.refined ? p.shaft_hz : 0.0;
  r.threshold_log10_p = std::log10(o.record_false_alarm / (static_cast<double>(r.bands.size()) * static_cast<double>(kFamilies)));
  for (int f = 0; f < kFamilies; ++f) {
    auto& fr = r.families[static_cast<size_t>(f)];
    fr.name = k_names[f];
    fr.predicted_hz = tmpl[static_cast<size_t>(f)].base_hz;
    fr.log10_p = 1.0;  // "none yet"
  }
  // Each band's normalised spectrum, made once: the scores, the shaft-comb check and the cage-comb
  // check below all read it.
  std::vector<NormalisedSpectrum> spectra;
  spectra.reserve(r.bands.size());
  for (size_t b = 0; b < r.bands.size(); ++b) {
    spectra.push_back(normalise_spectrum(band_spectrum(r.bands[b]), f_max, o.floor_halfwidth_hz, shaft_for_exclusion,
                                         o.shaft_exclude_bins));
    const NormalisedSpectrum& ns = spectra.back();
    for (int f = 0; f < kFamilies; ++f) {
      const auto& t = tmpl[static_cast<size_t>(f)];
      auto& fr = r.families[static_cast<size_t>(f)];
      TemplateScore sc = score_template(ns, t.base_hz, t.lines, tol, o.line_p);
      const double lp = o.null[static_cast<size_t>(f)].log10_p(sc.score);
      fr.log10_p_per_band.push_back(lp);
      if (o.collect_surrogates) {
        const auto d = surrogate_scores(ns, t.base_hz, t.lines, tol, forbidden);
        fr.surrogates.insert(fr.surrogates.end(), d.begin(), d.end());
      }
      if (fr.log10_p > 0.5 || lp < fr.log10_p || (lp == fr.log10_p && sc.score > fr.score)) {
        fr.log10_p = lp;
        fr.score = sc.score;
        fr.lines = std::move(sc);
        fr.band_index = b;
      }
    }
  }
  if (o.keep_spectra) r.band_spectra = spectra;

  // Without a refined speed the shaft harmonics cannot be set aside bin by bin. A fundamental
  // line that sits on a shaft comb instead - k f_s with f_s within speed_range of nominal and
  // the comb's neighbours (k-1) f_s and (k+1) f_s (2 f_s, 3 f_s for k = 1) present on their own
  // in the same band - is the comb's, not the family's (6200: BSF = 1.98 f_r next to 2 f_r).
  std::array<bool, kFamilies> comb_member{};
  if (!r.speed.refined) {
    for (int f = 0; f < kFamilies; ++f) {
      auto& fr = r.families[static_cast<size_t>(f)];
      if (!fr.lines.fundamental_present) continue;
      const NormalisedSpectrum& ns = spectra[fr.band_index];  // speed not refined: nothing set aside
      auto present = [&](double hz) {
        const long c = std::lround(hz / df);
        double m = 0.0;
        for (long k = c - 1; k <= c + 1; ++k)
          if (k > 0 && k < static_cast<long>(ns.ratio.size())) m = std::max(m, ns.ratio[static_cast<size_t>(k)]);
        return -std::expm1(3.0 * std::log1p(-std::exp2(-m * m))) < o.line_p;
      };
      bool any_own = false;
      const auto& tl = tmpl[static_cast<size_t>(f)].lines;
      for (size_t i = 0; i < tl.size(); ++i) {
        const auto& l = fr.lines.lines[i];
        if (!tl[i].fundamental || !(l.p_value < o.line_p)) continue;
        const double k = std::round(l.hz / shaft_speed_hz);
        const double comb_hz = k >= 1 ? l.hz / k : 0.0;
        const bool on_comb = k >= 1 && std::abs(comb_hz - shaft_speed_hz) <= o.speed_range * shaft_speed_hz &&
                             (k >= 2 ? present((k - 1) * comb_hz) : present(3 * comb_hz)) && present((k + 1) * comb_hz);
        if (!on_comb) any_own = true;
      }
      if (!any_own) {
        fr.lines.fundamental_present = false;
        comb_member[static_cast<size_t>(f)] = true;
      }
    }
  }

  // 6. decision.
  for (int f = 0; f < kFamilies; ++f) {
    auto& fr = r.families[static_cast<size_t>(f)];
    fr.threshold_score = o.null[static_cast<size_t>(f)].score_at(r.threshold_log10_p);
    const bool significant = fr.log10_p < r.threshold_log10_p;
    fr.detected = significant && fr.lines.fundamental_present;
    if (fr.lines.fundamental_present) {
      const auto& l = fr.lines.lines;
      if (f == kBall)
        fr.found_hz = l[1].hz / 2.0;  // the 2 BSF line (the fundamental) / 2
      else
        fr.found_hz = l[0].hz;
    }
    if (!significant)
      fr.reason = "not significant: score " + fmt_p(fr.score) + " <= " + fmt_p(fr.threshold_score) + " (log10 P_null " +
                  fmt_p(fr.log10_p) + " >= " + fmt_p(r.threshold_log10_p) + ")";
    else if (!fr.detected && comb_member[static_cast<size_t>(f)])
      fr.reason = "lines significant (log10 P_null " + fmt_p(fr.log10_p) +
                  ") but the fundamental sits on a shaft-harmonic comb (speed not refined)";
    else if (!fr.detected)
      fr.reason = "lines significant (log10 P_null " + fmt_p(fr.log10_p) + ") but the fundamental is absent";
  }
  // Outer race inside a cage comb (see BearingCheckOptions::comb_dominance).
  auto& fo = r.families[kOuter];
  if (fo.detected) {
    const int z = g.ball_count;
    const double ftf = fo.lines.lines[0].hz / z;  // BPFO = Z FTF: the comb's spacing from the BPFO line found
    // In BPFO's band and in the cage family's best band (where a comb shows best).
    for (size_t bi : {fo.band_index, r.families[kCage].band_index}) {
      const auto& band = r.bands[bi];
      const NormalisedSpectrum& ns = spectra[bi];
      auto peak = [&](double hz) {
        const long c = std::lround(hz / df);
        double m = 0.0;
        for (long k = c - 1; k <= c + 1; ++k)
          if (k > 0 && k < static_cast<long>(ns.ratio.size()) && !ns.excluded[static_cast<size_t>(k)])
            m = std::max(m, ns.ratio[static_cast<size_t>(k)]);
        return m;
      };
      double teeth = 0.0;
      for (int n : {1, 2, 3, z - 2, z - 1, z + 1, z + 2}) teeth = std::max(teeth, peak(n * ftf));
      const double bpfo_ratio = peak(z * ftf);
      // The comb is there if the cage family is detected or a tooth is present on its own
      // (Rayleigh p of the largest of its 3 bins < line_p).
      const bool comb = r.families[kCage].detected || -std::expm1(3.0 * std::log1p(-std::exp2(-teeth * teeth))) < o.line_p;
      r.cage_teeth_ratio = std::max(r.cage_teeth_ratio, teeth);
      if (comb && bpfo_ratio < o.comb_dominance * teeth) {
        fo.detected = false;
        std::snprintf(buf, sizeof buf,
                      "significant, but a tooth of the cage comb: in %s the BPFO line is %.1fx its floor < %.1f x the "
                      "strongest cage tooth (%.1fx); cage modulation (a ball fault going round with the cage, or the "
                      "cage) also puts a line on BPFO = %d FTF",
                      band.name.c_str(), bpfo_ratio, o.comb_dominance, teeth, z);
        fo.reason = buf;
        break;
      }
    }
  }
  // Shared lines: where two detected families' lines coincide (6200: 2 BSF = BPFI - f_r; 6205:
  // 3 BPFO ~ 2 BPFI), a line is evidence for neither. Each detected family is ranked by its
  // score on the lines no other detected family also found; a family with no such evidence above
  // the threshold cannot be named.
  int n_detected = 0;
  for (const auto& fr : r.families) n_detected += fr.detected ? 1 : 0;
  if (n_detected >= 2) {
    for (int f = 0; f < kFamilies; ++f) {
      auto& fr = r.families[static_cast<size_t>(f)];
      if (!fr.detected) continue;
      double chi2 = 0.0;
      int m = 0;
      for (const auto& l : fr.lines.lines) {
        if (!(l.hz > 0)) continue;
        bool shared = false;
        for (int e = 0; e < kFamilies && !shared; ++e) {
          if (e == f || !r.families[static_cast<size_t>(e)].detected) continue;
          for (const auto& q : r.families[static_cast<size_t>(e)].lines.lines)
            if (q.hz > 0 && q.p_value < o.line_p && std::abs(q.hz - l.hz) <= std::max(2.0 * df, tol * l.hz)) shared = true;
        }
        if (shared) continue;
        chi2 += -2.0 * std::log(std::max(l.p_value, 1e-300));
        ++m;
      }
      fr.unique_score = m > 0 ? -log_chi2_sf_even(chi2, m) / std::log(10.0) : 0.0;
      fr.unique_log10_p = o.null[static_cast<size_t>(f)].log10_p(fr.unique_score);
    }
  } else {
    for (auto& fr : r.families) {
      fr.unique_score = fr.score;
      fr.unique_log10_p = fr.log10_p;
    }
  }
  // A detected ball family carries the cage modulation (BearingCheckOptions::cage_as_ball_modulation).
  const bool cage_is_ball_modulation = o.cage_as_ball_modulation && r.families[kBall].detected &&
                                       r.families[kBall].unique_log10_p < r.threshold_log10_p &&
                                       r.families[kCage].detected;
  int best = -1;
  for (int f = 0; f < kFamilies; ++f) {
    const auto& fr = r.families[static_cast<size_t>(f)];
    if (f == kCage && cage_is_ball_modulation) continue;
    if (fr.detected && fr.unique_log10_p < r.threshold_log10_p &&
        (best < 0 || fr.unique_log10_p < r.families[static_cast<size_t>(best)].unique_log10_p))
      best = f;
  }
  if (best < 0 && n_detected >= 2) {
    r.verdict = "unclear";
    r.reason = "several families are detected but none on lines of its own (their evidence is shared lines):";
    for (auto& fr : r.families)
      if (fr.detected) {
        fr.reason = "detected on shared lines only (score on its own lines " + fmt_p(fr.unique_score) + ")";
        r.reason += " " + fr.name;
      }
    return r;
  }
  // Nothing named in the whitened bands: look for the cage-rate modulation in the raw signal
  // (BearingCheckOptions::cage_modulation_as_ball (b), only with raw_cage_scan: off by default).
  if (o.cage_modulation_as_ball && o.raw_cage_scan && best < 0)
    scan_raw_cage(raw, bo, tmpl[kCage], f_max, shaft_for_exclusion, tol, forbidden, o, r.raw_cage);
  if (best < 0 && r.raw_cage.detected) {
    const auto& rc = r.raw_cage;
    const double ftf_hz = rc.lines.lines.empty() ? p.ftf_hz : rc.lines.lines[0].hz;
    std::snprintf(buf, sizeof buf,
                  "not significant in the whitened bands; detected in the raw signal's %.0f-%.0f Hz band (score %.1f > "
                  "%.1f, log10 P_null %.1f < %.1f over %zu raw bands)",
                  rc.band.low_hz, rc.band.high_hz, rc.score, rc.threshold_score, rc.log10_p, rc.threshold_log10_p, rc.bands);
    r.families[kCage].reason = buf;
    r.verdict = "ball";
    std::snprintf(buf, sizeof buf,
                  "cage-rate modulation: the cage family (FTF %.2f Hz) in the raw signal's envelope, %.0f-%.0f Hz "
                  "(log10 P_null %.1f < %.1f, null: the record's own surrogates), and no race or ball-spin "
                  "line family: a ball defect going round with the cage through the load zone (a cage fault gives the "
                  "same lines)%s",
                  ftf_hz, rc.band.low_hz, rc.band.high_hz, rc.log10_p, rc.threshold_log10_p,
                  fo.reason.rfind("significant, but a tooth", 0) == 0 ? "; the BPFO line is a tooth of its comb" : "");
    r.reason = buf;
    return r;
  }
  if (best < 0 && fo.reason.rfind("significant, but a tooth", 0) == 0) {
    r.verdict = "unclear";
    r.reason = "bpfo " + fo.reason;
    return r;
  }
  if (best < 0) {
    r.verdict = "healthy";
    std::snprintf(buf, sizeof buf,
                  "no family significant: every family's P_null is above %.1e (record-wise false-alarm rate %.0e over "
                  "%zu bands x %d families)",
                  std::pow(10.0, r.threshold_log10_p), o.record_false_alarm, r.bands.size(), kFamilies);
    r.reason = buf;
    return r;
  }
  const auto& w = r.families[static_cast<size_t>(best)];
  r.verdict_band = w.band_index;
  r.verdict = best == kCage && o.cage_modulation_as_ball ? "ball" : k_verdicts[best];
  for (int f = 0; f < kFamilies; ++f) {
    auto& fr = r.families[static_cast<size_t>(f)];
    if (f == best) {
      fr.reason = "named: strongest detected family (log10 P_null " + fmt_p(fr.log10_p) + ", score " + fmt_p(fr.score) +
                  ", band " + r.bands[fr.band_index].name + ")";
    } else if (f == kCage && cage_is_ball_modulation) {
      fr.reason = "detected (log10 P_null " + fmt_p(fr.log10_p) +
                  "): taken as the ball family's cage modulation (a ball fault's impacts are modulated at FTF), "
                  "not a verdict of its own";
    } else if (fr.detected) {
      fr.reason = std::string("detected but weaker than ") + k_names[best] + " on lines of its own (log10 P_null " +
                  fmt_p(fr.unique_log10_p) + " vs " + fmt_p(w.unique_log10_p) + ")";
    }
  }
  const auto& band = r.bands[w.band_index];
  if (best == kCage) {
    std::snprintf(buf, sizeof buf,
                  "only the cage family (FTF %.2f Hz) is detected (log10 P_null %.1f in %s %.0f-%.0f Hz): cage "
                  "modulation without a race or ball line family of its own%s%s",
                  w.found_hz.value_or(w.predicted_hz), w.log10_p, band.name.c_str(), band.band.low_hz, band.band.high_hz,
                  o.cage_modulation_as_ball ? ": a ball defect going round with the cage through the load zone (a cage "
                                              "fault, or a healthy bearing's ball-size variation, gives the same "
                                              "lines)" : "",
                  r.cage_teeth_ratio > 0 && !fo.detected ? "; the BPFO line is a tooth of its comb" : "");
  } else {
    std::snprintf(buf, sizeof buf,
                  "%s family detected: fundamental %.2f Hz (predicted %.2f), score %.1f > %.1f (log10 P_null %.1f < "
                  "%.1f, null measured on healthy records) in %s %.0f-%.0f Hz",
                  k_names[best], w.found_hz.value_or(0.0), w.predicted_hz, w.score, w.threshold_score, w.log10_p,
                  r.threshold_log10_p, band.name.c_str(), band.band.low_hz, band.band.high_hz);
  }
  r.reason = buf;
  return r;
}

}  // namespace amb::host::bearing
