#include "host-tools/core/fit/drop_fit.hpp"

#include <chrono>
#include <cmath>
#include <memory>
#include <stdexcept>

#include <Eigen/QR>

#include "model/drop/drop_model.hpp"

namespace amb::host::fit {

namespace md = model::drop;

std::string DropFitOptions::check() const {
  if (!(mu_min >= 0.0 && mu_max > mu_min)) return "friction bounds must satisfy 0 <= mu_min < mu_max";
  if (fit_restitution && !(restitution_min >= 0.0 && restitution_max <= 1.0 && restitution_max > restitution_min))
    return "restitution bounds must satisfy 0 <= min < max <= 1";
  if (!(offset_max_fraction > 0.0 && offset_max_fraction < 1.0)) return "offset_max_fraction must be in (0, 1)";
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
};

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
                          std::vector<double>& du_out) {
  const int m = model.modes_per_plane();
  std::vector<int> rigid;  // lateral DOF indices of the rigid-body modes (x then y)
  for (int axis = 0; axis < 2; ++axis)
    for (int i = 0; i < m; ++i)
      if (model.modal_omega2()(i) == 0.0) rigid.push_back(axis * m + i);
  const int nr = static_cast<int>(rigid.size());
  if (nr == 0 || n < 10) return false;
  md::DropScenario s = sc;
  s.pre_trigger_s = 0.0;
  s.window_s = static_cast<double>(n) / sc.sample_rate_hz;
  auto run = [&](const md::DropState& st, Eigen::VectorXd& y) {
    model.restore(st);
    const md::DropTrace tr = md::record_drop(model, s, false);
    if (tr.counters.contact_steps > 0 || tr.samples.size() < n) return false;
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
  if (!run(st, y)) return false;  // the corrected fall must stay contact-free too
  levitated = st;
  return true;
}

}  // namespace

DropFitResult fit_drop(const DropMeasurement& m, const board::BoardConfig& board, const DropFitOptions& o) {
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
  std::vector<double> meas_w;
  if (!m.speed_rad_s.empty())
    meas_w.assign(m.speed_rad_s.begin() + static_cast<long>(first), m.speed_rad_s.begin() + static_cast<long>(first + n));
  const DropFeatures meas = drop_features(rig, view, meas_s, meas_w, period, spin_sign, o.rubbing);

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
  for (int w = 0; w < workers; ++w) models.push_back(std::make_unique<md::DropModel>(rig, board.controller, board.rate_hz, mo));
  md::levitate(*models[0], sc);
  md::DropState levitated = models[0]->state();
  std::vector<double> rigid_dq, rigid_du;
  int free_fall_used = 0;
  if (o.estimate_initial_state && m.amplifiers_off) {
    const size_t nf = free_fall_samples(rig, view, meas_s, o.free_fall_radius_fraction);
    if (estimate_rigid_state(*models[0], levitated, sc, meas_s, nf, rigid_dq, rigid_du)) free_fall_used = static_cast<int>(nf);
    models[0]->restore(levitated);
    models[0]->clear_counters();
  }

  std::vector<double> lo{o.mu_min}, hi{o.mu_max};
  if (o.fit_restitution) {
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
    p.mu = x[i++];
    p.e = o.fit_restitution ? x[i++] : mo.restitution;
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
    model.restore(levitated);
    return md::record_drop(model, sc, keep_contacts);
  };
  auto features_of = [&](const md::DropTrace& tr, const model::PlantParams& rig_used) {
    std::vector<std::array<double, 4>> s;
    std::vector<double> w;
    for (const auto& smp : tr.samples) {
      s.push_back(smp.sensor_m);
      if (!meas_w.empty()) w.push_back(smp.spin_rad_s);
    }
    return drop_features(rig_used, view, s, w, period, spin_sign, o.rubbing);
  };
  const CostFunction cost = [&](const std::vector<double>& x, int worker) {
    const Params p = unpack(x);
    model::PlantParams rig_used;
    const md::DropTrace tr = simulate(*models[static_cast<size_t>(worker)], p, false, rig_used);
    // A fitted bearing centre moves the measured contact angles too.
    const DropFeatures meas_p = o.fit_centre_offset ? drop_features(rig_used, view, meas_s, meas_w, period, spin_sign, o.rubbing) : meas;
    return drop_cost(meas_p, features_of(tr, rig_used), rig.aux[0].clearance_m, spin0, o.weights).total;
  };
  ProgressFunction progress;
  if (o.progress)
    progress = [&](int it, double best, double h) {
      o.progress("fit: iteration " + std::to_string(it) + ", cost " + std::to_string(best) + ", stencil " + std::to_string(h));
    };
  const ImplicitFilteringSummary s = implicit_filtering(cost, lo, hi, o.optimiser, progress);

  DropFitResult r;
  const Params best = unpack(s.x);
  r.friction_coefficient = best.mu;
  r.restitution = best.e;
  r.centre_offset_m = {best.dx, best.dy};
  model::PlantParams rig_used;
  r.trace = simulate(*models[0], best, true, rig_used);
  const DropFeatures fitted = features_of(r.trace, rig_used);
  const DropFeatures meas_p = o.fit_centre_offset ? drop_features(rig_used, view, meas_s, meas_w, period, spin_sign, o.rubbing) : meas;
  r.rubbing = fitted.rubbing;
  r.measured_rubbing = meas_p.rubbing;
  r.cost = drop_cost(meas_p, fitted, rig.aux[0].clearance_m, spin0, o.weights);
  r.initial_rigid_dq = rigid_dq;
  r.initial_rigid_du = rigid_du;
  r.free_fall_samples = free_fall_used;
  r.evaluations = s.evaluations + 1;
  r.converged = s.converged;
  r.stop_reason = s.stop_reason;
  r.cost_history = s.cost_history;
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

}  // namespace amb::host::fit
