#include "host-tools/core/io/number_text.hpp"
#include "host-tools/core/residual/sweep_frf.hpp"

#include <algorithm>
#include <cmath>
#include <Eigen/Dense>
#include <cstdio>
#include <fftw3.h>
#include <functional>
#include <limits>
#include <cstdlib>
#include <stdexcept>

#include "host-tools/core/io/mat_file.hpp"
#include "host-tools/core/residual/modal_peaks.hpp"

namespace amb::host::residual {
namespace {

using cd = std::complex<double>;
constexpr double k_inf = std::numeric_limits<double>::infinity();


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

std::vector<double> values_of(const UpdateModel& m) {
  std::vector<double> v;
  for (const auto& p : m.p) v.push_back(p.value);
  return v;
}

double value_in(const UpdateModel& m, const std::vector<double>& v, const std::string& name) {
  for (size_t i = 0; i < m.p.size(); ++i)
    if (m.p[i].name == name) return v[i];
  return std::numeric_limits<double>::quiet_NaN();
}

SweepFitEvaluation to_eval(const UpdateModel& m, const FrfFit& f, const FrfFitData& d, const std::vector<size_t>& channels,
                           int parameters) {
  SweepFitEvaluation ev;
  ev.excited_axis = 2 * m.base.excited;
  const double g = value_in(m, f.values, "pid_gain_scale");
  ev.gain_scale = std::isfinite(g) ? g : 1.0;
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

double bic_of(const UpdateModel& m, const FrfFit& f, const FrfFitData& d, const std::vector<size_t>& channels) {
  return f.cost + (free_count(m) + static_cast<int>(channels.size())) * std::log(std::max(1, used_points(d, channels)));
}

// Frequencies first (damping and force gain held: they shift no peak), then the complex FRF
// with the accelerometer positions searched (fixed = true: kept at `positions`, a cheaper
// screening fit); the accelerometer masses follow the positions.
FrfFit update(UpdateModel& m, const std::vector<double>& start, const FrfFitData& d, const std::vector<size_t>& channels,
              const std::vector<double>& peaks_hz, const std::vector<double>& norms, const std::vector<double>& positions,
              int max_eval, bool fixed = false) {
  std::vector<double> fit_pos, fit_norm;
  for (size_t c : channels) {
    fit_pos.push_back(positions[c]);
    fit_norm.push_back(norms[c]);
  }
  m.fixed_positions = fixed;
  m.mass_axial_m = positions;
  std::vector<bool> was(m.p.size());
  for (size_t i = 0; i < m.p.size(); ++i) {
    was[i] = m.p[i].free;
    if (m.p[i].name.rfind("damping_ratio", 0) == 0 || m.p[i].name == "force_gain_n_per_a") m.p[i].free = false;
  }
  const auto v1 = peaks_hz.empty() ? start : fit_frequencies(m, start, peaks_hz, fit_pos, max_eval, fit_norm);
  for (size_t i = 0; i < m.p.size(); ++i) m.p[i].free = was[i];
  FrfFit f = fit_parameters(m, v1, d, channels, max_eval);
  if (!fixed) {
    m.mass_axial_m = f.accel_axial_m;
    f = fit_parameters(m, f.values, d, channels, max_eval / 2);
    m.mass_axial_m = f.accel_axial_m;
  }
  const FrfFit r = evaluate_fit(m, f.values, d, channels);
  m.fixed_positions = false;
  return r;
}

std::vector<ModeMatch> match_modes(const UpdateModel& m, const FrfFit& f, const std::vector<MeasuredPeak>& peaks,
                                   const std::vector<double>& norms, const SweepFrf& zp) {
  std::vector<ModeMatch> out;
  const model::analysis::HalfOpenFrf hm(to_model(m, f.values));
  std::vector<double> fm;
  for (const auto& p : peaks) fm.push_back(p.frequency_hz);
  const auto mp = model_peaks(hm, fm, f.accel_axial_m, norms);
  for (size_t k = 0; k < peaks.size(); ++k) {
    ModeMatch mm;
    mm.measured_hz = peaks[k].frequency_hz;
    mm.model_hz = mp[k];
    mm.prominence = peaks[k].prominence;
    mm.error_pct = 100.0 * (mp[k] / fm[k] - 1.0);
    const double fq = std::isfinite(mp[k]) ? mp[k] : fm[k];
    mm.mac = mac(peaks[k].shape, hm.accel_per_current(fq, f.accel_axial_m));
    mm.ema_measured_hz = mm.ema_model_hz = std::numeric_limits<double>::quiet_NaN();
    out.push_back(mm);
  }
  // Experimental modal analysis, band by band (peaks closer than 8 % share one band).
  const size_t nch = zp.h.size();
  for (size_t k0 = 0; k0 < fm.size();) {
    size_t k1 = k0 + 1;
    while (k1 < fm.size() && fm[k1] / fm[k1 - 1] < 1.08) ++k1;
    const double lo = 0.95 * fm[k0], hi = 1.05 * fm[k1 - 1];
    std::vector<double> fb;
    std::vector<std::vector<cd>> hmeas(nch), hmod(nch);
    std::vector<std::vector<double>> w(nch);
    std::vector<Eigen::RowVectorXcd> rows;
    for (double z : f.accel_axial_m) rows.push_back(hm.shape_row(z).cast<cd>());
    for (size_t i = 0; i < zp.f_hz.size(); ++i) {
      if (zp.f_hz[i] < lo || zp.f_hz[i] > hi) continue;
      fb.push_back(zp.f_hz[i]);
      const double om = 2.0 * M_PI * zp.f_hz[i];
      const Eigen::VectorXcd q = -m.sign * om * om * hm.modal_response(zp.f_hz[i]);
      for (size_t c = 0; c < nch; ++c) {
        hmeas[c].push_back(zp.h[c][i]);
        hmod[c].push_back((rows[c] * q)(0));
        const double g = std::min(zp.coherence[c][i], 0.98);
        w[c].push_back(g / (1.0 - g));
      }
    }
    const std::vector<double> starts(fm.begin() + static_cast<std::ptrdiff_t>(k0), fm.begin() + static_cast<std::ptrdiff_t>(k1));
    const auto em = fit_modes(fb, hmeas, w, lo, hi, starts);
    const auto eo = fit_modes(fb, hmod, w, lo, hi, starts);
    for (size_t k = k0; k < k1 && em.size() == starts.size() && eo.size() == starts.size(); ++k) {
      auto& mm = out[k];
      const auto& a = em[k - k0];
      const auto& b2 = eo[k - k0];
      mm.ema_measured_hz = a.frequency_hz;
      mm.ema_measured_zeta = a.damping_ratio;
      mm.ema_model_hz = b2.frequency_hz;
      mm.ema_model_zeta = b2.damping_ratio;
      mm.ema_error_pct = 100.0 * (b2.frequency_hz / a.frequency_hz - 1.0);
      mm.ema_mac = mac(a.shape, b2.shape);
    }
    k0 = k1;
  }
  return out;
}

// I/V = g A / (1 + K H A): see CurrentLoopCheck.
std::vector<cd> current_loop_model(const UpdateModel& m, const std::vector<double>& v, const std::vector<double>& f_hz) {
  const auto hp = to_model(m, v);
  const model::analysis::HalfOpenFrf f(hp);
  const auto& be = hp.bearing[static_cast<size_t>(hp.excited)];
  std::vector<cd> out;
  for (double fh : f_hz) {
    const cd s(0.0, 2.0 * M_PI * fh);
    const cd amp = 1.0 / (1.0 + s * be.actuator_lag_s);
    const cd k = f.controller_force_per_m(fh) / be.ki_n_per_a;
    out.push_back(amp / (1.0 + k * f.sensor_displacement(fh) * amp));
  }
  return out;
}

// Fit the real injection gain (closed form, weighted) and the error figures.
void fit_gain(const std::vector<cd>& meas, std::vector<cd>& model, const std::vector<double>& w, double& gain, FrfErrors& e) {
  cd num = 0.0;
  double den = 0.0;
  for (size_t i = 0; i < meas.size(); ++i) {
    num += w[i] * std::conj(model[i]) * meas[i];
    den += w[i] * std::norm(model[i]);
  }
  gain = den > 0.0 ? (num / den).real() : 0.0;
  for (auto& x : model) x *= gain;
  FrfFitData d;
  d.h = {meas};
  d.w = {w};
  d.f_hz.assign(meas.size(), 0.0);
  e = frf_errors(d, {model}, {0});
}

}  // namespace

TumSweep read_tum_sweep(const std::string& dir) {
  const std::string in_mat = dir + "/Sweep_Time_Anregung.mat", out_mat = dir + "/Sweep_Time_Ausgang.mat";
  TumSweep s;
  s.current_a = read_mat_vector(in_mat, "Signal.y_values.values");
  const double dt = read_mat_scalar(in_mat, "Signal.x_values.increment");
  if (!(dt > 0.0)) throw std::runtime_error(in_mat + ": sample increment is not positive");
  s.fs_hz = 1.0 / dt;
  const auto acc = read_mat_matrix(out_mat, "Signal_0.y_values.values");
  s.accel_display_factor = read_mat_scalar(out_mat, "Signal_0.y_values.quantity.unit_transformation.factor");
  for (size_t c = 0; c < acc.cols; ++c) s.accel_m_s2.push_back(acc.column(c));  // stored in MKS: m/s^2
  s.command_v = read_mat_vector(out_mat, "Signal_1.y_values.values");
  const double dt1 = read_mat_scalar(out_mat, "Signal_0.x_values.increment");
  if (std::abs(dt1 / dt - 1.0) > 1e-9) throw std::runtime_error(out_mat + ": sample increment differs from the excitation file's");
  if (s.command_v.size() != s.current_a.size()) s.command_v.clear();
  return s;
}

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
                                const board::BoardConfig& b, const SweepOptions& o, const std::vector<double>& command_v) {
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
  const PeakOptions po{o.f_min_hz, o.f_max_hz, std::min(0.5, o.min_coherence), 3.0};
  const auto peaks = find_peaks(zp.f_hz, zp.h, zp.coherence, po);
  const auto norms = channel_norms(zp.f_hz, zp.h, zp.coherence, po);
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
      const auto f = evaluate_fit(t, values_of(t), d, all);
      if (f.cost < nominal.cost) { nominal = f; m = t; }
    }
  out.before = to_eval(m, nominal, d, all, 0);
  out.modes_before = match_modes(m, nominal, peaks, norms, zp);
  const auto nominal_positions = nominal.accel_axial_m;
  const int full = o.max_evaluations, screen = o.screen_evaluations;

