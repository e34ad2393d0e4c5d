#include "host-tools/core/sweep/sweep_residual.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>

#include <nlopt.hpp>

#include "host-tools/core/io/number_text.hpp"
#include "host-tools/core/residual/engine/elements.hpp"
#include "host-tools/core/residual/frf_update.hpp"

namespace amb::host::sweep {
namespace {

using cd = std::complex<double>;
namespace fx = model::effects;
using residual::UpdateParameter;

// One fitted parameter of an element, within the catalogue's physical bounds.
struct Param {
  UpdateParameter p;
  std::string element;
  std::function<void(fx::EffectSet&, double)> set;
};

double to_unit(const UpdateParameter& p, double v) {
  if (p.log_scale) return (std::log(v) - std::log(p.lower)) / (std::log(p.upper) - std::log(p.lower));
  return (v - p.lower) / (p.upper - p.lower);
}
double from_unit(const UpdateParameter& p, double u) {
  u = std::clamp(u, 0.0, 1.0);
  if (p.log_scale) return std::exp(std::log(p.lower) + u * (std::log(p.upper) - std::log(p.lower)));
  return p.lower + u * (p.upper - p.lower);
}

Param make(const std::string& element, const std::string& name, const std::string& unit, bool log_scale, double value,
           std::function<void(fx::EffectSet&, double)> set) {
  const auto* spec = residual::engine::find_element(element);
  Param q;
  q.element = element;
  q.p.name = name;
  q.p.unit = unit;
  q.p.log_scale = log_scale;
  q.p.value = value;
  q.p.nominal = value;
  for (const auto& ps : spec ? spec->parameters : std::vector<residual::engine::ParameterSpec>{})
    if (ps.name == name) {
      q.p.lower = ps.lower;
      q.p.upper = ps.upper;
      q.p.meaning = ps.meaning;
    }
  if (!(q.p.upper > q.p.lower)) throw std::logic_error("sweep residual: no catalogue bounds for " + element + "." + name);
  if (log_scale && !(q.p.lower > 0.0)) throw std::logic_error("sweep residual: log parameter with a lower bound <= 0: " + name);
  q.set = std::move(set);
  return q;
}

// The candidates' parameters (catalogue: engine/elements.cpp). `plane` for the pedestal.
std::vector<Param> candidate_params(const std::string& element, int plane, double f0, double mass) {
  std::vector<Param> v;
  if (element == "amplifier_lag") {
    v.push_back(make(element, "time_constant_s", "s", false, f0, [](fx::EffectSet& e, double x) {
      e.amplifier_lag = fx::AmplifierLag{x};
    }));
  } else if (element == "pedestal_resonance") {
    auto ped = [plane](fx::EffectSet& e) -> fx::PedestalResonance& {
      if (!e.pedestal) e.pedestal = fx::PedestalResonance{plane, 10.0, 40.0, 0.05};
      return *e.pedestal;
    };
    v.push_back(make(element, "mass_kg", "kg", true, mass, [ped](fx::EffectSet& e, double x) { ped(e).mass_kg = x; }));
    v.push_back(make(element, "frequency_hz", "Hz", true, f0, [ped](fx::EffectSet& e, double x) { ped(e).frequency_hz = x; }));
    v.push_back(make(element, "damping_ratio", "1", true, 0.05, [ped](fx::EffectSet& e, double x) { ped(e).damping_ratio = x; }));
  } else if (element == "sensor_gain") {
    const char* names[4] = {"gain_a1", "gain_a2", "gain_b1", "gain_b2"};
    for (int k = 0; k < 4; ++k)
      v.push_back(make(element, names[k], "1", true, 1.0, [k](fx::EffectSet& e, double x) {
        if (!e.sensor_gain) e.sensor_gain = fx::SensorGain{};
        e.sensor_gain->gain[static_cast<size_t>(k)] = x;
      }));
  }
  return v;
}

fx::EffectSet effects_of(const std::vector<Param>& ps, const std::vector<double>& values) {
  fx::EffectSet e;
  for (size_t i = 0; i < ps.size(); ++i) ps[i].set(e, values[i]);
  return e;
}

double wrap(double a) { return std::remainder(a, 2.0 * M_PI); }

class Evaluator {
 public:
  Evaluator(const SweepEstimate& e, const SweepLoopModel& m, const SweepResidualOptions& o) : m_(m) {
    data_.f_hz = m.f_hz();
    for (const auto& ax : e.axes) {
      std::vector<cd> hs, hg;
      std::vector<double> ws, wg;
      for (const auto& l : ax.lines) {
        const bool use = l.s.coherence >= o.min_coherence && std::abs(l.s.h) > 0.0 && std::abs(l.g.h) > 0.0;
        const double f2 = o.model_error_floor * o.model_error_floor;
        hs.push_back(l.s.h);
        hg.push_back(l.g.h);
        ws.push_back(use ? 1.0 / (std::pow(l.s.sigma / std::abs(l.s.h), 2) + f2) : 0.0);
        wg.push_back(use ? 1.0 / (std::pow(l.g.sigma / std::abs(l.g.h), 2) + f2) : 0.0);
        n_ += use ? 4 : 0;
      }
      data_.h.push_back(hs);
      data_.h.push_back(hg);
      data_.w.push_back(ws);
      data_.w.push_back(wg);
    }
  }
  // Misfit of model lines [axis][line].
  double misfit(const std::vector<std::vector<ModelResponse>>& lines) const {
    double c = 0.0;
    for (size_t a = 0; a < lines.size(); ++a)
      for (size_t l = 0; l < lines[a].size(); ++l) {
        for (int k = 0; k < 2; ++k) {
          const double w = data_.w[2 * a + static_cast<size_t>(k)][l];
          if (!(w > 0.0)) continue;
          const cd mod = k == 0 ? lines[a][l].s : lines[a][l].g;
          if (!(std::abs(mod) > 0.0) || !std::isfinite(mod.real()) || !std::isfinite(mod.imag())) return 1e30;
          const cd d = std::log(data_.h[2 * a + static_cast<size_t>(k)][l] / mod);
          c += w * (d.real() * d.real() + std::pow(wrap(d.imag()), 2));
        }
      }
    return c;
  }
  // Largest predicted change between two models over the compared lines (S and G), in
  // standard errors of the line (estimator scatter and the model's stated accuracy).
  double largest_change_sigma(const fx::EffectSet& a, const fx::EffectSet& b) const {
    const auto la = m_.with(a), lb = m_.with(b);
    double best = 0.0;
    for (size_t x = 0; x < la.size(); ++x)
      for (size_t l = 0; l < la[x].size(); ++l)
        for (int k = 0; k < 2; ++k) {
          const double w = data_.w[2 * x + static_cast<size_t>(k)][l];
          if (!(w > 0.0)) continue;
          const cd d = std::log((k == 0 ? la[x][l].s : la[x][l].g) / (k == 0 ? lb[x][l].s : lb[x][l].g));
          const double v = std::sqrt(w * (d.real() * d.real() + std::pow(wrap(d.imag()), 2)));
          if (std::isfinite(v)) best = std::max(best, v);
        }
    return best;
  }
  double cost(const fx::EffectSet& e) const {
    try {
      return misfit(m_.with(e));
    } catch (const std::exception&) {
      return 1e30;
    }
  }
  SweepFit figures(const fx::EffectSet& e, int parameters, double f_lo, double f_hi) const {
    SweepFit f;
    f.lines = m_.with(e);
    f.misfit = misfit(f.lines);
    f.parameters = parameters;
    f.data_points = n_;
    f.bic = 2.0 * f.misfit + parameters * std::log(std::max(1, n_));
    std::vector<std::vector<cd>> hm;
    for (const auto& ax : f.lines) {
      std::vector<cd> s, g;
      for (const auto& q : ax) {
        s.push_back(q.s);
        g.push_back(q.g);
      }
      hm.push_back(s);
      hm.push_back(g);
    }
    std::vector<size_t> sc, gc;
    for (size_t a = 0; a < f.lines.size(); ++a) {
      sc.push_back(2 * a);
      gc.push_back(2 * a + 1);
    }
    f.s_db_rms = residual::frf_errors(data_, hm, sc).spectral_db;
    f.g_db_rms = residual::frf_errors(data_, hm, gc).spectral_db;
    for (size_t a = 0; a < f.lines.size(); ++a) {
      const auto p = m_.peak(a, f_lo, f_hi, e);
      f.model_peak.push_back(p.peak);
      f.model_peak_hz.push_back(p.frequency_hz);
      f.model_zone.push_back(model::analysis::to_string(p.zone));
    }
    return f;
  }
  int points() const { return n_; }

