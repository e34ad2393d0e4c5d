#include "host-tools/core/residual/frf_update.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <nlopt.hpp>
#include <stdexcept>

namespace amb::host::residual {
namespace {

using cd = std::complex<double>;
using model::analysis::HalfOpenFrf;
using model::analysis::HalfOpenParams;
constexpr double k_grid_m = 0.002;   // accelerometer position grid, m
constexpr double k_big = 1e30;

// Complex log without std::log(complex)'s slow special-case path (8x faster here).
cd fast_log(const cd& a) {
  const double n = std::norm(a);
  return n > 0.0 ? cd(0.5 * std::log(n), std::atan2(a.imag(), a.real())) : cd(-700.0, 0.0);
}

double to_unit(const UpdateParameter& p, double v) {
  return p.log_scale ? std::log(v / p.lower) / std::log(p.upper / p.lower) : (v - p.lower) / (p.upper - p.lower);
}
double from_unit(const UpdateParameter& p, double u) {
  u = std::clamp(u, 0.0, 1.0);
  return p.log_scale ? p.lower * std::pow(p.upper / p.lower, u) : p.lower + u * (p.upper - p.lower);
}

size_t index_of(const UpdateModel& m, const std::string& name) {
  for (size_t i = 0; i < m.p.size(); ++i)
    if (m.p[i].name == name) return i;
  throw std::logic_error("frf update: no parameter " + name);
}

double value_of(const UpdateModel& m, const std::vector<double>& v, const std::string& name) { return v[index_of(m, name)]; }

// Log of the model acceleration FRF on the position grid: ln(bin, grid) (a column per position).
struct GridLogs {
  std::vector<double> z;
  Eigen::MatrixXcd ln;   // bins x grid positions
  Eigen::MatrixXcd q;    // modal coordinates x bins
};

GridLogs grid_logs(const HalfOpenFrf& f, const FrfFitData& d, double sign) {
  GridLogs g;
  for (double z = 0.0; z <= f.length_m() + 1e-9; z += k_grid_m) g.z.push_back(z);
  const Eigen::Index nb = static_cast<Eigen::Index>(d.f_hz.size()), ng = static_cast<Eigen::Index>(g.z.size());
  Eigen::MatrixXd shapes(ng, 0);
  for (Eigen::Index k = 0; k < ng; ++k) {
    const Eigen::RowVectorXd row = f.shape_row(g.z[static_cast<size_t>(k)]);
    if (shapes.cols() == 0) shapes.resize(ng, row.size());
    shapes.row(k) = row;
  }
  g.q.resize(shapes.cols(), nb);
  for (Eigen::Index i = 0; i < nb; ++i) {
    const double w = 2.0 * M_PI * d.f_hz[static_cast<size_t>(i)];
    g.q.col(i) = -sign * w * w * f.modal_response(d.f_hz[static_cast<size_t>(i)]);
  }
  g.ln = (shapes.cast<cd>() * g.q).transpose();  // acceleration per A, bins x positions
  for (Eigen::Index k = 0; k < ng; ++k)
    for (Eigen::Index i = 0; i < nb; ++i) {
      g.ln(i, k) = fast_log(g.ln(i, k));
    }
  return g;
}

double wrap(double a) { return a - 2.0 * M_PI * std::nearbyint(a / (2.0 * M_PI)); }

double log_misfit(const cd& ln_meas, const cd& ln_model) {
  const double re = ln_meas.real() - ln_model.real();
  const double im = wrap(ln_meas.imag() - ln_model.imag());
  return re * re + im * im;
}

std::vector<std::vector<cd>> measured_logs(const FrfFitData& d) {
  std::vector<std::vector<cd>> l(d.h.size());
  for (size_t c = 0; c < d.h.size(); ++c)
    for (const cd& h : d.h[c]) l[c].push_back(std::abs(h) > 0.0 ? std::log(h) : cd(-700.0, 0.0));
  return l;
}

// The model at the accelerometer positions m.mass_axial_m (no position search).
FrfFit evaluate_at(const UpdateModel& m, const HalfOpenFrf& f, const std::vector<double>& v, const FrfFitData& d,
                   const std::vector<size_t>& channels) {
  FrfFit r;
  r.values = v;
  r.channels = channels;
  r.accel_axial_m = m.mass_axial_m;
  const size_t nch = d.h.size(), nb = d.f_hz.size();
  const auto lm = measured_logs(d);
  r.h_model.assign(nch, std::vector<cd>(nb));
  std::vector<Eigen::RowVectorXcd> rows;
  for (double z : m.mass_axial_m) rows.push_back(f.shape_row(z).cast<cd>());
  std::vector<bool> used_ch(nch, false);
  for (size_t c : channels) used_ch[c] = true;
  for (size_t i = 0; i < nb; ++i) {
    const double w = 2.0 * M_PI * d.f_hz[i];
    const Eigen::VectorXcd q = -m.sign * w * w * f.modal_response(d.f_hz[i]);
    for (size_t c = 0; c < nch; ++c) {
      r.h_model[c][i] = (rows[c] * q)(0);
      if (used_ch[c] && d.w[c][i] > 0.0 && std::abs(r.h_model[c][i]) > 0.0)
        r.cost += d.w[c][i] * log_misfit(lm[c][i], fast_log(r.h_model[c][i]));
    }
  }
  r.evaluations = 1;
  return r;
}

}  // namespace

bool at_bound(const UpdateParameter& p, double value) {
  const double u = to_unit(p, value);
  return p.free && (u < 0.01 || u > 0.99);
}

UpdateModel make_update_model(const board::BoardConfig& b, int excited, size_t channels) {
  UpdateModel m;
  auto& hp = m.base;
  hp.rotor = b.plant.rotor;
  if (b.plant.amb.size() < 2) throw std::invalid_argument("frf update: the board needs two AMBs");
  for (int j = 0; j < 2; ++j) {
    const auto& a = b.plant.amb[static_cast<size_t>(j)];
    auto& br = hp.bearing[static_cast<size_t>(j)];
    br.axial_m = a.axial_m;
    br.ks_n_per_m = a.ks_n_per_m;
    br.ki_n_per_a = a.ki_n_per_a;
  }
  hp.excited = excited;
  hp.controller = b.controller;
  double dmin = std::numeric_limits<double>::infinity();
  for (const auto& e : hp.rotor.elements) dmin = std::min(dmin, e.outer_diameter_m);
  for (size_t e = 0; e < hp.rotor.elements.size(); ++e)
    (hp.rotor.elements[e].outer_diameter_m > dmin * 1.01 ? m.zone_elements : m.shaft_elements).push_back(e);
  for (size_t k = 1; k < hp.rotor.disks.size(); ++k)
    if (hp.rotor.disks[k].mass_kg > hp.rotor.disks[m.centre_disk].mass_kg) m.centre_disk = k;
  const auto& a0 = b.plant.amb[static_cast<size_t>(excited)];
  // A digital controller's delay: sampling, computation and zero-order hold, about 1.5 periods.
  const double delay0 = b.rate_hz > 0.0 ? 1.5 / b.rate_hz : 1e-4;
  const double amp0 = a0.amplifier_bandwidth_hz > 0.0 ? 1.0 / (2.0 * M_PI * a0.amplifier_bandwidth_hz) : 1.6e-4;
  m.lag = true;
  // name, unit, meaning, nominal, lower, upper, log
  m.p = {
      {"shaft_bending_scale", "1", "EI of the plain shaft: E 200-215 GPa, diameter 7.74 (CAD area) to 8.0 mm", 1.0, 0.85, 1.05, false},
      {"zone_bending_scale", "1", "EI of the stiffened zones under the AMB rotors and the disc hub (a joint-stiffness device, RIG.md 2a): from the plain shaft (0.48) to a near-rigid sleeve joint", 1.0, 0.48, 20.0, true},
      {"disc_mass_scale", "1", "centre-disc lumped mass (CAD, incl. sleeves and screws) +-10 %", 1.0, 0.9, 1.1, false, false},
      {"disc_inertia_scale", "1", "centre-disc transverse and polar inertia +-30 %", 1.0, 0.7, 1.3, false},
      {"amb_rotor_mass_scale", "1", "AMB rotor + clamping sleeve lumped masses +-10 %", 1.0, 0.9, 1.1, false, false},
      {"amb_rotor_inertia_scale", "1", "AMB rotor inertias +-30 %", 1.0, 0.7, 1.3, false},
      {"ks_n_per_m", "N/m", "AMB negative stiffness (both bearings): 1.0e5 measured (Dietz, S7) to 1.92e5 computed (S1), +30 %", a0.ks_n_per_m, 0.8e5, 2.5e5, true},
      {"force_gain_n_per_a", "N/A", "AMB force per ampere of control current (ki): 50 measured (Dietz, S7), 59.9 computed (S1); 40-80", a0.ki_n_per_a, 40.0, 80.0, true},
      {"pid_gain_scale", "1", "PID gains of the closed bearing relative to set B (P = 5000 A/m): P 2500-9000 A/m", 1.0, 0.5, 1.8, true},
      {"pid_derivative_scale", "1", "derivative gain of the closed bearing relative to D = 5 A s/m (unrecorded for 2018)", 1.0, 0.3, 3.0, true},
      {"loop_delay_s", "s", "delay of the closed bearing's digital loop (sampling, computation, hold; rate unrecorded): 1 us - 0.5 ms", delay0, 1e-6, 5e-4, true},
      {"amplifier_lag_s", "s",
       "first-order lag of the current amplifier (command -> coil current) in the closed bearing's loop, from the board's amplifier "
       "bandwidth; held: in the acceleration FRFs only the loop's total phase lag counts (freed, it is correlated -0.995 with the "
       "loop delay); 10 us - 2 ms",
       amp0, 1e-5, 2e-3, true, false},
  };
  for (int k = 1; k <= 4; ++k)
    m.p.push_back({"damping_ratio_mode" + std::to_string(k), "1",
                   "modal damping ratio of free-free bending mode " + std::to_string(k) + " (measured 0.15-1.3 %, RIG.md 6)", 0.005, 3e-4, 0.05, true});
  for (auto& p : m.p) p.value = p.nominal;
  (void)channels;  // accelerometer masses are placed once their positions are known
  return m;
}

bool has_parameter(const UpdateModel& m, const std::string& name) {
  for (const auto& p : m.p)
    if (p.name == name) return true;
  return false;
}

void add_sensor_mass(UpdateModel& m, double mass_kg) {
  m.sensor_mass = true;
  m.p.push_back({"accel_mass_kg", "kg", "mass of each shaft accelerometer incl. mounting and cable end (type unrecorded): 0.5-25 g", mass_kg,
                 0.0005, 0.025, true, true, mass_kg});
}

void free_amplifier_lag(UpdateModel& m) {
  for (auto& p : m.p)
    if (p.name == "amplifier_lag_s") p.free = true;
}

void add_housing(UpdateModel& m, int bearing, double frequency_hz, double mass_kg, double damping_ratio) {
  m.housing = true;
  m.housing_bearing = bearing;
  m.p.push_back({"housing_mass_kg", "kg", "modal mass of the housing / foundation mode at the bearing", mass_kg, 0.3, 50.0, true, true, mass_kg});
  m.p.push_back({"housing_frequency_hz", "Hz", "housing / foundation mode frequency", frequency_hz, 30.0, 500.0, true, true, frequency_hz});
  m.p.push_back({"housing_damping_ratio", "1", "housing mode damping ratio", damping_ratio, 0.005, 0.3, true, true, damping_ratio});
}

void add_coupling(UpdateModel& m, double axial_m, double mass_kg) {
  m.coupling = true;
  m.coupling_axial_m = axial_m;
  m.p.push_back({"coupling_mass_kg", "kg",
                 "drive coupling on the shaft end (cardan-joint hub and the share of the joint it carries; RIG.md 2: the servomotor drives "
                 "the shaft through a cardan joint): 2-200 g",
                 mass_kg, 0.002, 0.2, true, true, mass_kg});
}

void add_eddy(UpdateModel& m, double time_s) {
  m.eddy = true;
  m.p.push_back({"eddy_time_s", "s",
                 "eddy-current time constant of the AMB iron (G = 1 / (1 + sqrt(s te))): 1 / (2 pi te) is where the skin-effect "
                 "reluctance of solid iron equals the air gap's; 1 us (nearly none) to 50 ms (flux halved below 5 Hz)",
                 time_s, 1e-6, 0.05, true, true, time_s});
}

void add_resonator(UpdateModel& m, double axial_m, double mass_kg, double frequency_hz, double damping_ratio) {
  m.resonator = true;
  double len = 0.0;
  for (const auto& e : m.base.rotor.elements) len += e.length_m;
  m.p.push_back({"resonator_axial_m", "m", "where the part is attached along the shaft", axial_m, 0.0, len, false, true, axial_m});
  m.p.push_back({"resonator_mass_kg", "kg", "effective mass of a part attached through a compliant joint (sensor, cable, sleeve, target ring): 0.1 g - 200 g",
                 mass_kg, 1e-4, 0.2, true, true, mass_kg});
  m.p.push_back({"resonator_frequency_hz", "Hz", "its natural frequency on that joint with the shaft held", frequency_hz, 50.0, 500.0, true, true,
                 frequency_hz});
  m.p.push_back({"resonator_damping_ratio", "1", "its damping ratio", damping_ratio, 0.002, 0.3, true, true, damping_ratio});
}

std::string element_of(const std::string& parameter) {
  if (parameter == "accel_mass_kg") return "sensor_mass";
  if (parameter == "amplifier_lag_s") return "";
  if (parameter.rfind("housing_", 0) == 0) return "pedestal_resonance";
  if (parameter.rfind("coupling_", 0) == 0) return "drive_coupling";
  if (parameter == "eddy_time_s") return "eddy_current_lag";
  if (parameter.rfind("resonator_", 0) == 0) return "attached_resonator";
  return "";
}

HalfOpenParams to_model(const UpdateModel& m, const std::vector<double>& v) {
  HalfOpenParams p = m.base;
  p.element_stiffness_scale.assign(p.rotor.elements.size(), 1.0);
  for (size_t e : m.shaft_elements) p.element_stiffness_scale[e] = value_of(m, v, "shaft_bending_scale");
  for (size_t e : m.zone_elements) p.element_stiffness_scale[e] = value_of(m, v, "zone_bending_scale");
  p.disk_mass_scale.assign(p.rotor.disks.size(), value_of(m, v, "amb_rotor_mass_scale"));
  p.disk_inertia_scale.assign(p.rotor.disks.size(), value_of(m, v, "amb_rotor_inertia_scale"));
  p.disk_mass_scale[m.centre_disk] = value_of(m, v, "disc_mass_scale");
  p.disk_inertia_scale[m.centre_disk] = value_of(m, v, "disc_inertia_scale");
  for (auto& br : p.bearing) {
    br.ks_n_per_m = value_of(m, v, "ks_n_per_m");
    br.actuator_lag_s = m.lag ? value_of(m, v, "amplifier_lag_s") : 0.0;
    br.eddy_time_s = m.eddy ? value_of(m, v, "eddy_time_s") : 0.0;
  }
  // Force per measured ampere: the AMB's force per control ampere over the current channel's scale.
  p.bearing[static_cast<size_t>(p.excited)].ki_n_per_a = value_of(m, v, "force_gain_n_per_a") / m.current_channel;
  const double g = value_of(m, v, "pid_gain_scale");
  p.controller.kp_n_per_m *= g;
  p.controller.ki_n_per_m_s *= g;
  p.controller.kd_n_s_per_m *= g * value_of(m, v, "pid_derivative_scale");
  p.loop_delay_s = value_of(m, v, "loop_delay_s");
  if (m.sensor_mass)
    for (double z : m.mass_axial_m) p.attached.push_back({z, value_of(m, v, "accel_mass_kg")});
  p.flexible_damping_ratio.clear();
  for (int k = 1; k <= 4; ++k) p.flexible_damping_ratio.push_back(value_of(m, v, "damping_ratio_mode" + std::to_string(k)));
  if (m.coupling) p.attached.push_back({m.coupling_axial_m, value_of(m, v, "coupling_mass_kg")});
  if (m.resonator)
    p.resonators.push_back({value_of(m, v, "resonator_axial_m"), value_of(m, v, "resonator_mass_kg"), value_of(m, v, "resonator_frequency_hz"),
                            value_of(m, v, "resonator_damping_ratio")});
  if (m.housing) {
    auto& h = p.bearing[static_cast<size_t>(m.housing_bearing)].housing;
    h.mass_kg = value_of(m, v, "housing_mass_kg");
    h.frequency_hz = value_of(m, v, "housing_frequency_hz");
    h.damping_ratio = value_of(m, v, "housing_damping_ratio");
  }
  return p;
}

FrfFit evaluate_fit(const UpdateModel& m, const std::vector<double>& v, const FrfFitData& d, const std::vector<size_t>& channels) {
  FrfFit r;
  r.values = v;
  r.channels = channels;
  const HalfOpenFrf f(to_model(m, v));
  if (m.fixed_positions && m.mass_axial_m.size() == d.h.size()) return evaluate_at(m, f, v, d, channels);
  const GridLogs g = grid_logs(f, d, m.sign);
  const auto lm = measured_logs(d);
  const size_t nch = d.h.size(), ng = g.z.size(), nb = d.f_hz.size();
  r.accel_axial_m.assign(nch, 0.0);
  r.h_model.assign(nch, std::vector<cd>(nb));
  std::vector<double> chan_cost(nch, 0.0);
  for (size_t c = 0; c < nch; ++c) {
    std::vector<size_t> used;
    for (size_t i = 0; i < nb; ++i)
      if (d.w[c][i] > 0.0) used.push_back(i);
    std::vector<double> s(ng, 0.0);
    for (size_t k = 0; k < ng; ++k) {
      const cd* col = g.ln.data() + static_cast<std::ptrdiff_t>(k * nb);
      double acc = 0.0;
      for (size_t i : used) acc += d.w[c][i] * log_misfit(lm[c][i], col[i]);
      s[k] = acc;
    }
    const size_t kb = static_cast<size_t>(std::min_element(s.begin(), s.end()) - s.begin());
    double z = g.z[kb];
    if (kb > 0 && kb + 1 < ng) {  // parabolic refinement between grid points
      const double den = s[kb - 1] - 2.0 * s[kb] + s[kb + 1];
      if (den > 0.0) z += std::clamp(0.5 * (s[kb - 1] - s[kb + 1]) / den, -0.5, 0.5) * k_grid_m;
    }
    r.accel_axial_m[c] = z;
    const Eigen::RowVectorXcd row = f.shape_row(z).cast<cd>();
    double cc = 0.0;
    for (size_t i = 0; i < nb; ++i) {
      r.h_model[c][i] = (row * g.q.col(static_cast<Eigen::Index>(i)))(0);
      if (d.w[c][i] > 0.0 && std::abs(r.h_model[c][i]) > 0.0) cc += d.w[c][i] * log_misfit(lm[c][i], fast_log(r.h_model[c][i]));
    }
    chan_cost[c] = std::min(cc, s[kb]);
  }
  for (size_t c : channels) r.cost += chan_cost[c];
  r.evaluations = 1;
  return r;
}

namespace {

std::vector<size_t> free_indices(const UpdateModel& m) {
  std::vector<size_t> idx;
  for (size_t i = 0; i < m.p.size(); ++i)
    if (m.p[i].free) idx.push_back(i);
  return idx;
}

struct NloptCtx {
  std::function<double(const std::vector<double>&)> f;
  int n = 0;
};

double nlopt_trampoline(unsigned, const double* x, double*, void* data) {
  auto* c = static_cast<NloptCtx*>(data);
  std::vector<double> u(x, x + c->n);
  try {
    const double v = c->f(u);
    return std::isfinite(v) ? v : k_big;
  } catch (const std::exception&) {
    return k_big;
  }
}

// Minimise f over the free parameters in unit coordinates; returns all values.
std::vector<double> minimise(const UpdateModel& m, const std::vector<double>& start,
                             const std::function<double(const std::vector<double>&)>& cost, int max_eval, int* evals) {
  const auto idx = free_indices(m);
  auto values_of = [&](const std::vector<double>& u) {
    std::vector<double> v = start;
    for (size_t k = 0; k < idx.size(); ++k) v[idx[k]] = from_unit(m.p[idx[k]], u[k]);
    return v;
  };
  std::vector<double> u0;
  for (size_t i : idx) u0.push_back(std::clamp(to_unit(m.p[i], start[i]), 0.0, 1.0));
  if (idx.empty()) return start;
  NloptCtx ctx;
  int count = 0;
  ctx.n = static_cast<int>(idx.size());
  ctx.f = [&](const std::vector<double>& u) { ++count; return cost(values_of(u)); };
  nlopt::opt opt(idx.size() > 1 ? nlopt::LN_BOBYQA : nlopt::LN_COBYLA, static_cast<unsigned>(idx.size()));
  opt.set_lower_bounds(std::vector<double>(idx.size(), 0.0));
  opt.set_upper_bounds(std::vector<double>(idx.size(), 1.0));
  opt.set_min_objective(nlopt_trampoline, &ctx);
  opt.set_maxeval(max_eval);
  opt.set_xtol_abs(1e-4);
  opt.set_ftol_rel(1e-7);
  opt.set_initial_step(std::vector<double>(idx.size(), 0.08));
  double fmin = 0.0;
  std::vector<double> u = u0;
  try {
    opt.optimize(u, fmin);
  } catch (const std::exception&) {
    // NLopt throws on roundoff-limited stops; u holds the best point found.
  }
  if (evals) *evals += count;
  return values_of(u);
}

}  // namespace

FrfFit fit_parameters(const UpdateModel& m, const std::vector<double>& start, const FrfFitData& d,
                      const std::vector<size_t>& channels, int max_evaluations) {
  int evals = 0;
  const auto v = minimise(m, start, [&](const std::vector<double>& x) { return evaluate_fit(m, x, d, channels).cost; },
                          max_evaluations, &evals);
  FrfFit r = evaluate_fit(m, v, d, channels);
  r.evaluations = evals + 1;
  return r;
}

std::vector<double> model_peaks(const HalfOpenFrf& f, const std::vector<double>& measured_hz, const std::vector<double>& axial_m,
                                const std::vector<double>& norms) {
  std::vector<Eigen::RowVectorXcd> rows;
  for (size_t c = 0; c < axial_m.size(); ++c)
    rows.push_back(f.shape_row(axial_m[c]).cast<cd>() / std::sqrt(c < norms.size() && norms[c] > 0.0 ? norms[c] : 1.0));
  std::vector<double> out;
  for (double fm : measured_hz) {
    const int n = 80;
    std::vector<double> fr(n + 1), s(n + 1);
    for (int k = 0; k <= n; ++k) {
      fr[static_cast<size_t>(k)] = fm * (0.96 + 0.08 * k / n);
      const Eigen::VectorXcd q = f.modal_response(fr[static_cast<size_t>(k)]);
      double a = 0.0;
      for (const auto& r : rows) a += std::norm((r * q)(0));
      s[static_cast<size_t>(k)] = std::log(a) + 4.0 * std::log(fr[static_cast<size_t>(k)]);
    }
    // The interior local maximum closest to the measured frequency.
    double best = std::numeric_limits<double>::quiet_NaN(), dist = k_big;
    for (int k = 1; k < n; ++k) {
      const size_t i = static_cast<size_t>(k);
      if (s[i] >= s[i - 1] && s[i] > s[i + 1]) {
        const double den = s[i - 1] - 2.0 * s[i] + s[i + 1];
        const double off = den < 0.0 ? std::clamp(0.5 * (s[i - 1] - s[i + 1]) / den, -0.5, 0.5) : 0.0;
        const double fp = fr[i] + off * (fr[1] - fr[0]);
        if (std::abs(fp - fm) < dist) { dist = std::abs(fp - fm); best = fp; }
      }
    }
    out.push_back(best);
  }
  return out;
}

std::vector<double> fit_frequencies(const UpdateModel& m, const std::vector<double>& start, const std::vector<double>& measured_hz,
                                    const std::vector<double>& axial_m, int max_evaluations, const std::vector<double>& norms) {
  auto cost = [&](const std::vector<double>& v) {
    const HalfOpenFrf f(to_model(m, v));
    const auto mp = model_peaks(f, measured_hz, axial_m, norms);
    double c = 0.0;
    for (size_t k = 0; k < mp.size(); ++k) {
      const double e = std::isfinite(mp[k]) ? std::log(mp[k] / measured_hz[k]) / 0.01 : 5.0;
      c += e * e;
    }
    return c;
  };
  return minimise(m, start, cost, max_evaluations, nullptr);
}

FrfErrors frf_errors(const FrfFitData& d, const std::vector<std::vector<cd>>& hm, const std::vector<size_t>& channels) {
  FrfErrors e;
  double sdb = 0.0, sln = 0.0, pr = 0.0;
  int n = 0, nc = 0;
  for (size_t c : channels) {
    std::vector<double> a, q;
    for (size_t i = 0; i < d.f_hz.size(); ++i) {
      if (!(d.w[c][i] > 0.0) || !(std::abs(hm[c][i]) > 0.0)) continue;
      const cd lr = std::log(d.h[c][i] / hm[c][i]);
      sdb += std::pow(20.0 / std::log(10.0) * lr.real(), 2);
      sln += lr.real() * lr.real() + std::pow(wrap(lr.imag()), 2);
      ++n;
      a.push_back(std::log(std::abs(d.h[c][i])));
      q.push_back(std::log(std::abs(hm[c][i])));
    }
    if (a.size() < 3) continue;
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
    ++nc;
  }
  e.bins = n;
  e.spectral_db = n > 0 ? std::sqrt(sdb / n) : 0.0;
  e.rms_ln = n > 0 ? std::sqrt(sln / n) : 0.0;
  e.pearson = nc > 0 ? pr / nc : 0.0;
  return e;
}

Identifiability identifiability(const UpdateModel& m, const FrfFit& fit, const FrfFitData& d) {
  Identifiability r;
  const auto idx = free_indices(m);
  const auto lm = measured_logs(d);
  auto residuals = [&](const std::vector<double>& v) {
    const HalfOpenFrf f(to_model(m, v));
    std::vector<double> out;
    for (size_t c : fit.channels) {
      const Eigen::RowVectorXcd row = f.shape_row(fit.accel_axial_m[c]).cast<cd>();
      for (size_t i = 0; i < d.f_hz.size(); ++i) {
        if (!(d.w[c][i] > 0.0)) continue;
        const double w = 2.0 * M_PI * d.f_hz[i];
        const cd h = -m.sign * w * w * (row * f.modal_response(d.f_hz[i]))(0);
        const cd lr = lm[c][i] - std::log(h);
        const double sw = std::sqrt(d.w[c][i]);
        out.push_back(sw * lr.real());
        out.push_back(sw * wrap(lr.imag()));
      }
    }
    return out;
  };
  const auto r0 = residuals(fit.values);
  Eigen::MatrixXd j(static_cast<Eigen::Index>(r0.size()), static_cast<Eigen::Index>(idx.size()));
  for (size_t k = 0; k < idx.size(); ++k) {
    const auto& p = m.p[idx[k]];
    const double u = to_unit(p, fit.values[idx[k]]);
    const double h = 1e-3;
    std::vector<double> vp = fit.values, vm = fit.values;
    vp[idx[k]] = from_unit(p, u + h);
    vm[idx[k]] = from_unit(p, u - h);
    const double du = to_unit(p, vp[idx[k]]) - to_unit(p, vm[idx[k]]);
    const auto rp = residuals(vp), rm = residuals(vm);
    for (size_t i = 0; i < r0.size(); ++i) j(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(k)) = (rp[i] - rm[i]) / du;
    r.names.push_back(p.name);
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(j, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd sv = svd.singularValues();
  for (Eigen::Index k = 0; k < sv.size(); ++k) {
    r.singular_values.push_back(sv(k));
    if (sv(k) > 1e-4 * sv(0)) ++r.rank;
  }
  r.condition = sv(sv.size() - 1) > 0.0 ? sv(0) / sv(sv.size() - 1) : std::numeric_limits<double>::infinity();
  r.null_share.assign(idx.size(), 0.0);
  for (Eigen::Index k = r.rank; k < sv.size(); ++k)
    for (size_t a = 0; a < idx.size(); ++a) r.null_share[a] += std::pow(svd.matrixV()(static_cast<Eigen::Index>(a), k), 2);
  // Covariance (normalised coordinates) = s^2 (J^T J)^+, s^2 = cost / (N - p).
  const double dof = std::max(1.0, static_cast<double>(r0.size()) - static_cast<double>(idx.size()));
  double ss = 0.0;
  for (double x : r0) ss += x * x;
  Eigen::VectorXd inv = Eigen::VectorXd::Zero(sv.size());
  for (Eigen::Index k = 0; k < sv.size(); ++k)
    if (sv(k) > 1e-10 * sv(0)) inv(k) = 1.0 / (sv(k) * sv(k));
  const Eigen::MatrixXd cov = (ss / dof) * svd.matrixV() * inv.asDiagonal() * svd.matrixV().transpose();
  const size_t n = idx.size();
  r.correlation.assign(n, std::vector<double>(n, 0.0));
  for (size_t a = 0; a < n; ++a) {
    r.std_normalised.push_back(std::sqrt(std::max(0.0, cov(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(a)))));
    for (size_t b = 0; b < n; ++b) {
      const double den = std::sqrt(cov(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(a)) *
                                   cov(static_cast<Eigen::Index>(b), static_cast<Eigen::Index>(b)));
      r.correlation[a][b] = den > 0.0 ? cov(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b)) / den : 0.0;
    }
  }
  for (size_t a = 0; a < n; ++a)
    for (size_t b = a + 1; b < n; ++b)
      if (std::abs(r.correlation[a][b]) > 0.9) {
        char buf[200];
        std::snprintf(buf, sizeof buf, "%s and %s correlated %.2f", r.names[a].c_str(), r.names[b].c_str(), r.correlation[a][b]);
        r.notes.push_back(buf);
      }
  return r;
}

}  // namespace amb::host::residual