  const double len = model::analysis::HalfOpenFrf(to_model(m, values_of(m))).length_m();

  // Candidate elements. Each adds its parameters with a start chosen by evaluating a few
  // physically distinct starts (accelerometers at their current positions).
  struct Candidate {
    std::string name, what;
    std::function<bool(UpdateModel&, std::vector<double>&)> add;  // false: already in the model
  };
  auto best_start = [&](const UpdateModel& base, const std::vector<double>& v0,
                        const std::vector<std::function<void(UpdateModel&)>>& starts, UpdateModel& tm, std::vector<double>& tv) {
    double bc = k_inf;
    for (const auto& st : starts) {
      UpdateModel t = base;
      st(t);
      std::vector<double> v = v0;
      for (size_t i = v0.size(); i < t.p.size(); ++i) v.push_back(t.p[i].value);
      t.fixed_positions = true;
      const double c = evaluate_fit(t, v, d, all).cost;
      if (c < bc) { bc = c; tm = t; tv = v; }
    }
    tm.fixed_positions = false;
  };
  // Resonator starts: between each pair of close measured peaks (a split mode) and at each
  // peak, at positions along the shaft.
  std::vector<double> rstarts;
  for (size_t k = 0; k + 1 < peak_hz.size(); ++k)
    if (peak_hz[k + 1] / peak_hz[k] < 1.08) rstarts.push_back(0.5 * (peak_hz[k] + peak_hz[k + 1]));
  for (double f : peak_hz) rstarts.push_back(f);
  std::vector<Candidate> cands;
  cands.push_back({"sensor_mass", "accelerometer masses on the shaft", [&](UpdateModel& t, std::vector<double>& v) {
                     if (t.sensor_mass) return false;
                     add_sensor_mass(t, 0.005);
                     v.push_back(0.005);
                     return true;
                   }});
  cands.push_back({"amplifier_lag", "current-amplifier lag in the closed bearing's loop freed (the board's 1 kHz bandwidth held otherwise)",
                   [&](UpdateModel& t, std::vector<double>&) {
                     for (const auto& p : t.p)
                       if (p.name == "amplifier_lag_s" && p.free) return false;
                     free_amplifier_lag(t);
                     return true;
                   }});
  cands.push_back({"eddy_current_lag", "eddy currents in the AMB iron (force and negative stiffness through 1 / (1 + sqrt(s te)))",
                   [&](UpdateModel& t, std::vector<double>& v) {
                     if (t.eddy) return false;
                     UpdateModel tm;
                     std::vector<double> tv;
                     std::vector<std::function<void(UpdateModel&)>> st;
                     for (double te : {1e-5, 1e-4, 1e-3}) st.push_back([te](UpdateModel& x) { add_eddy(x, te); });
                     best_start(t, v, st, tm, tv);
                     t = tm;
                     v = tv;
                     return true;
                   }});
  for (double z : {0.0, len})
    cands.push_back({"drive_coupling", io::printf_text("drive coupling mass on the shaft end at %.0f mm", z * 1e3), [&, z](UpdateModel& t, std::vector<double>& v) {
                       if (t.coupling) return false;
                       add_coupling(t, z, 0.02);
                       v.push_back(0.02);
                       return true;
                     }});
  cands.push_back({"attached_resonator", "a part attached to the shaft through a compliant joint", [&](UpdateModel& t, std::vector<double>& v) {
                     if (t.resonator) return false;
                     UpdateModel tm;
                     std::vector<double> tv;
                     std::vector<std::function<void(UpdateModel&)>> st;
                     for (double f0 : rstarts)
                       for (double z = 0.05; z < len; z += 0.1)
                         for (double mr : {0.001, 0.01}) st.push_back([=](UpdateModel& x) { add_resonator(x, z, mr, f0, 0.01); });
                     best_start(t, v, st, tm, tv);
                     // Its position is not separable from its mass (only m phi(z)^2 near the split
                     // mode counts): held at the best grid position, the rest fitted.
                     for (auto& p : tm.p)
                       if (p.name == "resonator_axial_m") p.free = false;
                     t = tm;
                     v = tv;
                     return true;
                   }});
  for (int j : {0, 1})
    cands.push_back({"pedestal_resonance", io::printf_text("housing / foundation mode at the AMB at %.0f mm", m.base.bearing[static_cast<size_t>(j)].axial_m * 1e3),
                     [&, j](UpdateModel& t, std::vector<double>& v) {
                       if (t.housing) return false;
                       UpdateModel tm;
                       std::vector<double> tv;
                       std::vector<std::function<void(UpdateModel&)>> st;
                       for (double f0 : {60.0, 120.0, 250.0, 450.0})
                         for (double mh : {1.0, 5.0}) st.push_back([=](UpdateModel& x) { add_housing(x, j, f0, mh, 0.05); });
                       best_start(t, v, st, tm, tv);
                       t = tm;
                       v = tv;
                       return true;
                     }});