 private:
  const SweepLoopModel& m_;
  residual::FrfFitData data_;
  int n_ = 0;
};

struct Ctx {
  std::function<double(const std::vector<double>&)> f;
};

double trampoline(unsigned k, const double* x, double*, void* d) {
  const double v = static_cast<Ctx*>(d)->f(std::vector<double>(x, x + k));
  return std::isfinite(v) ? v : 1e30;
}

// Bounded fit of all parameters (unit coordinates, BOBYQA; one parameter: COBYLA).
std::vector<double> refine(const Evaluator& ev, const std::vector<Param>& ps, std::vector<double> start, int max_eval) {
  const size_t n = ps.size();
  std::vector<double> u(n);
  for (size_t i = 0; i < n; ++i) u[i] = std::clamp(to_unit(ps[i].p, start[i]), 0.0, 1.0);
  auto values = [&](const std::vector<double>& x) {
    std::vector<double> v(n);
    for (size_t i = 0; i < n; ++i) v[i] = from_unit(ps[i].p, x[i]);
    return v;
  };
  Ctx ctx{[&](const std::vector<double>& x) { return ev.cost(effects_of(ps, values(x))); }};
  nlopt::opt opt(n > 1 ? nlopt::LN_BOBYQA : nlopt::LN_COBYLA, static_cast<unsigned>(n));
  opt.set_lower_bounds(std::vector<double>(n, 0.0));
  opt.set_upper_bounds(std::vector<double>(n, 1.0));
  opt.set_min_objective(trampoline, &ctx);
  opt.set_maxeval(max_eval);
  opt.set_xtol_abs(1e-5);
  opt.set_ftol_rel(1e-9);
  opt.set_initial_step(std::vector<double>(n, 0.05));
  double fmin = 0.0;
  try {
    opt.optimize(u, fmin);
  } catch (const std::exception&) {
    // roundoff-limited stop: u holds the best point
  }
  return values(u);
}

struct Track {
  std::vector<Param> ps;
  std::vector<double> v;
  double cost = 0.0;
};

// The candidate added to `cur` and everything refitted, from several starts.
Track fit_candidate(const Evaluator& ev, const Track& cur, const std::string& element, double f_lo, double f_hi, int max_eval) {
  std::vector<Track> starts;
  auto with = [&](std::vector<Param> extra) {
    Track t = cur;
    for (auto& p : extra) {
      t.v.push_back(p.p.value);
      t.ps.push_back(std::move(p));
    }
    t.cost = ev.cost(effects_of(t.ps, t.v));
    starts.push_back(std::move(t));
  };
  if (element == "amplifier_lag") {
    for (double tau : {5e-5, 2e-4, 6e-4}) with(candidate_params(element, 0, tau, 0.0));
  } else if (element == "pedestal_resonance") {
    for (int plane : {0, 1})
      for (int i = 0; i < 12; ++i)
        for (double mass : {2.0, 20.0})
          with(candidate_params(element, plane, f_lo * std::pow(f_hi / f_lo, i / 11.0), mass));
  } else {
    with(candidate_params(element, 0, 0.0, 0.0));
  }
  std::sort(starts.begin(), starts.end(), [](const Track& a, const Track& b) { return a.cost < b.cost; });
  Track best;
  best.cost = std::numeric_limits<double>::infinity();
  for (size_t k = 0; k < std::min<size_t>(4, starts.size()); ++k) {
    Track t = starts[k];
    t.v = refine(ev, t.ps, t.v, max_eval);
    t.cost = ev.cost(effects_of(t.ps, t.v));
    if (t.cost < best.cost) best = std::move(t);
  }
  return best;
}

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : "+") + x;
  return s.empty() ? "none" : s;
}

}  // namespace

