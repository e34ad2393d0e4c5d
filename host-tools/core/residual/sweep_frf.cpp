#include "host-tools/core/residual/sweep_frf.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fftw3.h>
#include <limits>

#include "host-tools/core/residual/nelder_mead.hpp"
#include "model/effects/effect_loop_model.hpp"
#include "model/rotor/rotor_model.hpp"

namespace amb::host::residual {
namespace {

using cd = std::complex<double>;
using model::effects::EffectKind;
using model::effects::EffectSet;
constexpr double k_inf = std::numeric_limits<double>::infinity();
constexpr double k_grid_m = 0.005;   // accelerometer position grid, m

std::string fmt(const char* f, double a, double b = 0.0, double c = 0.0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, f, a, b, c);
  return buf;
}

struct Problem {
  const SweepFrf& frf;
  const board::BoardConfig& b;
  const SweepOptions& o;
  std::vector<size_t> bins;            // bins used in the fit
  std::vector<std::vector<double>> w;  // [channel][bin] weights
  std::vector<double> grid;            // candidate positions, m
  double length_m = 0.0;
  double rotor_mass_kg = 0.0;
};

SweepFitEvaluation evaluate(const Problem& p, const EffectSet& fx, int axis, double gain) {
  SweepFitEvaluation ev;
  ev.effects = fx;
  ev.excited_axis = axis;
  ev.gain_scale = gain;
  board::BoardConfig b = p.b;
  b.controller.kp_n_per_m *= gain;
  b.controller.ki_n_per_m_s *= gain;
  b.controller.kd_n_s_per_m *= gain;
  const model::effects::EffectLoopModel m(b.plant, b.controller, b.rate_hz, 0.0, fx);
  std::vector<model::effects::AccelPoint> pts;
  for (double z : p.grid) pts.push_back({z, 0.0});
  const size_t nch = p.frf.h.size(), ng = p.grid.size(), nb = p.bins.size();
  // model[grid][bin]
  std::vector<std::vector<cd>> hm(ng, std::vector<cd>(nb));
  for (size_t i = 0; i < nb; ++i) {
    const auto r = m.at(p.frf.f_hz[p.bins[i]], pts);
    const cd cur = r.injection(4 + axis, axis);
    for (size_t g = 0; g < ng; ++g) hm[g][i] = r.accel_injection(static_cast<Eigen::Index>(g), axis) / cur;
  }
  ev.accel_axial_m.assign(nch, 0.0);
  ev.h_model.assign(nch, std::vector<cd>(p.frf.f_hz.size(), cd(0.0, 0.0)));
  double cost = 0.0, wsum = 0.0, e_ln = 0.0, e_db = 0.0, pr = 0.0;
  for (size_t c = 0; c < nch; ++c) {
    double best = k_inf;
    size_t bg = 0;
    for (size_t g = 0; g < ng; ++g) {
      double s = 0.0;
      for (size_t i = 0; i < nb; ++i) s += p.w[c][i] * std::norm(std::log(p.frf.h[c][p.bins[i]] / hm[g][i]));
      if (s < best) { best = s; bg = g; }
    }
    ev.accel_axial_m[c] = p.grid[bg];
    cost += best;
    std::vector<double> a, q;
    for (size_t i = 0; i < nb; ++i) {
      ev.h_model[c][p.bins[i]] = hm[bg][i];
      const cd lr = std::log(p.frf.h[c][p.bins[i]] / hm[bg][i]);
      wsum += p.w[c][i];
      e_ln += p.w[c][i] * std::norm(lr);
      e_db += p.w[c][i] * std::pow(20.0 / std::log(10.0) * lr.real(), 2);
      a.push_back(std::log(std::abs(p.frf.h[c][p.bins[i]])));
      q.push_back(std::log(std::abs(hm[bg][i])));
    }
    double ma = 0, mq = 0;
    for (size_t i = 0; i < a.size(); ++i) { ma += a[i]; mq += q[i]; }
    ma /= static_cast<double>(a.size());
    mq /= static_cast<double>(a.size());
    double sab = 0, saa = 0, sbb = 0;
    for (size_t i = 0; i < a.size(); ++i) {
      sab += (a[i] - ma) * (q[i] - mq);
      saa += (a[i] - ma) * (a[i] - ma);
      sbb += (q[i] - mq) * (q[i] - mq);
    }
    pr += saa > 0 && sbb > 0 ? sab / std::sqrt(saa * sbb) : 0.0;
  }
  ev.cost = cost;
  ev.error.rms = std::sqrt(e_ln / wsum);
  ev.error.spectral = std::sqrt(e_db / wsum);
  ev.error.pearson = pr / static_cast<double>(nch);
  ev.parameters = 2 + static_cast<int>(nch);
  for (int k = 0; k < model::effects::k_effect_kinds; ++k)
    if (fx.has(static_cast<EffectKind>(k))) ev.parameters += element_parameters(static_cast<EffectKind>(k));
  ev.data_points = static_cast<int>(2 * nch * nb);
  ev.bic = cost + ev.parameters * std::log(static_cast<double>(ev.data_points));
  return ev;
}

// Nonlinear parameters: [ln gain, element logs...].
std::vector<double> pack(const EffectSet& e, double gain) {
  std::vector<double> x{std::log(gain)};
  if (e.pedestal) {
    x.push_back(std::log(e.pedestal->frequency_hz));
    x.push_back(std::log(e.pedestal->damping_ratio));
    x.push_back(std::log(e.pedestal->mass_kg));
  }
  if (e.amplifier_lag) x.push_back(std::log(e.amplifier_lag->time_constant_s));
  if (e.rotor_mode) x.push_back(std::log(e.rotor_mode->frequency_scale));
  if (e.saturation) x.push_back(std::log(e.saturation->saturation_current_a));
  if (e.sensor_mass) x.push_back(std::log(e.sensor_mass->mass_kg));
  return x;
}

std::pair<EffectSet, double> unpack(const std::vector<double>& x, EffectSet e, const Problem& p) {
  size_t i = 0;
  auto get = [&](double lo, double hi) { return std::clamp(std::exp(x[i++]), lo, hi); };
  const double gain = get(0.2, 5.0);
  if (e.pedestal) {
    e.pedestal->frequency_hz = get(3.0, p.o.f_max_hz);
    e.pedestal->damping_ratio = get(0.003, 0.7);
    e.pedestal->mass_kg = get(0.01 * p.rotor_mass_kg, 100.0 * p.rotor_mass_kg);
  }
  if (e.amplifier_lag) e.amplifier_lag->time_constant_s = get(1e-6, 0.02);
  if (e.rotor_mode) e.rotor_mode->frequency_scale = get(0.5, 2.0);
  if (e.saturation) e.saturation->saturation_current_a = get(0.3 * p.b.plant.amb[0].bias_current_a, 100.0 * p.b.plant.amb[0].bias_current_a);
  if (e.sensor_mass) e.sensor_mass->mass_kg = get(1e-4, 0.2);
  return {e, gain};
}

SweepFitEvaluation refine(const Problem& p, const EffectSet& e, int axis, double gain, int max_eval) {
  auto f = [&](const std::vector<double>& x) {
    const auto [ee, g] = unpack(x, e, p);
    try {
      const double v = evaluate(p, ee, axis, g).cost;
      return std::isfinite(v) ? v : k_inf;
    } catch (const std::exception&) {
      return k_inf;
    }
  };
  const auto r = nelder_mead(f, pack(e, gain), 0.2, max_eval, 1e-2);
  const auto [ee, g] = unpack(r.x, e, p);
  return evaluate(p, ee, axis, g);
}

}  // namespace