  // One track per reading of the current channel: the board's own parameters updated, then
  // forward selection of the elements.
  struct Track {
    UpdateModel m;
    FrfFit updated, cur;
    std::vector<CandidateScore> ranking;
    std::vector<EffectAdded> effects;
    std::vector<std::string> bounds;
    double bic = 0.0;
    int rank_deficit = 0;  // of the current model's Jacobian
  };
  auto bounds_of = [&](const UpdateModel& t, const std::vector<double>& v, size_t from) {
    std::vector<std::string> b2;
    for (size_t i = from; i < t.p.size(); ++i)
      if (at_bound(t.p[i], v[i])) b2.push_back(t.p[i].name);
    return b2;
  };
  auto run_track = [&](double channel) {
    Track tr;
    tr.m = m;
    tr.m.current_channel = channel;
    tr.updated = update(tr.m, values_of(tr.m), d, all, peak_hz, norms, nominal_positions, full);
    tr.cur = tr.updated;
    double bic = bic_of(tr.m, tr.cur, d, all);
    {
      const auto id = identifiability(tr.m, tr.cur, d);
      tr.rank_deficit = static_cast<int>(id.names.size()) - id.rank;
    }
    std::vector<bool> done(cands.size(), false);
    for (int round = 1; round <= static_cast<int>(cands.size()); ++round) {
      struct Tried { size_t k; UpdateModel t; FrfFit f; double dbic; };
      std::vector<Tried> tried;
      for (size_t k = 0; k < cands.size(); ++k) {
        if (done[k]) continue;
        UpdateModel t = tr.m;
        std::vector<double> v = tr.cur.values;
        t.mass_axial_m = tr.cur.accel_axial_m;
        if (!cands[k].add(t, v)) { done[k] = true; continue; }
        const FrfFit f = update(t, v, d, all, peak_hz, norms, tr.cur.accel_axial_m, screen, true);
        tried.push_back({k, t, f, bic - bic_of(t, f, d, all)});
      }
      std::sort(tried.begin(), tried.end(), [](const Tried& a2, const Tried& c2) { return a2.dbic > c2.dbic; });
      bool added = false;
      for (auto& t1 : tried) {
        if (!(t1.dbic > o.criterion.min_delta_ic)) break;  // the screening already shows it does not earn its parameters
        UpdateModel t = t1.t;
        const FrfFit f = update(t, t1.f.values, d, all, peak_hz, norms, tr.cur.accel_axial_m, full);
        const double dbic = bic - bic_of(t, f, d, all);
        auto own = bounds_of(t, f.values, tr.m.p.size());
        if (cands[t1.k].name == "amplifier_lag")
          for (const auto& n : bounds_of(t, f.values, 0))
            if (n == "amplifier_lag_s") own.push_back(n);
        done[t1.k] = true;
        // Identified: no own parameter on its bound, the Jacobian keeps full rank and no own
        // parameter is interchangeable with another (|correlation| >= 0.99): else the data
        // cannot tell it from what is there.
        std::string why;
        for (const auto& n : own) why += (why.empty() ? "" : "; ") + n + " on its bound";
        if (why.empty()) {
          const auto id = identifiability(t, f, d);
          // A rank deficit counts against the candidate only when its own parameters make up
          // most of the unidentified directions: a deficit carried by parameters already there
          // (e.g. a loop delay the data barely see) says nothing about the new element.
          const int deficit = static_cast<int>(id.names.size()) - id.rank;
          double own_share = 0.0;
          const std::string name = cands[t1.k].name;
          for (size_t a2 = 0; a2 < id.names.size(); ++a2)
            if (element_of(id.names[a2]) == name || (name == "amplifier_lag" && id.names[a2] == "amplifier_lag_s"))
              own_share += id.null_share[a2];
          if (deficit > tr.rank_deficit && own_share > 0.5 * (deficit - tr.rank_deficit))
            why = io::printf_text("Jacobian rank %d of %.0f", id.rank, static_cast<double>(id.names.size())) +
                  io::printf_text(", its own parameters %.0f %% of the unidentified directions", 100.0 * own_share / deficit);
          for (size_t a2 = 0; a2 < id.names.size(); ++a2)
            for (size_t b2 = 0; b2 < id.names.size(); ++b2)
              if (a2 != b2 && (element_of(id.names[a2]) == name || (name == "amplifier_lag" && id.names[a2] == "amplifier_lag_s")) &&
                  std::abs(id.correlation[a2][b2]) >= 0.99 && element_of(id.names[b2]) != name)
                why += (why.empty() ? "" : "; ") + id.names[a2] + " and " + id.names[b2] + io::printf_text(" correlated %.3f", id.correlation[a2][b2]);
        }
        // The engine's criterion (engine/criterion.hpp). The misfit is coherence-weighted
        // (the H1 estimator's noise), so its decrease is the element's effect in noise units.
        engine::CandidateEvidence ce;
        ce.element = cands[t1.k].name;
        ce.evidence = cands[t1.k].what + io::printf_text(" (round %d): misfit %.5g -> %.5g", round, tr.cur.cost, f.cost);
        ce.delta_ic = dbic;
        ce.ic_basis = "BIC of the FRF: complex Gaussian per bin with the H1 estimator's coherence-based variance";
        ce.effect_sigma = std::sqrt(std::max(0.0, tr.cur.cost - f.cost));
        ce.identified = why.empty();
        ce.not_identified = why;
        ce.decision.push_back({"coherence-weighted FRF misfit", "1", tr.cur.cost, f.cost});
        const engine::Decision dec = engine::decide(ce, o.criterion);
        CandidateScore cs = scored(ce, dec);
        if (!dec.kept) {
          cs.evidence += ": not added (" + dec.reason + ")";
          tr.ranking.push_back(cs);
          continue;
        }
        cs.evidence += ": added";
        tr.rank_deficit = [&] {
          const auto id = identifiability(t, f, d);
          return static_cast<int>(id.names.size()) - id.rank;
        }();
        tr.ranking.push_back(cs);
        EffectAdded e;
        e.name = cs.name;
        e.delta_bic = dbic;
        e.evidence = cs.evidence;
        for (size_t i = tr.m.p.size(); i < t.p.size(); ++i) e.parameters.emplace_back(t.p[i].name, f.values[i]);
        if (cs.name == "drive_coupling") e.parameters.emplace_back("coupling_axial_m", t.coupling_axial_m);
        if (cs.name == "amplifier_lag") e.parameters.emplace_back("amplifier_lag_s", value_in(t, f.values, "amplifier_lag_s"));
        tr.effects.push_back(e);
        for (size_t i = 0; i < t.p.size(); ++i) t.p[i].value = f.values[i];
        tr.m = t;
        tr.cur = f;
        bic = bic_of(tr.m, tr.cur, d, all);
        added = true;
        break;
      }
      if (!added) {
        // Nothing more earns its parameters: the last screening of each remaining candidate.
        for (auto& t1 : tried)
          if (!done[t1.k]) {
            CandidateScore cs;
            cs.name = cands[t1.k].name;
            cs.delta_bic = t1.dbic;
            cs.evidence = cands[t1.k].what + io::printf_text(" (round %d): screening BIC decrease %.1f: not added", round, t1.dbic);
            tr.ranking.push_back(cs);
          }
        break;
      }
    }
    for (size_t i = 0; i < tr.m.p.size(); ++i) tr.m.p[i].value = tr.cur.values[i];
    tr.bounds = bounds_of(tr.m, tr.cur.values, 0);
    tr.bic = bic;
    return tr;
  };
  // The current channel: "Point10" is the control current, or the difference of the axis' two
  // coil currents (twice it). Each reading gets its own track; a reading that leaves a
  // parameter on a bound loses, then the lower BIC wins.
  Track best;
  double best_score = k_inf;
  for (double c : {1.0, 2.0}) {
    Track tr = run_track(c);
    if (std::getenv("AMB_SWEEP_DEBUG")) {
      std::fprintf(stderr, "track c=%.0f: updated cost %.6g, final cost %.6g BIC %.6g\n", c, tr.updated.cost, tr.cur.cost, tr.bic);
      for (const auto& r : tr.ranking) std::fprintf(stderr, "   %s %.1f %s\n", r.name.c_str(), r.delta_bic, r.evidence.c_str());
      for (size_t i = 0; i < tr.m.p.size(); ++i) std::fprintf(stderr, "   %-26s %.5g%s\n", tr.m.p[i].name.c_str(), tr.cur.values[i], at_bound(tr.m.p[i], tr.cur.values[i]) ? " AT BOUND" : "");
    }
    std::string ev = io::printf_text(c == 1.0 ? "read as the control current: BIC %.6g after updating, %.6g with the elements; force gain %.1f N/A"
                                  : "read as the difference of the two coil currents (2x the control current): BIC %.6g after updating, "
                                    "%.6g with the elements; force gain %.1f N/A per control ampere",
                         bic_of(m, tr.updated, d, all), tr.bic, value_in(tr.m, tr.cur.values, "force_gain_n_per_a"));
    for (const auto& n : tr.bounds) ev += "; " + n + " on its bound";
    out.channel_evidence.push_back(ev);
    const double score = tr.bic + (tr.bounds.empty() ? 0.0 : 1e12);
    if (score < best_score) { best_score = score; best = std::move(tr); }
  }
  m = best.m;
  FrfFit cur = best.cur;
  out.current_channel = m.current_channel;
  out.updated = to_eval(m, best.updated, d, all, [&] {
    int n = 0;
    for (const auto& p : m.p) n += p.free && element_of(p.name).empty() ? 1 : 0;
    return n;
  }());
  out.ranking = best.ranking;
  out.effects_added = best.effects;
  if (m.current_channel != 1.0) {
    EffectAdded e;
    e.name = "current_channel";
    e.parameters.emplace_back("measured_per_control_ampere", m.current_channel);
    e.evidence = "the excitation channel reads twice the control current (the difference of the axis' two coil currents): " +
                 out.channel_evidence[0] + " | " + out.channel_evidence[1];
    out.effects_added.insert(out.effects_added.begin(), e);
  }
  for (const char* nt : {"sensor_runout", "aux_bearing_offset"})
  {
    CandidateScore c;
    c.name = nt;
    c.testable = false;
    c.delta_bic = -k_inf;
    c.evidence = "no rotation / no rest or contact segment in a standstill sweep: not testable";
    out.ranking.push_back(c);
  }
  // Final values: added elements' parameters in effects_added follow the last refit.
  for (auto& a : out.effects_added)
    for (auto& [n, v] : a.parameters)
      if (has_parameter(m, n)) v = value_in(m, cur.values, n);
  for (size_t i = 0; i < m.p.size(); ++i) m.p[i].value = cur.values[i];
  out.after = to_eval(m, cur, d, all, free_count(m));
  out.parameters = m.p;
  for (const auto& p : m.p) out.parameter_at_bound.push_back(at_bound(p, p.value));
  out.modes_after = match_modes(m, cur, peaks, norms, zp);
  out.identifiability = identifiability(m, cur, d);