SweepResidualOutcome run_sweep_residual(const SweepEstimate& e, const SweepLoopModel& m, const SweepResidualOptions& o) {
  const std::string bad = o.criterion.check();
  if (!bad.empty()) throw std::invalid_argument("sweep residual: " + bad);
  if (e.axes.size() != m.axes().size()) throw std::invalid_argument("sweep residual: the model is not built on the record's axes");
  for (const auto& ax : e.axes)
    if (ax.lines.size() != m.f_hz().size()) throw std::invalid_argument("sweep residual: the model is not built on the record's lines");
  SweepResidualOutcome out;
  const Evaluator ev(e, m, o);
  if (ev.points() == 0) throw std::invalid_argument("sweep residual: no line reaches the coherence floor");
  const double f_lo = m.f_hz().front(), f_hi = m.f_hz().back();
  Track cur;
  cur.cost = ev.cost({});
  double bic = 2.0 * cur.cost;
  const double ln_n = std::log(std::max(1, ev.points()));
  out.before = ev.figures({}, 0, f_lo, f_hi);
  // Model updating first (as the steady loop does, EffectSet::update): the board's actuator
  // force constant (ki and ks together) is uncertain on a real rig and, linearised at the
  // centre, differs from the loop's operating point carrying the rotor's weight. Fitted within
  // [0.8, 1.25] and kept when it earns its parameter (not an element: never named as one).
  {
    Param q;
    q.element = "";
    q.p.name = "force_scale";
    q.p.unit = "1";
    q.p.meaning = "actual / board actuator force constant (ki and ks together)";
    q.p.lower = 0.8;
    q.p.upper = 1.25;
    q.p.log_scale = true;
    q.p.nominal = q.p.value = 1.0;
    q.set = [](fx::EffectSet& s, double x) { s.update.force_scale = x; };
    Track t = cur;
    t.ps.push_back(q);
    t.v.push_back(1.0);
    t.v = refine(ev, t.ps, t.v, o.max_evaluations);
    t.cost = ev.cost(effects_of(t.ps, t.v));
    const double dbic = bic - (2.0 * t.cost + ln_n);
    const double u = to_unit(q.p, t.v[0]);
    out.update.done = true;
    out.update.force_scale = t.v[0];
    out.update.delta_bic = dbic;
    out.update.at_bound = u < 0.01 || u > 0.99;
    out.update.kept = dbic > o.criterion.min_delta_ic && !out.update.at_bound;
    if (out.update.kept) {
      cur = std::move(t);
      bic = 2.0 * cur.cost + ln_n;
    }
    out.notes.push_back(io::printf_text("model updating: force scale %.4f (BIC decrease %.1f)%s", out.update.force_scale, dbic,
                                        out.update.kept ? ": kept as the base model" : out.update.at_bound ? ": on its bound, not kept" : ": not kept"));
  }
  out.updated = ev.figures(effects_of(cur.ps, cur.v), static_cast<int>(cur.ps.size()), f_lo, f_hi);
  std::vector<std::string> remaining{"amplifier_lag", "pedestal_resonance", "sensor_gain"};
  std::vector<std::string> kept;
  for (int round = 1; round <= o.max_effects && !remaining.empty(); ++round) {
    struct Tried {
      std::string name;
      Track t;
      double dbic;
    };
    std::vector<Tried> tried;
    for (const auto& c : remaining) {
      Track t = fit_candidate(ev, cur, c, f_lo, f_hi, o.max_evaluations);
      const double b2 = 2.0 * t.cost + static_cast<double>(t.ps.size()) * ln_n;
      tried.push_back({c, std::move(t), bic - b2});
    }
    std::sort(tried.begin(), tried.end(), [](const Tried& a, const Tried& b) { return a.dbic > b.dbic; });
    bool added = false;
    for (auto& tr : tried) {
      if (added) {
        // Decided against the model before this round's element: not comparable any more.
        residual::CandidateScore cs;
        cs.name = tr.name;
        cs.delta_bic = tr.dbic;
        cs.evidence = io::printf_text("round %d: screening BIC decrease %.1f; not decided (another element kept this round)", round,
                                      tr.dbic);
        out.ranking.push_back(cs);
        continue;
      }
      residual::engine::CandidateEvidence ce;
      ce.element = tr.name;
      ce.delta_ic = tr.dbic;
      ce.ic_basis = "BIC of the sweep lines: complex Gaussian per line and function (S, G) with the period scatter's variance "
                    "plus the model's stated accuracy";
      ce.effect_sigma = ev.largest_change_sigma(effects_of(tr.t.ps, tr.t.v), effects_of(cur.ps, cur.v));
      std::string why, vals;
      for (size_t i = cur.ps.size(); i < tr.t.ps.size(); ++i) {
        const auto& p = tr.t.ps[i].p;
        const double u = to_unit(p, tr.t.v[i]);
        vals += (vals.empty() ? "" : ", ") + p.name + io::printf_text(" %.4g", tr.t.v[i]);
        if (u < 0.01 || u > 0.99) why += (why.empty() ? "" : "; ") + p.name + " on its bound";
      }
      ce.identified = why.empty();
      ce.not_identified = why;
      ce.evidence = io::printf_text("round %d: weighted misfit %.6g -> %.6g (", round, cur.cost, tr.t.cost) + vals + ")";
      // The misfit at its noise floor (its expectation, one per compared complex value, when the
      // model is right to within the stated variance) cannot fall materially: it counts only
      // above that (engine::Feature::counts_above).
      ce.decision.push_back({"weighted sweep misfit (S, G)", "1", cur.cost, tr.t.cost, false, 0.5 * ev.points()});
      const SweepFit f_after = ev.figures(effects_of(tr.t.ps, tr.t.v), static_cast<int>(tr.t.ps.size()), f_lo, f_hi);
      const SweepFit f_cur = ev.figures(effects_of(cur.ps, cur.v), static_cast<int>(cur.ps.size()), f_lo, f_hi);
      ce.information.push_back({"S error", "dB rms", f_cur.s_db_rms, f_after.s_db_rms});
      ce.information.push_back({"G error", "dB rms", f_cur.g_db_rms, f_after.g_db_rms});
      const auto dec = residual::engine::decide(ce, o.criterion);
      residual::CandidateScore cs = residual::scored(ce, dec);
      if (!dec.kept) {
        cs.evidence += ": not added (" + dec.reason + ")";
        out.ranking.push_back(cs);
        continue;
      }
      cs.evidence += ": added";
      out.ranking.push_back(cs);
      residual::EffectAdded ea;
      ea.name = tr.name;
      ea.delta_bic = tr.dbic;
      ea.evidence = cs.evidence;
      cur = tr.t;
      // Polish the kept model before the next round (restarts until the misfit stops falling
      // by 0.1 %), so that a later candidate is not credited with a refit the kept model
      // still had in it.
      for (int pass = 0; pass < 4; ++pass) {
        Track t = cur;
        t.v = refine(ev, t.ps, t.v, 2 * o.max_evaluations);
        t.cost = ev.cost(effects_of(t.ps, t.v));
        const bool better = t.cost < cur.cost * (1.0 - 1e-3);
        if (t.cost < cur.cost) cur = std::move(t);
        if (!better) break;
      }
      bic = 2.0 * cur.cost + static_cast<double>(cur.ps.size()) * ln_n;
      kept.push_back(tr.name);
      out.effects_added.push_back(ea);
      added = true;
    }
    if (!added) break;
    remaining.erase(std::remove(remaining.begin(), remaining.end(), kept.back()), remaining.end());
  }
  // Final values of every kept element's parameters (after the last joint refit).
  for (auto& ea : out.effects_added)
    for (size_t i = 0; i < cur.ps.size(); ++i)
      if (cur.ps[i].element == ea.name) ea.parameters.emplace_back(cur.ps[i].p.name, cur.v[i]);
  out.found = effects_of(cur.ps, cur.v);
  out.after = ev.figures(out.found, static_cast<int>(cur.ps.size()), f_lo, f_hi);
  for (size_t a = 0; a < e.axes.size(); ++a) {
    const double mp = e.axes[a].peak.peak;
    out.before.peak_ratio.push_back(mp / out.before.model_peak[a]);
    out.after.peak_ratio.push_back(mp / out.after.model_peak[a]);
  }
  out.verdict = join(kept);
  out.notes.push_back(io::printf_text("compared: %d real values (S and G at the lines with S coherence >= %.2f); model accuracy floor %.3g",
                                      ev.points(), o.min_coherence, o.model_error_floor));
  out.notes.push_back("not tried on a sweep: rotor_mode (bending modes above the swept band on these rigs), sensor_mass "
                      "(accelerometer-instrumented rigs); not testable: sensor_runout, aux_bearing_offset, "
                      "aux_support_compliance, magnetic_saturation (no rotation, rest or contact, small-signal)");
  return out;
}

}  // namespace amb::host::sweep
