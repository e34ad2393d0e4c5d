#include "host-tools/core/residual/sweep_frf.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fftw3.h>
#include <limits>

#include "host-tools/core/residual/modal_peaks.hpp"

namespace amb::host::residual {
namespace {

using cd = std::complex<double>;
constexpr double k_inf = std::numeric_limits<double>::infinity();

std::string fmt(const char* f, double a, double b = 0.0, double c = 0.0, double d = 0.0) {
  char buf[320];
  std::snprintf(buf, sizeof buf, f, a, b, c, d);
  return buf;
}

FrfFitData make_data(const SweepFrf& frf, const SweepOptions& o) {
  FrfFitData d;
  std::vector<size_t> bins;
  for (size_t k = 0; k < frf.f_hz.size(); ++k)
    if (frf.f_hz[k] >= o.f_min_hz && frf.f_hz[k] <= o.f_max_hz) bins.push_back(k);
  for (size_t k : bins) d.f_hz.push_back(frf.f_hz[k]);
  d.h.assign(frf.h.size(), {});
  d.w.assign(frf.h.size(), {});
  for (size_t c = 0; c < frf.h.size(); ++c)
    for (size_t k : bins) {
      d.h[c].push_back(frf.h[c][k]);
      const double g = frf.coherence[c][k];
      d.w[c].push_back(g >= o.min_coherence ? frf.segments * std::min(g, 0.98) / (1.0 - std::min(g, 0.98)) : 0.0);
    }
  return d;
}

int used_points(const FrfFitData& d, const std::vector<size_t>& channels) {
  int n = 0;
  for (size_t c : channels)
    for (double w : d.w[c]) n += w > 0.0 ? 2 : 0;
  return n;
}

int free_count(const UpdateModel& m) {
  int n = 0;
  for (const auto& p : m.p) n += p.free ? 1 : 0;
  return n;
}

// Marks the parameters that belong to switched-off elements as fixed.
void sync_free(UpdateModel& m) {
  for (auto& p : m.p) {
    if (p.name == "accel_mass_kg") p.free = m.sensor_mass;
    if (p.name == "actuator_lag_s" || p.name == "loop_delay_s") p.free = m.lag;
  }
}

SweepFitEvaluation to_eval(const UpdateModel& m, const FrfFit& f, const FrfFitData& d, const std::vector<size_t>& channels,
                           int parameters) {
  SweepFitEvaluation ev;
  ev.excited_axis = 2 * m.base.excited;
  for (size_t i = 0; i < m.p.size(); ++i)
    if (m.p[i].name == "pid_gain_scale") ev.gain_scale = f.values[i];
  ev.accel_axial_m = f.accel_axial_m;
  ev.cost = f.cost;
  ev.parameters = parameters + static_cast<int>(channels.size());
  ev.data_points = used_points(d, channels);
  ev.bic = ev.cost + ev.parameters * std::log(std::max(1, ev.data_points));
  const auto e = frf_errors(d, f.h_model, channels);
  ev.error.rms = e.rms_ln;
  ev.error.spectral = e.spectral_db;
  ev.error.pearson = e.pearson;
  ev.h_model = f.h_model;
  return ev;
}

std::vector<double> values_of(const UpdateModel& m) {
  std::vector<double> v;
  for (const auto& p : m.p) v.push_back(p.value);
  return v;
}

// Frequencies first, then the complex FRF; accelerometer masses follow the positions.
FrfFit update(UpdateModel& m, const std::vector<double>& start, const FrfFitData& d, const std::vector<size_t>& channels,
              const std::vector<double>& peaks_hz, const std::vector<double>& positions, int max_eval) {
  std::vector<double> fit_pos;
  for (size_t c : channels) fit_pos.push_back(positions[c]);
  std::vector<bool> was(m.p.size());
  for (size_t i = 0; i < m.p.size(); ++i) {
    was[i] = m.p[i].free;
    if (m.p[i].name.rfind("damping_ratio", 0) == 0 || m.p[i].name == "force_gain_n_per_a") m.p[i].free = false;
  }
  const auto v1 = peaks_hz.empty() ? start : fit_frequencies(m, start, peaks_hz, fit_pos, max_eval);
  for (size_t i = 0; i < m.p.size(); ++i) m.p[i].free = was[i];
  FrfFit f = fit_parameters(m, v1, d, channels, max_eval);
  m.mass_axial_m = f.accel_axial_m;
  f = fit_parameters(m, f.values, d, channels, max_eval / 2);
  m.mass_axial_m = f.accel_axial_m;
  return evaluate_fit(m, f.values, d, channels);
}

std::vector<ModeMatch> match_modes(const UpdateModel& m, const FrfFit& f, const std::vector<MeasuredPeak>& peaks) {
  std::vector<ModeMatch> out;
  const model::analysis::HalfOpenFrf hm(to_model(m, f.values));
  std::vector<double> fm;
  for (const auto& p : peaks) fm.push_back(p.frequency_hz);
  const auto mp = model_peaks(hm, fm, f.accel_axial_m);
  for (size_t k = 0; k < peaks.size(); ++k) {
    ModeMatch mm;
    mm.measured_hz = peaks[k].frequency_hz;
    mm.model_hz = mp[k];
    mm.prominence = peaks[k].prominence;
    mm.error_pct = 100.0 * (mp[k] / fm[k] - 1.0);
    const double fq = std::isfinite(mp[k]) ? mp[k] : fm[k];
    auto shape = hm.accel_per_current(fq, f.accel_axial_m);
    mm.mac = mac(peaks[k].shape, shape);
    out.push_back(mm);
  }
  return out;
}

}  // namespace

SweepFrf estimate_frf(const std::vector<double>& x, const std::vector<std::vector<double>>& ys, double fs, const SweepOptions& o) {
  SweepFrf r;
  const int seg = static_cast<int>(o.segment_s * fs), hop = seg / 2;
  const int nfft = seg * std::max(1, o.zero_pad), nb = nfft / 2 + 1;
  std::vector<double> win(static_cast<size_t>(seg)), in(static_cast<size_t>(nfft), 0.0);
  for (int i = 0; i < seg; ++i) win[static_cast<size_t>(i)] = 0.5 - 0.5 * std::cos(2.0 * M_PI * i / seg);
  std::vector<fftw_complex> out(static_cast<size_t>(nb));
  fftw_plan plan = fftw_plan_dft_r2c_1d(nfft, in.data(), out.data(), FFTW_ESTIMATE);
  auto fft = [&](const std::vector<double>& s, size_t start, std::vector<cd>& spec) {
    for (int i = 0; i < seg; ++i) in[static_cast<size_t>(i)] = s[start + static_cast<size_t>(i)] * win[static_cast<size_t>(i)];
    fftw_execute(plan);
    spec.resize(static_cast<size_t>(nb));
    for (int k = 0; k < nb; ++k) spec[static_cast<size_t>(k)] = cd(out[static_cast<size_t>(k)][0], out[static_cast<size_t>(k)][1]);
  };
  const size_t nch = ys.size();
  std::vector<double> sxx(static_cast<size_t>(nb), 0.0);
  std::vector<std::vector<cd>> sxy(nch, std::vector<cd>(static_cast<size_t>(nb), 0.0));
  std::vector<std::vector<double>> syy(nch, std::vector<double>(static_cast<size_t>(nb), 0.0));
  std::vector<cd> xs, yspec;
  for (size_t start = 0; start + static_cast<size_t>(seg) <= x.size(); start += static_cast<size_t>(hop)) {
    const double t0 = static_cast<double>(start) / fs, t1 = t0 + o.segment_s;
    bool skip = false;
    for (const auto& sp : o.exclude_spans_s) skip = skip || (t1 > sp[0] && t0 < sp[1]);
    if (skip) continue;
    ++r.segments;
    fft(x, start, xs);
    for (int k = 0; k < nb; ++k) sxx[static_cast<size_t>(k)] += std::norm(xs[static_cast<size_t>(k)]);
    for (size_t c = 0; c < nch; ++c) {
      fft(ys[c], start, yspec);
      for (int k = 0; k < nb; ++k) {
        sxy[c][static_cast<size_t>(k)] += std::conj(xs[static_cast<size_t>(k)]) * yspec[static_cast<size_t>(k)];
        syy[c][static_cast<size_t>(k)] += std::norm(yspec[static_cast<size_t>(k)]);
      }
    }
  }
  fftw_destroy_plan(plan);
  r.h.assign(nch, {});
  r.coherence.assign(nch, {});
  for (int k = 1; k < nb; ++k) {
    r.f_hz.push_back(k * fs / nfft);
    for (size_t c = 0; c < nch; ++c) {
      const double den = sxx[static_cast<size_t>(k)];
      r.h[c].push_back(den > 0 ? sxy[c][static_cast<size_t>(k)] / den : cd(0.0, 0.0));
      const double g = den > 0 && syy[c][static_cast<size_t>(k)] > 0
                           ? std::norm(sxy[c][static_cast<size_t>(k)]) / (den * syy[c][static_cast<size_t>(k)]) : 0.0;
      r.coherence[c].push_back(g);
    }
  }
  return r;
}

SweepOutcome run_sweep_residual(const std::vector<double>& input, const std::vector<std::vector<double>>& outputs, double fs,
                                const board::BoardConfig& b, const SweepOptions& o) {
  SweepOutcome out;
  const size_t nch = outputs.size();
  if (nch == 0 || input.size() < static_cast<size_t>(4.0 * o.segment_s * fs))
    throw std::invalid_argument("sweep residual: need at least one output channel and four segments of data");
  for (const auto& y : outputs)
    if (y.size() != input.size()) throw std::invalid_argument("sweep residual: output channels must have the input's length");
  const double bias = b.plant.amb.empty() ? 0.0 : b.plant.amb[0].bias_current_a;
  out.nonlinear = detect_nonlinear_spans(input, outputs, fs, bias);
  SweepOptions oe = o;
  for (const auto& s : out.nonlinear) oe.exclude_spans_s.push_back({s.t0_s, s.t1_s});
  oe.zero_pad = 1;
  out.frf = estimate_frf(input, outputs, fs, oe);
  oe.zero_pad = 4;
  const SweepFrf zp = estimate_frf(input, outputs, fs, oe);
  out.data = make_data(out.frf, o);
  const auto& d = out.data;
  std::vector<size_t> all;
  for (size_t c = 0; c < nch; ++c) all.push_back(c);
  // Peaks: resonance tops lose coherence in a 1 s window of a sweep (ring-down), so the peak
  // search accepts coherence >= 0.5; the compared band keeps min_coherence.
  const auto peaks = find_peaks(zp.f_hz, zp.h, zp.coherence, {o.f_min_hz, o.f_max_hz, std::min(0.5, o.min_coherence), 3.0});
  std::vector<double> peak_hz;
  for (const auto& p : peaks) peak_hz.push_back(p.frequency_hz);

  // The board's own model: excited AMB and sign convention chosen by the data.
  UpdateModel m;
  FrfFit nominal;
  nominal.cost = k_inf;
  for (int e : {0, 1})
    for (double s : {1.0, -1.0}) {
      UpdateModel t = make_update_model(b, e, nch);
      t.sign = s;
      t.sensor_mass = false;
      t.lag = false;
      sync_free(t);
      const auto f = evaluate_fit(t, values_of(t), d, all);
      if (f.cost < nominal.cost) { nominal = f; m = t; }
    }
  out.before = to_eval(m, nominal, d, all, 0);
  out.modes_before = match_modes(m, nominal, peaks);
  const auto nominal_positions = nominal.accel_axial_m;

  // Model updating with the accelerometer masses and the actuator lag in the model.
  m.sensor_mass = true;
  m.lag = true;
  sync_free(m);
  m.mass_axial_m = nominal_positions;
  FrfFit cur = update(m, values_of(m), d, all, peak_hz, nominal_positions, o.max_evaluations);
  auto bic_of = [&](const UpdateModel& mm, const FrfFit& f) { return to_eval(mm, f, d, all, free_count(mm)).bic; };
  double bic = bic_of(m, cur);

  // Elements: keep each of the updating's added elements only if removing it costs BIC;
  // then candidate housing modes at either bearing.
  auto removal = [&](bool UpdateModel::*flag, const char* name, const std::string& what) {
    UpdateModel t = m;
    t.*flag = false;
    sync_free(t);
    const FrfFit f = fit_parameters(t, cur.values, d, all, o.max_evaluations / 2);
    CandidateScore c;
    c.name = name;
    c.delta_bic = bic_of(t, f) - bic;
    c.evidence = what + fmt(": without it the FRF misfit is %.4g instead of %.4g; BIC cost of removing it %.1f", f.cost, cur.cost, c.delta_bic);
    return std::make_pair(c, std::make_pair(t, f));
  };
  std::vector<CandidateScore> ranking;
  for (auto [flag, name, what] : {std::make_tuple(&UpdateModel::sensor_mass, "sensor_mass", std::string("accelerometer masses on the shaft")),
                                  std::make_tuple(&UpdateModel::lag, "amplifier_lag", std::string("actuator lag (eddy currents, amplifier) and loop delay"))}) {
    auto [c, alt] = removal(flag, name, what);
    ranking.push_back(c);
    if (!(c.delta_bic > o.min_delta_bic)) {  // not earned: leave it out
      m = alt.first;
      cur = alt.second;
      bic = bic_of(m, cur);
    }
  }
  {
    CandidateScore best;
    best.delta_bic = -k_inf;
    UpdateModel bm;
    FrfFit bf;
    for (int j : {0, 1}) {
      UpdateModel t = m;
      double start_f = 100.0, start_cost = k_inf;
      for (double f0 : {60.0, 120.0, 250.0, 450.0}) {
        UpdateModel s = m;
        add_housing(s, j, f0, 3.0, 0.05);
        const double c = evaluate_fit(s, values_of(s).size() == cur.values.size() + 3 ? [&] {
          auto v = cur.values;
          v.push_back(3.0);
          v.push_back(f0);
          v.push_back(0.05);
          return v;
        }() : values_of(s), d, all).cost;
        if (c < start_cost) { start_cost = c; start_f = f0; }
      }
      add_housing(t, j, start_f, 3.0, 0.05);
      auto v = cur.values;
      v.push_back(3.0);
      v.push_back(start_f);
      v.push_back(0.05);
      const FrfFit f = fit_parameters(t, v, d, all, o.max_evaluations);
      CandidateScore c;
      c.name = "pedestal_resonance";
      c.delta_bic = bic - bic_of(t, f);
      c.evidence = fmt("housing / foundation mode at the AMB at %.0f mm: misfit %.4g -> %.4g; BIC decrease %.1f",
                       m.base.bearing[static_cast<size_t>(j)].axial_m * 1e3, cur.cost, f.cost, c.delta_bic);
      ranking.push_back(c);
      if (c.delta_bic > best.delta_bic) { best = c; bm = t; bf = f; }
    }
    if (best.delta_bic > o.min_delta_bic) {
      m = bm;
      cur = bf;
      bic = bic_of(m, cur);
    }
  }
  std::sort(ranking.begin(), ranking.end(), [](const auto& a, const auto& c) { return a.delta_bic > c.delta_bic; });
  for (const char* nt : {"sensor_runout", "aux_bearing_offset"})
    ranking.push_back({nt, false, -k_inf, "no rotation / no rest or contact segment in a standstill sweep: not testable"});
  out.ranking = ranking;
  for (size_t i = 0; i < m.p.size(); ++i) m.p[i].value = cur.values[i];
  out.after = to_eval(m, cur, d, all, free_count(m));
  auto element = [&](const std::string& name, std::vector<std::string> keys, double dbic) {
    EffectAdded a;
    a.name = name;
    a.delta_bic = dbic;
    for (const auto& k : keys)
      for (const auto& p : m.p)
        if (p.name == k) a.parameters.emplace_back(k, p.value);
    a.evidence = "kept by the updating (BIC)";
    out.effects_added.push_back(a);
  };
  for (const auto& c : ranking) {
    if (c.name == "sensor_mass" && m.sensor_mass) element("sensor_mass", {"accel_mass_kg"}, c.delta_bic);
    if (c.name == "amplifier_lag" && m.lag) element("amplifier_lag", {"actuator_lag_s", "loop_delay_s"}, c.delta_bic);
  }
  if (m.housing) element("pedestal_resonance", {"housing_mass_kg", "housing_frequency_hz", "housing_damping_ratio"}, 0.0);
  for (auto& a : out.effects_added)
    for (const auto& c : ranking)
      if (c.name == a.name && c.delta_bic > -k_inf) { a.evidence = c.evidence; a.delta_bic = c.delta_bic; }
  out.parameters = m.p;
  for (const auto& p : m.p) out.parameter_at_bound.push_back(at_bound(p, p.value));
  out.modes_after = match_modes(m, cur, peaks);
  out.identifiability = identifiability(m, cur, d);

  // Validation: fit on half the accelerometers, check on the other half, both ways.
  if (o.validate && nch >= 2) {
    for (int split = 0; split < 2; ++split) {
      ValidationRun vr;
      for (size_t c = 0; c < nch; ++c) (static_cast<int>(c % 2) == split ? vr.fit_channels : vr.check_channels).push_back(c);
      UpdateModel t = m;
      for (auto& p : t.p) p.value = p.nominal;
      t.mass_axial_m = nominal_positions;
      const FrfFit f = update(t, values_of(t), d, vr.fit_channels, peak_hz, nominal_positions, o.max_evaluations);
      vr.fit = frf_errors(d, f.h_model, vr.fit_channels);
      vr.check = frf_errors(d, f.h_model, vr.check_channels);
      vr.check_nominal = frf_errors(d, nominal.h_model, vr.check_channels);
      out.validation.push_back(vr);
    }
  }

  // Notes.
  out.notes.push_back(fmt("compared band %.0f-%.0f Hz where coherence >= %.2f per channel: %.0f of the channel-bins", o.f_min_hz,
                          o.f_max_hz, o.min_coherence, out.after.data_points / 2.0));
  for (const auto& s : out.nonlinear) out.notes.push_back(fmt("nonlinear stretch %.2f-%.2f s left out: ", s.t0_s, s.t1_s) + s.reason);
  out.notes.push_back(fmt("excited: the AMB at %.0f mm (current as input, the other bearing closed), sign %+.0f",
                          m.base.bearing[static_cast<size_t>(m.base.excited)].axial_m * 1e3, m.sign));
  std::string pos = "accelerometer positions fitted (mm):";
  for (double z : out.after.accel_axial_m) pos += fmt(" %.0f", z * 1e3);
  out.notes.push_back(pos);
  for (const auto& mm : out.modes_after)
    out.notes.push_back(fmt("peak %.2f Hz: model %.2f Hz (%+.2f %%), MAC %.3f", mm.measured_hz, mm.model_hz, mm.error_pct, mm.mac));
  for (const auto& n : out.identifiability.notes) out.notes.push_back("identifiability: " + n);
  std::string v;
  for (const auto& a : out.effects_added) v += (v.empty() ? "" : "+") + a.name;
  out.verdict = v.empty() ? "none" : v;
  return out;
}

}  // namespace amb::host::residual