  // Validation: fit on half the accelerometers, check on the other half, both ways.
  if (o.validate && nch >= 2) {
    for (int split = 0; split < 2; ++split) {
      ValidationRun vr;
      for (size_t c = 0; c < nch; ++c) (static_cast<int>(c % 2) == split ? vr.fit_channels : vr.check_channels).push_back(c);
      UpdateModel t = m;
      for (auto& p : t.p) p.value = p.nominal;
      const FrfFit f = update(t, values_of(t), d, vr.fit_channels, peak_hz, norms, nominal_positions, full);
      vr.fit = frf_errors(d, f.h_model, vr.fit_channels);
      vr.check = frf_errors(d, f.h_model, vr.check_channels);
      vr.check_nominal = frf_errors(d, nominal.h_model, vr.check_channels);
      vr.h_model = f.h_model;
      out.validation.push_back(vr);
    }
  }

  // The other record type: the excited bearing's current per sweep voltage.
  if (command_v.size() == input.size()) {
    auto& cl = out.current_loop;
    SweepOptions oi = o;
    oi.exclude_spans_s = oe.exclude_spans_s;
    oi.zero_pad = 1;
    const SweepFrf iv = estimate_frf(command_v, {input}, fs, oi);
    std::vector<double> w;
    for (size_t k = 0; k < iv.f_hz.size(); ++k) {
      if (iv.f_hz[k] < o.f_min_hz || iv.f_hz[k] > o.f_max_hz) continue;
      const double g = std::min(iv.coherence[0][k], 0.98);
      cl.f_hz.push_back(iv.f_hz[k]);
      cl.measured.push_back(iv.h[0][k]);
      cl.compared.push_back(g >= o.min_coherence);
      w.push_back(g >= o.min_coherence ? g / (1.0 - g) : 0.0);
    }
    cl.model = current_loop_model(m, cur.values, cl.f_hz);
    fit_gain(cl.measured, cl.model, w, cl.gain, cl.error);
    UpdateModel nb = m;
    std::vector<double> nv = values_of(nb);
    for (size_t i = 0; i < nb.p.size(); ++i) nv[i] = nb.p[i].nominal;
    auto board_model = current_loop_model(nb, nv, cl.f_hz);
    double g0 = 0.0;
    fit_gain(cl.measured, board_model, w, g0, cl.error_board);
    cl.done = true;
  }