SweepFrf estimate_frf(const std::vector<double>& x, const std::vector<std::vector<double>>& ys, double fs, const SweepOptions& o) {
  SweepFrf r;
  const int seg = static_cast<int>(o.segment_s * fs), hop = seg / 2, nb = seg / 2 + 1;
  std::vector<double> win(static_cast<size_t>(seg)), in(static_cast<size_t>(seg));
  for (int i = 0; i < seg; ++i) win[static_cast<size_t>(i)] = 0.5 - 0.5 * std::cos(2.0 * M_PI * i / seg);
  std::vector<fftw_complex> out(static_cast<size_t>(nb));
  fftw_plan plan = fftw_plan_dft_r2c_1d(seg, in.data(), out.data(), FFTW_ESTIMATE);
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
    if (t1 > o.exclude_t0_s && t0 < o.exclude_t1_s) continue;
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
    r.f_hz.push_back(k * fs / seg);
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
  out.frf = estimate_frf(input, outputs, fs, o);
  Problem p{out.frf, b, o, {}, {}, {}, 0.0, 0.0};
  const auto fe = model::rotor::build_rotor_model(b.plant.rotor);
  p.length_m = fe.length_m;
  p.rotor_mass_kg = fe.mass_kg;
  for (double z = 0.0; z <= p.length_m + 1e-9; z += k_grid_m) p.grid.push_back(z);
  for (size_t k = 0; k < out.frf.f_hz.size(); ++k) {
    const double f = out.frf.f_hz[k];
    if (f < o.f_min_hz || f > o.f_max_hz || (f >= o.exclude_f0_hz && f <= o.exclude_f1_hz)) continue;
    p.bins.push_back(k);
  }
  p.w.assign(outputs.size(), std::vector<double>(p.bins.size()));
  for (size_t c = 0; c < outputs.size(); ++c)
    for (size_t i = 0; i < p.bins.size(); ++i) {
      const double g = std::min(out.frf.coherence[c][p.bins[i]], 0.98);
      p.w[c][i] = out.frf.segments * g / (1.0 - g);
    }

  // Base fit: excited AMB (discrete) and the gain scale; positions inside every evaluation.
  SweepFitEvaluation best;
  best.cost = k_inf;
  for (int axis : {0, 2}) {
    const auto ev = refine(p, {}, axis, 1.0, o.max_evaluations / 2);
    if (ev.cost < best.cost) best = ev;
  }
  out.before = best;
  SweepFitEvaluation now = best;
  EffectSet current;
  const std::vector<EffectKind> kinds{EffectKind::pedestal_resonance, EffectKind::amplifier_lag, EffectKind::rotor_mode,
                                      EffectKind::magnetic_saturation, EffectKind::sensor_mass};
  // Structure: measured/model magnitude ratio per bin (mean over channels, smoothed).
  auto structure = [&](const SweepFitEvaluation& ev) {
    std::vector<std::string> notes;
    const size_t nb = p.bins.size();
    std::vector<double> r(nb, 0.0), s(nb, 0.0);
    for (size_t i = 0; i < nb; ++i) {
      double a = 0.0, ws = 0.0;
      for (size_t c = 0; c < outputs.size(); ++c) {
        a += p.w[c][i] * 20.0 * std::log10(std::abs(out.frf.h[c][p.bins[i]]) / std::abs(ev.h_model[c][p.bins[i]]));
        ws += p.w[c][i];
      }
      r[i] = ws > 0 ? a / ws : 0.0;
    }
    for (size_t i = 0; i < nb; ++i) {
      double a = 0.0;
      int n = 0;
      for (size_t j = (i > 2 ? i - 2 : 0); j <= std::min(nb - 1, i + 2); ++j, ++n) a += r[j];
      s[i] = a / n;
    }
    std::vector<std::pair<double, double>> ex;
    for (size_t i = 1; i + 1 < nb; ++i)
      if (std::abs(s[i]) > 6.0 && std::abs(s[i]) >= std::abs(s[i - 1]) && std::abs(s[i]) >= std::abs(s[i + 1]))
        ex.emplace_back(out.frf.f_hz[p.bins[i]], s[i]);
    std::sort(ex.begin(), ex.end(), [](const auto& x, const auto& y) { return std::abs(x.second) > std::abs(y.second); });
    for (size_t i = 0; i < std::min<size_t>(5, ex.size()); ++i)
      notes.push_back(fmt(ex[i].second > 0 ? "measured FRF above the model at %.1f Hz by %.1f dB (fixed frequency, no speed)"
                                           : "model FRF above the measured at %.1f Hz by %.1f dB",
                          ex[i].first, std::abs(ex[i].second)));
    std::string pos = "accelerometer positions fitted (mm):";
    for (double z : ev.accel_axial_m) pos += fmt(" %.0f", z * 1e3);
    notes.push_back(pos);
    notes.push_back(fmt("excited actuator axis %.0f (0: AMB at 113 mm, 2: AMB at 623 mm), PID gain scale %.3f", ev.excited_axis, ev.gain_scale));
    return notes;
  };
  out.notes = structure(best);

  for (int round = 0; round < o.max_effects; ++round) {
    std::vector<CandidateScore> scores;
    std::vector<SweepFitEvaluation> fits;
    for (EffectKind k : kinds) {
      if (current.has(k)) continue;
      std::vector<EffectSet> starts;
      auto with = [&](auto setter) { EffectSet e = current; setter(e); starts.push_back(e); };
      switch (k) {
        case EffectKind::pedestal_resonance:
          for (int plane = 0; plane < 2; ++plane)
            for (double f = 12.0; f < o.f_max_hz; f *= 1.5)
              with([&](EffectSet& e) { e.pedestal = model::effects::PedestalResonance{plane, p.rotor_mass_kg, f, 0.05}; });
          break;
        case EffectKind::amplifier_lag:
          for (double tau = 5e-5; tau < 5e-3; tau *= 2.5) with([&](EffectSet& e) { e.amplifier_lag = model::effects::AmplifierLag{tau}; });
          break;
        case EffectKind::rotor_mode:
          for (double sc = 0.8; sc < 1.25; sc *= 1.04) with([&](EffectSet& e) { e.rotor_mode = model::effects::RotorMode{sc}; });
          break;
        case EffectKind::magnetic_saturation:
          for (double ratio = 0.6; ratio < 20.0; ratio *= 1.6)
            with([&](EffectSet& e) { e.saturation = model::effects::MagneticSaturation{ratio * b.plant.amb[0].bias_current_a}; });
          break;
        case EffectKind::sensor_mass:
          for (double mk = 0.002; mk < 0.05; mk *= 1.8)
            with([&](EffectSet& e) { e.sensor_mass = model::effects::SensorMass{mk, now.accel_axial_m}; });
          break;
        default: break;
      }
      std::vector<std::pair<double, size_t>> sc;
      for (size_t i = 0; i < starts.size(); ++i) {
        double v = k_inf;
        try { v = evaluate(p, starts[i], now.excited_axis, now.gain_scale).cost; } catch (const std::exception&) {}
        sc.emplace_back(v, i);
      }
      std::sort(sc.begin(), sc.end());
      const auto ev = refine(p, starts[sc.front().second], now.excited_axis, now.gain_scale, o.max_evaluations);
      CandidateScore c;
      c.name = model::effects::effect_name(k);
      c.delta_bic = now.bic - ev.bic;
      std::string pars;
      for (const auto& [n, v] : effect_parameters(ev.effects, k)) pars += " " + n + "=" + fmt("%.4g", v);
      c.evidence = "FRF misfit falls from " + fmt("%.3g to %.3g", now.cost, ev.cost) + " with" + pars + fmt("; BIC decrease %.1f", c.delta_bic);
      scores.push_back(c);
      fits.push_back(ev);
    }
    for (const char* nt : {"sensor_runout", "aux_bearing_offset"})
      if (round == 0) scores.push_back({nt, false, -k_inf, "no rotation / no rest or contact segment in a standstill sweep: not testable"});
    std::vector<size_t> idx;
    for (size_t i = 0; i < fits.size(); ++i) idx.push_back(i);
    std::sort(idx.begin(), idx.end(), [&](size_t a, size_t c) { return scores[a].delta_bic > scores[c].delta_bic; });
    if (round == 0) {
      for (size_t i : idx) out.ranking.push_back(scores[i]);
      for (size_t i = fits.size(); i < scores.size(); ++i) out.ranking.push_back(scores[i]);
    }
    if (idx.empty() || !(scores[idx[0]].delta_bic > o.min_delta_bic)) break;
    const auto& ev = fits[idx[0]];
    current = ev.effects;
    now = ev;
    EffectAdded a;
    a.name = scores[idx[0]].name;
    a.delta_bic = scores[idx[0]].delta_bic;
    a.evidence = scores[idx[0]].evidence;
    out.effects_added.push_back(a);
  }
  for (auto& a : out.effects_added) a.parameters = effect_parameters(current, *model::effects::effect_from_name(a.name));
  out.after = now;
  std::string v;
  for (const auto& a : out.effects_added) v += (v.empty() ? "" : "+") + a.name;
  out.verdict = v.empty() ? "none" : v;
  return out;
}

}  // namespace amb::host::residual
