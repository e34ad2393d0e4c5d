#include "host-tools/core/fit/drop_fit.hpp"

#include <chrono>
#include <cmath>
#include <memory>
#include <stdexcept>

#include <Eigen/QR>
#include <algorithm>
#include <nlopt.hpp>
#include <thread>

#include "model/drop/drop_model.hpp"

namespace amb::host::fit {

namespace md = model::drop;

std::string DropFitOptions::check() const {
  if (!(mu_min >= 0.0 && mu_max > mu_min)) return "friction bounds must satisfy 0 <= mu_min < mu_max";
  if (fit_restitution && !(restitution_min >= 0.0 && restitution_max <= 1.0 && restitution_max > restitution_min))
    return "restitution bounds must satisfy 0 <= min < max <= 1";
  if (!(offset_max_fraction > 0.0 && offset_max_fraction < 1.0)) return "offset_max_fraction must be in (0, 1)";
  if (!(stiffness_factor_min > 0.0 && stiffness_factor_max > stiffness_factor_min)) return "stiffness factor bounds must satisfy 0 < min < max";
  if (!(damping_max_n_s_per_m > 0.0)) return "damping_max_n_s_per_m must be > 0";
  if (!(ring_drag_max_n_m > 0.0)) return "ring_drag_max_n_m must be > 0";
  if (polish_max_evaluations < 1) return "polish_max_evaluations must be >= 1";
  if (!(uncertainty_step > 0.0 && uncertainty_step < 0.5)) return "uncertainty_step must be in (0, 0.5)";
  if (!(max_window_s > 0.0)) return "max_window_s must be > 0";
  if (!(settle_s >= 0.0)) return "settle_s must be >= 0";
  if (!(free_fall_radius_fraction > 0.0 && free_fall_radius_fraction < 1.0)) return "free_fall_radius_fraction must be in (0, 1)";
  if (std::string e = model.check(); !e.empty()) return "model: " + e;
  if (std::string e = rubbing.check(); !e.empty()) return "rubbing: " + e;
  if (std::string e = optimiser.check(); !e.empty()) return "optimiser: " + e;
  return {};
}

namespace {

// Parameters of one evaluation, unpacked from the optimiser's vector.
struct Params {
  double mu = 0.0, e = 0.0, dx = 0.0, dy = 0.0;
  double stiffness = 0.0, damping = 0.0, drag = 0.0;  // compliant-law stiffness / damping, ring drag
  double eps = 0.0, exponent = 0.0;                    // slip regularisation, spring exponent
};

// Cost at x in the unit box (bounds lo/hi) for NLopt.
struct PolishData {
  const CostFunction* f;
  const std::vector<double>* lo;
  const std::vector<double>* hi;
  int evaluations = 0;
  double best = 1e300;
  std::vector<double> best_x;
};

double polish_cost(unsigned n, const double* z, double* grad, void* data) {
  (void)grad;  // derivative-free
  auto* d = static_cast<PolishData*>(data);
  std::vector<double> x(n);
  for (unsigned i = 0; i < n; ++i) x[i] = (*d->lo)[i] + std::clamp(z[i], 0.0, 1.0) * ((*d->hi)[i] - (*d->lo)[i]);
  const double c = (*d->f)(x, 0);
  ++d->evaluations;
  if (c < d->best) {
    d->best = c;
    d->best_x = x;
  }
  return c;
}

// Samples after the trigger during which the measured rotor is still in free fall: until the
// orbit radius at either aux bearing first reaches `fraction` x clearance (sensor view).
size_t free_fall_samples(const model::PlantParams& rig, const md::SensorOrbit& view,
                         const std::vector<std::array<double, 4>>& sensor_m, double fraction) {
  for (size_t i = 0; i < sensor_m.size(); ++i)
    for (int k = 0; k < 2; ++k) {
      const auto p = view.at_aux_plane(sensor_m[i], k);
      const auto& aux = rig.aux[static_cast<size_t>(k)];
      if (std::hypot(p[0] - aux.centre_offset_x_m, p[1] - aux.centre_offset_y_m) >= fraction * aux.clearance_m) return i;
    }
  return sensor_m.size();
}

// Rigid-body part of the state at the trigger from the measured free fall. Between the
// trigger (amplifiers off) and the first contact the model is linear in its initial state,
// so the sensor readings are base + S d exactly, d = (q, u) of the rigid-body modes; S comes
// from one simulation per unknown, d from linear least squares over all four sensors.
// Why: the model's levitated state is noise-free, the measured rotor's is not; the lateral
// velocity at the trigger (mm/s from sensor noise through the PID's derivative) changes the
// bounce sequence and with it the swing energy, the mean normal force and the spin-down by
// several per cent at low friction, which the fit otherwise absorbs into mu (it was biased
// low by 1-3 % on generated drops). The estimate reads only the measurement.
// Returns false (state unchanged) when the free fall is too short or the model touches.
bool estimate_rigid_state(md::DropModel& model, md::DropState& levitated, const md::DropScenario& sc,
                          const std::vector<std::array<double, 4>>& meas_s, size_t n, std::vector<double>& dq_out,
                          std::vector<double>& du_out, double* residual_rms_m = nullptr, size_t min_samples = 10,
                          bool contact_may_follow = false, size_t skip_samples = 0) {
  const int m = model.modes_per_plane();
  std::vector<int> rigid;  // lateral DOF indices of the rigid-body modes (x then y)
  for (int axis = 0; axis < 2; ++axis)
    for (int i = 0; i < m; ++i)
      if (model.modal_omega2()(i) == 0.0) rigid.push_back(axis * m + i);
  const int nr = static_cast<int>(rigid.size());
  if (nr == 0 || n < min_samples) return false;
  md::DropScenario s = sc;
  s.pre_trigger_s = 0.0;
  s.window_s = static_cast<double>(n) / sc.sample_rate_hz;
  auto run = [&](const md::DropState& st, Eigen::VectorXd& y, bool contact_ok = false) {
    model.restore(st);
    const md::DropTrace tr = md::record_drop(model, s, false);
    if ((tr.counters.contact_steps > 0 && !contact_ok) || tr.samples.size() < n) return false;
    y.resize(static_cast<Eigen::Index>(4 * n));
    for (size_t i = 0; i < n; ++i)
      for (size_t k = 0; k < 4; ++k) y(static_cast<Eigen::Index>(4 * i + k)) = tr.samples[i].sensor_m[k];
    return true;
  };
  Eigen::VectorXd base, y;
  if (!run(levitated, base)) return false;
  // Probe sizes: ~1 um and ~1 mm/s at the rotor (mass-normalised modes: x sqrt(mass)).
  const double scale = std::sqrt(model.rotor_mass_kg());
  const double probe_q = 1e-6 * scale, probe_u = 1e-3 * scale;
  Eigen::MatrixXd sens(static_cast<Eigen::Index>(4 * n), 2 * nr);
  for (int j = 0; j < 2 * nr; ++j) {
    md::DropState st = levitated;
    const int dof = rigid[static_cast<size_t>(j % nr)];
    const double probe = j < nr ? probe_q : probe_u;
    (j < nr ? st.q : st.u)(dof) += probe;
    if (!run(st, y)) return false;
    sens.col(j) = (y - base) / probe;
  }
  Eigen::VectorXd r(static_cast<Eigen::Index>(4 * n));
  for (size_t i = 0; i < n; ++i)
    for (size_t k = 0; k < 4; ++k) r(static_cast<Eigen::Index>(4 * i + k)) = meas_s[i][k];
  r -= base;
  // Rows of the first skip_samples samples carry no weight (the model's first step after the
  // cut still holds the levitated state's transient).
  for (size_t i = 0; i < std::min(skip_samples, n); ++i)
    for (size_t k = 0; k < 4; ++k) {
      r(static_cast<Eigen::Index>(4 * i + k)) = 0.0;
      sens.row(static_cast<Eigen::Index>(4 * i + k)).setZero();
    }
  const Eigen::VectorXd d = sens.colPivHouseholderQr().solve(r);
  md::DropState st = levitated;
  dq_out.assign(static_cast<size_t>(nr), 0.0);
  du_out.assign(static_cast<size_t>(nr), 0.0);
  for (int j = 0; j < nr; ++j) {
    const int dof = rigid[static_cast<size_t>(j)];
    st.q(dof) += d(j);
    st.u(dof) += d(nr + j);
    dq_out[static_cast<size_t>(j)] = d(j);
    du_out[static_cast<size_t>(j)] = d(nr + j);
  }
  if (!run(st, y, contact_may_follow)) return false;  // the corrected fall must stay contact-free too
  if (residual_rms_m != nullptr) {
    double ss = 0.0;
    for (size_t i = std::min(skip_samples, n); i < n; ++i)
      for (size_t k = 0; k < 4; ++k) {
        const double e = y(static_cast<Eigen::Index>(4 * i + k)) - meas_s[i][k];
        ss += e * e;
      }
    *residual_rms_m = std::sqrt(ss / static_cast<double>(4 * (n - std::min(skip_samples, n))));
  }
  levitated = st;
  return true;
}

}  // namespace

namespace {

// One fit with the rotor structure of o.model.modes_per_plane.
DropFitResult fit_drop_structure(const DropMeasurement& m, const board::BoardConfig& board, const DropFitOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  if (const std::string e = m.check(); !e.empty()) throw std::invalid_argument("measurement " + m.source + ": " + e);
  if (const std::string e = o.check(); !e.empty()) throw std::invalid_argument("fit options: " + e);
  const model::PlantParams& rig = board.plant;
  const md::SensorOrbit view(rig);
  const double period = 1.0 / m.sample_rate_hz;
  const double spin0 = 2.0 * M_PI * m.speed_at_trigger_hz;
  const double spin_sign = spin0 >= 0.0 ? 1.0 : -1.0;

  // The measured event window.
  const size_t first = static_cast<size_t>(m.trigger_index);
  const size_t n = std::min(m.sensor_m.size() - first, static_cast<size_t>(std::lround(o.max_window_s * m.sample_rate_hz)));
  if (n < 10) throw std::invalid_argument("measurement " + m.source + ": fewer than 10 samples after the trigger");
  const std::vector<std::array<double, 4>> meas_s(m.sensor_m.begin() + static_cast<long>(first),
                                                  m.sensor_m.begin() + static_cast<long>(first + n));

  // Friction from the measured contact forces (friction_estimate.hpp), when asked and found.
  FrictionEstimate fe;
  if (o.friction_from_contact_forces && m.amplifiers_off) {
    fe = estimate_friction(m, rig, *o.rig_model, o.friction_estimate);
    if (o.progress)
      o.progress(fe.valid ? "fit: friction from contact forces " + std::to_string(fe.friction) + " +- " + std::to_string(fe.uncertainty) +
                                " (" + std::to_string(fe.windows_used) + " of " + std::to_string(fe.windows_total) + " windows sliding; rotor read " +
                                (fe.bending_modes > 0 ? "with its first bending mode taken out" : "as rigid") +
                                (fe.rotor_choice.empty() ? "" : ", chosen by " + fe.rotor_choice) + ")"
                          : "fit: friction from contact forces: " + fe.note + "; friction fitted");
  }
  const bool fit_mu = !fe.valid;
  const double fixed_mu = fe.valid ? std::clamp(fe.friction, o.mu_min, o.mu_max) : 0.0;
  const bool fixed_mu_clamped = fe.valid && fixed_mu != fe.friction;

  md::DropScenario sc;
  sc.speed_hz = m.speed_at_trigger_hz;
  // Levitated for the settling time plus the recorded pre-trigger history: the pre-drop
  // transient of the model then has the age the measurement shows at its trigger.
  sc.settle_s = o.settle_s + static_cast<double>(m.trigger_index) * period;
  sc.pre_trigger_s = 0.0;
  sc.window_s = static_cast<double>(n) * period;
  sc.sample_rate_hz = m.sample_rate_hz;
  sc.amplifiers_off = m.amplifiers_off;
  sc.faults = m.known_faults;

  // One model per worker, each with the same levitated pre-drop state.
  md::DropOptions mo = o.model;
  mo.internal_controller = true;
  mo.sensor_noise = false;
  const int workers = o.optimiser.threads;
  std::vector<std::unique_ptr<md::DropModel>> models;
  for (int w = 0; w < workers; ++w) models.push_back(std::make_unique<md::DropModel>(o.rig_model, rig, board.controller, board.rate_hz, mo));
  md::levitate(*models[0], sc);
  md::DropState levitated = models[0]->state();
  std::vector<double> rigid_dq, rigid_du;
  int free_fall_used = 0;
  double free_fall_rms = 0.0;
  if (o.estimate_initial_state && m.amplifiers_off) {
    const size_t nf = free_fall_samples(rig, view, meas_s, o.free_fall_radius_fraction);
    if (nf >= o.min_free_fall_samples &&
        estimate_rigid_state(*models[0], levitated, sc, meas_s, nf, rigid_dq, rigid_du, &free_fall_rms))
      free_fall_used = static_cast<int>(nf);
    // State at the trigger from the samples before it: a rotor that reached its aux bearing
    // at (or right after) the trigger leaves no free fall after it to estimate from. In the
    // main job the board triggers 4.1 ms after the AMB cut, when the bias flux's negative
    // stiffness (control currents cut, amplifiers still on until the safe state) has pulled
    // bearing A's end to the clearance. Its motion up to the trigger is smooth (no contact):
    // a quadratic least-squares fit per sensor over the last pre_trigger_fit_samples samples
    // up to the trigger gives each sensor's reading and rate there, extrapolated over the next
    // 3 samples (0.3 ms at 10 kHz); the rigid-body state is the least-squares one whose model
    // readings match them (samples 1-3: 12 readings, 8 unknowns; the first model step still
    // carries the levitated state's transient; contact may follow at once).
    if (free_fall_used == 0 && o.state_from_pre_trigger && m.trigger_index + 1 >= o.pre_trigger_fit_samples &&
        o.pre_trigger_fit_samples >= 3) {
      const int k = o.pre_trigger_fit_samples;
      constexpr int k_targets = 4;  // model samples 0..3; sample 0 not weighted
      std::vector<std::array<double, 4>> target(k_targets);
      for (size_t c = 0; c < 4; ++c) {
        // Quadratic LS in t (samples, 0 = trigger) over t = -(k-1) .. 0.
        Eigen::MatrixXd a(k, 3);
        Eigen::VectorXd yv(k);
        for (int i = 0; i < k; ++i) {
          const double t = static_cast<double>(i - (k - 1));
          a(i, 0) = 1.0;
          a(i, 1) = t;
          a(i, 2) = t * t;
          yv(i) = m.sensor_m[static_cast<size_t>(m.trigger_index - (k - 1) + i)][c];
        }
        const Eigen::Vector3d coef = a.colPivHouseholderQr().solve(yv);
        for (int j = 0; j < k_targets; ++j) target[static_cast<size_t>(j)][c] = coef(0) + coef(1) * j + coef(2) * j * j;
      }
      if (estimate_rigid_state(*models[0], levitated, sc, target, k_targets, rigid_dq, rigid_du, &free_fall_rms, k_targets,
                               true, 1)) {
        free_fall_used = -k;  // < 0: samples before the trigger
        if (o.progress)
          o.progress("fit: no free fall after the trigger; rigid-body state at the trigger from the " + std::to_string(k) +
                     " samples before it");
      }
    }
    models[0]->restore(levitated);
    models[0]->clear_counters();
  }
  std::vector<double> meas_w;
  if (!m.speed_rad_s.empty())
    meas_w.assign(m.speed_rad_s.begin() + static_cast<long>(first), m.speed_rad_s.begin() + static_cast<long>(first + n));
  const double lim = o.weights.lock_in_margin_s, lmin = o.weights.lock_in_min_s;
  const DropFeatures meas = drop_features(rig, view, meas_s, meas_w, period, spin_sign, o.rubbing, lim, lmin);
  // A simulation without a sustained backward whirl of its own is compared over the record's.
  const double lock_in_start = meas.lock_in.valid ? meas.lock_in.start_s : -1.0;

  const bool compliant = models[0]->compliant();
  const bool fit_k = compliant && o.fit_contact_stiffness, fit_c = compliant && o.fit_contact_damping;
  const double k_board = rig.aux[0].contact_stiffness_n_per_m;
  std::vector<double> lo, hi;
  std::vector<std::string> names;
  if (fit_mu) {
    lo.push_back(o.mu_min);
    hi.push_back(o.mu_max);
    names.push_back("friction_coefficient");
  }
  if (fit_k) {
    lo.push_back(std::log10(o.stiffness_factor_min));
    hi.push_back(std::log10(o.stiffness_factor_max));
    names.push_back("log10_contact_stiffness_factor");
  }
  if (fit_c) {
    lo.push_back(0.0);
    hi.push_back(o.damping_max_n_s_per_m);
    names.push_back("contact_damping_n_s_per_m");
  }
  const bool fit_eps = compliant && o.fit_slip_regularisation, fit_exp = compliant && o.fit_contact_exponent;
  if (fit_eps) {
    lo.push_back(std::log10(o.slip_regularisation_min_m_s));
    hi.push_back(std::log10(o.slip_regularisation_max_m_s));
    names.push_back("log10_slip_regularisation_m_s");
  }
  if (fit_exp) {
    lo.push_back(o.contact_exponent_min);
    hi.push_back(o.contact_exponent_max);
    names.push_back("contact_exponent");
  }
  if (o.fit_ring_drag) {
    lo.push_back(0.0);
    hi.push_back(o.ring_drag_max_n_m);
    names.push_back("ring_drag_n_m");
  }
  if (o.fit_restitution && !compliant) names.push_back("restitution");
  if (o.fit_centre_offset) names.insert(names.end(), {"centre_offset_x_m", "centre_offset_y_m"});
  if (o.fit_restitution && !compliant) {
    lo.push_back(o.restitution_min);
    hi.push_back(o.restitution_max);
  }
  const double off = o.offset_max_fraction * rig.aux[0].clearance_m;
  if (o.fit_centre_offset) {
    lo.insert(lo.end(), {-off, -off});
    hi.insert(hi.end(), {off, off});
  }
  auto unpack = [&](const std::vector<double>& x) {
    Params p;
    size_t i = 0;
    p.mu = fit_mu ? x[i++] : fixed_mu;
    p.stiffness = fit_k ? k_board * std::pow(10.0, x[i++]) : k_board;
    p.damping = fit_c ? x[i++] : rig.aux[0].contact_damping_n_s_per_m;
    p.eps = fit_eps ? std::pow(10.0, x[i++]) : mo.slip_regularisation_m_s;
    p.exponent = fit_exp ? x[i++] : models[0]->contact_exponent();
    p.drag = o.fit_ring_drag ? x[i++] : rig.aux[0].ring_friction_torque_n_m;
    p.e = (o.fit_restitution && !compliant) ? x[i++] : mo.restitution;
    if (o.fit_centre_offset) {
      p.dx = x[i++];
      p.dy = x[i++];
    }
    return p;
  };
  // One simulation with the parameters; the rig's offsets shifted by the fitted one.
  auto simulate = [&](md::DropModel& model, const Params& p, bool keep_contacts, model::PlantParams& rig_used) {
    rig_used = rig;
    for (size_t b = 0; b < 2; ++b) {
      rig_used.aux[b].centre_offset_x_m += p.dx;
      rig_used.aux[b].centre_offset_y_m += p.dy;
      model.set_aux_centre_offset(static_cast<int>(b), rig_used.aux[b].centre_offset_x_m, rig_used.aux[b].centre_offset_y_m);
    }
    model.set_friction_coefficient(p.mu);
    model.set_restitution(p.e);
    model.set_ring_drag(p.drag);
    if (compliant) {
      model.set_contact_exponent(p.exponent);
      model.set_slip_regularisation(p.eps);
      model.set_contact_stiffness(p.stiffness);
      model.set_contact_damping(p.damping);
    }
    model.restore(levitated);
    return md::record_drop(model, sc, keep_contacts);
  };
  auto features_of = [&](const md::DropTrace& tr, const model::PlantParams& rig_used, double exponent) {
    std::vector<std::array<double, 4>> s;
    std::vector<double> w;
    for (const auto& smp : tr.samples) {
      s.push_back(smp.sensor_m);
      if (!meas_w.empty()) w.push_back(smp.spin_rad_s);
    }
    DropFeatures f = drop_features(rig_used, view, s, w, period, spin_sign, o.rubbing, lim, lmin, lock_in_start);
    f.contact_exponent = exponent;
    return f;
  };
  const CostFunction cost = [&](const std::vector<double>& x, int worker) {
    const Params p = unpack(x);
    model::PlantParams rig_used;
    const md::DropTrace tr = simulate(*models[static_cast<size_t>(worker)], p, false, rig_used);
    // A fitted bearing centre moves the measured contact angles too.
    const DropFeatures meas_p = o.fit_centre_offset ? drop_features(rig_used, view, meas_s, meas_w, period, spin_sign, o.rubbing, lim, lmin) : meas;
    return drop_cost(meas_p, features_of(tr, rig_used, compliant ? p.exponent : 1.0), rig.aux[0].clearance_m, spin0, o.weights).total;
  };
  ProgressFunction progress;
  if (o.progress)
    progress = [&](int it, double best, double h) {
      o.progress("fit: iteration " + std::to_string(it) + ", cost " + std::to_string(best) + ", stencil " + std::to_string(h));
    };
  ImplicitFilteringSummary s;
  if (!lo.empty()) {
    s = implicit_filtering(cost, lo, hi, o.optimiser, progress);
  } else {  // nothing left to fit: one simulation
    s.cost = cost({}, 0);
    s.evaluations = 1;
    s.converged = true;
    s.stop_reason = "no unknown left to fit";
  }

  // Bounded local polish (NLopt BOBYQA in the unit box) from the implicit-filtering optimum.
  std::vector<double> x_best = s.x;
  double j_best = s.cost;
  int polish_evals = 0;
  if (o.polish && !lo.empty()) {
    PolishData pd{&cost, &lo, &hi, 0, 1e300, {}};
    const unsigned nu = static_cast<unsigned>(lo.size());
    nlopt::opt opt(nu == 1 ? nlopt::LN_SBPLX : nlopt::LN_BOBYQA, nu);
    opt.set_lower_bounds(std::vector<double>(nu, 0.0));
    opt.set_upper_bounds(std::vector<double>(nu, 1.0));
    opt.set_min_objective(polish_cost, &pd);
    opt.set_maxeval(o.polish_max_evaluations);
    opt.set_xtol_abs(o.optimiser.min_stencil);
    opt.set_initial_step(std::vector<double>(nu, 4.0 * o.optimiser.min_stencil > 0.02 ? 4.0 * o.optimiser.min_stencil : 0.02));
    std::vector<double> z(nu);
    for (unsigned i = 0; i < nu; ++i) z[i] = (s.x[i] - lo[i]) / (hi[i] - lo[i]);
    double jz = 0.0;
    try {
      opt.optimize(z, jz);
    } catch (const std::exception&) {
      // NLopt's roundoff/forced stops keep the best point seen (pd.best_x).
    }
    polish_evals = pd.evaluations;
    if (pd.best < j_best) {
      j_best = pd.best;
      x_best = pd.best_x;
    }
  }

  DropFitResult r;
  r.polish_evaluations = polish_evals;
  // Uncertainty per unknown: central second difference of the cost at the optimum; the change
  // that raises the cost by the misfit left there (J0) is not resolved: sigma = sqrt(J0 / a),
  // a = J'' / 2. A flat or noisy direction (a <= 0) reports half the range.
  {
    const size_t nu = lo.size();
    std::vector<std::vector<double>> probes;
    for (size_t i = 0; i < nu; ++i)
      for (int sgn = -1; sgn <= 1; sgn += 2) {
        std::vector<double> x = x_best;
        const double step = o.uncertainty_step * (hi[i] - lo[i]);
        x[i] = std::clamp(x[i] + sgn * step, lo[i], hi[i]);
        probes.push_back(x);
      }
    std::vector<double> jp(probes.size());
    std::vector<std::thread> pool;
    for (int w = 0; w < workers; ++w)
      pool.emplace_back([&, w] {
        for (size_t k = static_cast<size_t>(w); k < probes.size(); k += static_cast<size_t>(workers)) jp[k] = cost(probes[k], w);
      });
    for (auto& t : pool) t.join();
    for (size_t i = 0; i < nu; ++i) {
      DropFitResult::Unknown u;
      u.name = names[i];
      u.lower = lo[i];
      u.upper = hi[i];
      u.value = x_best[i];
      const double d_minus = x_best[i] - probes[2 * i][i], d_plus = probes[2 * i + 1][i] - x_best[i];
      double a = 0.0;
      if (d_minus > 0.0 && d_plus > 0.0)
        a = ((jp[2 * i + 1] - j_best) / d_plus + (jp[2 * i] - j_best) / d_minus) / (d_plus + d_minus);
      u.uncertainty = a > 0.0 ? std::sqrt(std::max(j_best, 1e-12) / a) : 0.5 * (hi[i] - lo[i]);
      u.bound_active = x_best[i] - lo[i] <= 0.005 * (hi[i] - lo[i]) || hi[i] - x_best[i] <= 0.005 * (hi[i] - lo[i]);
      // A physically zero-bounded quantity (damping, drag) at 0 is a value, not a stuck fit
      // of the friction; only the friction's and the stiffness's bounds make the fit suspect.
      r.bound_active = r.bound_active || (u.bound_active && (u.name == "friction_coefficient" || u.name == "log10_contact_stiffness_factor"));
      r.unknowns.push_back(u);
    }
    r.evaluations += static_cast<int>(probes.size());
    if (fit_mu) r.friction_uncertainty = r.unknowns[0].uncertainty;
  }
  r.friction_estimate = fe;
  if (!fit_mu) {
    r.friction_method = "contact_forces";
    r.friction_uncertainty = fe.uncertainty;
    // An estimate outside the fit's friction bounds is clamped for the simulation: a bound.
    r.bound_active = r.bound_active || fixed_mu_clamped;
  }
  const Params best = unpack(x_best);
  r.friction_coefficient = best.mu;
  r.restitution = best.e;
  r.centre_offset_m = {best.dx, best.dy};
  model::PlantParams rig_used;
  r.trace = simulate(*models[0], best, true, rig_used);
  const DropFeatures fitted = features_of(r.trace, rig_used, compliant ? best.exponent : 1.0);
  const DropFeatures meas_p = o.fit_centre_offset ? drop_features(rig_used, view, meas_s, meas_w, period, spin_sign, o.rubbing, lim, lmin) : meas;
  r.rubbing = fitted.rubbing;
  r.measured_rubbing = meas_p.rubbing;
  r.cost = drop_cost(meas_p, fitted, rig.aux[0].clearance_m, spin0, o.weights);
  r.initial_rigid_dq = rigid_dq;
  r.initial_rigid_du = rigid_du;
  r.free_fall_samples = free_fall_used;
  r.free_fall_residual_rms_m = free_fall_rms;
  r.evaluations += s.evaluations + polish_evals + 1;
  r.converged = s.converged && !r.bound_active;
  r.contact_law = models[0]->contact_law() == model::AuxContactLaw::hertz    ? "hertz"
                  : models[0]->contact_law() == model::AuxContactLaw::linear ? "linear"
                                                                             : "rigid";
  r.contact_stiffness_n_per_m = best.stiffness;
  r.contact_damping_n_s_per_m = best.damping;
  r.ring_drag_n_m = best.drag;
  r.whirl = meas_p.whirl;
  r.fitted_whirl = fitted.whirl;
  r.spin_down_rad_s2 = meas_p.spin_down_rad_s2;
  r.fitted_spin_down_rad_s2 = fitted.spin_down_rad_s2;
  r.lock_in = meas_p.lock_in;
  r.fitted_lock_in = fitted.lock_in;
  r.stop_reason = s.stop_reason + (o.polish ? "; NLopt polish: " + std::to_string(polish_evals) + " evaluations" : "");
  for (const auto& u : r.unknowns)
    if (u.bound_active) r.stop_reason += "; bound active: " + u.name;
  if (fixed_mu_clamped) r.stop_reason += "; bound active: friction estimate " + std::to_string(fe.friction) + " outside the friction bounds";
  r.cost_history = s.cost_history;
  r.rotor_modes_per_plane = models[0]->modes_per_plane();
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

}  // namespace

DropFitResult fit_drop(const DropMeasurement& m, const board::BoardConfig& board, const DropFitOptions& o_in) {
  DropFitOptions o = o_in;
  if (!o.rig_model) o.rig_model = model::RigModel::make(board.plant);
  if (!o.choose_rotor_structure || o.model.modes_per_plane != 0) {
    DropFitResult r = fit_drop_structure(m, board, o);
    r.structure_trials.push_back({r.rotor_modes_per_plane, r.cost.total, r.converged, r.bound_active});
    return r;
  }
  // The rotor's flexibility is an uncertain part of the model: the board's modes and the
  // rigid-body modes alone, same unknowns, same cost on the same record; the lower cost wins.
  const auto t0 = std::chrono::steady_clock::now();
  DropFitResult best;
  std::vector<DropFitResult::StructureTrial> trials;
  int evaluations = 0;
  for (const int modes : {0, 2}) {
    DropFitOptions oc = o;
    oc.model.modes_per_plane = modes;
    if (o.progress)
      oc.progress = [&o, modes](const std::string& line) { o.progress((modes == 0 ? "[flexible rotor] " : "[rigid rotor] ") + line); };
    DropFitResult r = fit_drop_structure(m, board, oc);
    trials.push_back({r.rotor_modes_per_plane, r.cost.total, r.converged, r.bound_active});
    evaluations += r.evaluations;
    if (trials.size() == 1 || r.cost.total < best.cost.total) best = std::move(r);
  }
  best.structure_trials = trials;
  best.evaluations = evaluations;  // both fits
  best.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (o.progress)
    o.progress("fit: rotor structure " + std::to_string(best.rotor_modes_per_plane) + " modes per plane (cost " +
               std::to_string(trials[0].cost) + " with " + std::to_string(trials[0].modes_per_plane) + ", " +
               std::to_string(trials[1].cost) + " with " + std::to_string(trials[1].modes_per_plane) + ")");
  return best;
}

}  // namespace amb::host::fit