  // Notes.
  out.notes.push_back(io::printf_text("compared band %.0f-%.0f Hz where coherence >= %.2f per channel: %.0f of the channel-bins", o.f_min_hz,
                          o.f_max_hz, o.min_coherence, out.after.data_points / 2.0));
  for (const auto& s : out.nonlinear) out.notes.push_back(io::printf_text("nonlinear stretch %.2f-%.2f s left out: ", s.t0_s, s.t1_s) + s.reason);
  out.notes.push_back(io::printf_text("excited: the AMB at %.0f mm (current as input, the other bearing closed), sign %+.0f",
                          m.base.bearing[static_cast<size_t>(m.base.excited)].axial_m * 1e3, m.sign));
  for (const auto& e : out.channel_evidence) out.notes.push_back("current channel " + e);
  std::string pos = "accelerometer positions fitted (mm):";
  for (double z : out.after.accel_axial_m) pos += io::printf_text(" %.0f", z * 1e3);
  out.notes.push_back(pos);
  for (const auto& mm : out.modes_after) {
    out.notes.push_back(io::printf_text("peak %.2f Hz: model %.2f Hz (%+.2f %%), MAC %.3f", mm.measured_hz, mm.model_hz, mm.error_pct, mm.mac));
    out.notes.push_back(io::printf_text("  modal fit: measured %.2f Hz (damping %.2f %%), model %.2f Hz (%.2f %%): %+.2f %%", mm.ema_measured_hz,
                            100.0 * mm.ema_measured_zeta, mm.ema_model_hz, 100.0 * mm.ema_model_zeta, mm.ema_error_pct) +
                        io::printf_text(", residue MAC %.3f", mm.ema_mac));
  }
  for (const auto& n : out.identifiability.notes) out.notes.push_back("identifiability: " + n);
  for (size_t i = 0; i < out.parameters.size(); ++i)
    if (out.parameter_at_bound[i]) out.notes.push_back("parameter on its bound: " + out.parameters[i].name);
  if (out.current_loop.done)
    out.notes.push_back(io::printf_text("current per sweep voltage (not fitted; injection gain %.3g A/V): %.2f dB rms, Pearson %.3f (board model %.2f dB, %.3f)",
                            out.current_loop.gain, out.current_loop.error.spectral_db, out.current_loop.error.pearson,
                            out.current_loop.error_board.spectral_db, out.current_loop.error_board.pearson));
  std::string v;
  for (const auto& a : out.effects_added) v += (v.empty() ? "" : "+") + a.name;
  out.verdict = v.empty() ? "none" : v;
  return out;
}

}  // namespace amb::host::residual
