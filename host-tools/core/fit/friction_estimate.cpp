#include "host-tools/core/fit/friction_estimate.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <memory>
#include <stdexcept>

#include <Eigen/Dense>

#include "model/drop/flexible_orbit.hpp"
#include "model/drop/sensor_orbit.hpp"
#include "model/plant/gaussian_rng.hpp"
#include "model/rotor/rotor_model.hpp"

namespace amb::host::fit {

std::string FrictionEstimateOptions::check() const {
  if (!(smoothing_half_window_s > 0.0)) return "smoothing_half_window_s must be > 0";
  if (!(skip_s >= 0.0)) return "skip_s must be >= 0";
  if (!(window_s > 0.0) || !(max_window_s > window_s)) return "need 0 < window_s < max_window_s";
  if (!(min_window_s >= 0.0 && min_window_s <= window_s)) return "need 0 <= min_window_s <= window_s";
  if (!(contact_radius_fraction > 0.0 && contact_radius_fraction < 1.0)) return "contact_radius_fraction must be in (0, 1)";
  if (!(min_impulse_fraction >= 0.0 && min_impulse_fraction < 1.0)) return "min_impulse_fraction must be in [0, 1)";
  if (!(sliding_fraction > 0.0 && sliding_fraction < 1.0)) return "sliding_fraction must be in (0, 1)";
  if (min_sliding_windows < 1) return "min_sliding_windows must be >= 1";
  if (bending_modes < 0) return "bending_modes must be >= 0";
  if (min_free_flight_samples < 1) return "min_free_flight_samples must be >= 1";
  if (!(clear_neighbour_fraction >= 0.0)) return "clear_neighbour_fraction must be >= 0";
  return {};
}

namespace {

// Contact forces per sample (rigid-body momentum balance), both bearings.
struct ContactSample {
  std::array<double, 2> radius_m{};  // aux-plane orbit radius from the bearing centre, m
  std::array<double, 2> normal_n{};  // towards the bearing centre on the rm, N
  std::array<double, 2> friction_n{};// opposing the collar's surface speed, N
};

// Quadratic least-squares derivatives over +-h samples: first and second derivative weights.
struct Derivative {
  std::vector<double> d1, d2;
  explicit Derivative(int h, double dt) {
    double s2 = 0.0, mt = 0.0;
    for (int t = -h; t <= h; ++t) { s2 += t * t; mt += t * t; }
    mt /= (2 * h + 1);
    double dd = 0.0;
    for (int t = -h; t <= h; ++t) dd += (t * t - mt) * (t * t - mt);
    for (int t = -h; t <= h; ++t) {
      d1.push_back(t / s2 / dt);
      d2.push_back(2.0 * (t * t - mt) / dd / (dt * dt));
    }
  }
};

// dOmega/dt per sample of [first, first + n) as the second derivative of the spin angle
// (trapezoid integral of the speed) through the very kernel that gives the contact forces from
// the orbit: an impact's speed drop is then spread over time exactly as its force (the
// first-derivative kernel of the speed spreads it with another shape, which a window edge
// cuts differently). Needs h samples of speed on either side.
std::vector<double> spin_rate_rad_s2(const DropMeasurement& m, size_t first, size_t n, int h) {
  const double dt = 1.0 / m.sample_rate_hz;
  const Derivative der(h, dt);
  const size_t lo = first - static_cast<size_t>(h);
  std::vector<double> angle(n + 2 * static_cast<size_t>(h), 0.0);
  for (size_t j = 1; j < angle.size(); ++j)
    angle[j] = angle[j - 1] + 0.5 * (m.speed_rad_s[lo + j - 1] + m.speed_rad_s[lo + j]) * dt;
  std::vector<double> rate(n, 0.0);
  for (size_t i = 0; i < n; ++i)
    for (int t = -h; t <= h; ++t) rate[i] += der.d2[static_cast<size_t>(t + h)] * angle[i + static_cast<size_t>(t + h)];
  return rate;
}

// Synchronous (1x) part of the resultant force and moment on the rotor that no contact exerts
// (the rotor's unbalance: m e Omega^2 rotating with the spin angle).
struct Synchronous {
  bool fitted = false;
  int samples = 0;                       // samples it was fitted on (free flight and contact)
  std::complex<double> force{}, moment{};  // per (rad/s)^2: F = Omega^2 force e^{i theta}, N s^2, N m s^2
};

// Rigid-body coordinates (x_G, y_G, slope_x, slope_y) from the rotor centre at the two sensor
// planes (x0, y0, x1, y1).
std::array<double, 4> rigid_coordinates(const std::array<double, 4>& pl, double zs0, double zs1, double zg) {
  const double sx = (pl[2] - pl[0]) / (zs1 - zs0), sy = (pl[3] - pl[1]) / (zs1 - zs0);
  return {pl[0] + (zg - zs0) * sx, pl[1] + (zg - zs0) * sy, sx, sy};
}

// Aux-plane forces (A x, y, B x, y) from resultant force f and moment mo about the centre of
// mass: F_A + F_B = F, la F_A + lb F_B = M.
std::array<double, 4> split_force(std::complex<double> f, std::complex<double> mo, double la, double lb) {
  const std::complex<double> fb = (mo - la * f) / (lb - la);
  return {f.real() - fb.real(), f.imag() - fb.imag(), fb.real(), fb.imag()};
}

// Rms of one bearing's aux-plane force (its x and y), averaged over +-a samples, over the
// (sample, bearing) pairs whose whole average lies in `free` (all of them when `free` is
// empty); counts them into `samples`.
double smoothed_rms(const std::vector<std::array<double, 4>>& f, const std::vector<std::array<bool, 2>>& free, size_t a,
                    int* samples) {
  double sum = 0.0;
  int k_used = 0;
  for (size_t b = 0; b < 2; ++b)
    for (size_t k = a; k + a < f.size(); ++k) {
      bool ok = true;
      for (size_t j = k - a; j <= k + a && !free.empty(); ++j) ok = ok && free[j][b];
      if (!ok) continue;
      std::array<double, 2> mean{};
      for (size_t j = k - a; j <= k + a; ++j)
        for (size_t c = 0; c < 2; ++c) mean[c] += f[j][2 * b + c] / static_cast<double>(2 * a + 1);
      ++k_used;
      sum += mean[0] * mean[0] + mean[1] * mean[1];
    }
  if (samples) *samples = k_used;
  return k_used > 0 ? std::sqrt(sum / k_used) : 0.0;
}

// What the momentum balance leaves in free flight (per bearing: not within the derivative
// fit's reach of contact), where the true contact force is zero: that bearing's force rms, N.
struct FreeFlight {
  int samples = 0;
  double force_rms_n = 0.0;
  double noise_rms_n = 0.0;  // the share of the board's probe noise (same description and filters)
  int bending_modes = 0;     // of the rotor description the forces were computed with
};

// Averaging half width of the free-flight force, samples (0.5 ms at 10 kHz: the probe noise
// through the derivative fit lies mostly above 1 kHz, a rotor's ringing after an impact below).
constexpr size_t kFreeFlightAverage = 2;

std::vector<ContactSample> contact_forces(const DropMeasurement& m, const model::PlantParams& rig, size_t first, size_t last,
                                          int h, const model::RigModel& rm, const FrictionEstimateOptions& o,
                                          const std::vector<double>& rate, Synchronous* sync_out, FreeFlight* free_out) {
  const model::drop::SensorOrbit view(rig);
  const double dt = 1.0 / m.sample_rate_hz;
  const double zs0 = rig.sensor[0].axial_m, zs1 = rig.sensor[2].axial_m;
  const double zg = rm.rotor().centre_of_mass_m;
  const double mass = rm.rotor().mass_kg, it = rm.rotor().transverse_inertia_kg_m2, ip = rm.rotor().polar_inertia_kg_m2;
  const double la = rig.aux[0].axial_m - zg, lb = rig.aux[1].axial_m - zg;
  const double g = rig.gravity_m_s2;
  // Rotor centre at the two sensor planes per sample from the trigger on, (x0, y0, x1, y1);
  // with bending modes, their rigid-body part (the bending the aux-plane loads cause taken out).
  const size_t start = std::min(static_cast<size_t>(m.trigger_index), first - static_cast<size_t>(h));
  std::vector<std::array<double, 4>> planes;
  planes.reserve(last + static_cast<size_t>(h) - start);
  for (size_t i = start; i < last + static_cast<size_t>(h); ++i) {
    const auto p0 = view.at_sensor_plane(m.sensor_m[i], 0), p1 = view.at_sensor_plane(m.sensor_m[i], 1);
    planes.push_back({p0[0], p0[1], p1[0], p1[1]});
  }
  std::unique_ptr<model::drop::FlexibleOrbit> flex;
  if (o.bending_modes > 0) {
    flex = std::make_unique<model::drop::FlexibleOrbit>(rm, std::array<double, 2>{zs0, zs1},
                                                        std::array<double, 2>{rig.aux[0].axial_m, rig.aux[1].axial_m},
                                                        o.bending_modes);
    if (flex->usable()) {
      planes = flex->rigid_part(planes, dt);
      if (free_out) free_out->bending_modes = o.bending_modes;
    } else {
      flex.reset();
    }
  }
  // Rigid-body coordinates per sample: x_G, y_G, slope_x, slope_y.
  std::vector<std::array<double, 4>> q(m.sensor_m.size());
  for (size_t i = first - static_cast<size_t>(h); i < last + static_cast<size_t>(h); ++i) {
    q[i] = rigid_coordinates(planes[i - start], zs0, zs1, zg);
  }
  const Derivative der(h, dt);
  const double omega0 = 2.0 * M_PI * m.speed_at_trigger_hz;
  const double spin_sign = omega0 >= 0.0 ? 1.0 : -1.0;
  const size_t n = last - first;
  // Resultant force (x, y) and moment about the centre of mass from the contacts, the spin
  // speed and angle, and the aux-plane orbit per sample.
  std::vector<std::complex<double>> force(n), moment(n);
  std::vector<double> omega(n), theta(n);
  std::vector<std::array<std::array<double, 2>, 2>> at_aux(n);
  std::vector<ContactSample> out(n);
  double angle = 0.0;
  for (size_t k = 0; k < n; ++k) {
    const size_t i = first + k;
    std::array<double, 4> v{}, a{};
    for (int t = -h; t <= h; ++t) {
      const auto& qq = q[i + static_cast<size_t>(t + h) - static_cast<size_t>(h)];
      for (size_t c = 0; c < 4; ++c) {
        v[c] += der.d1[static_cast<size_t>(t + h)] * qq[c];
        a[c] += der.d2[static_cast<size_t>(t + h)] * qq[c];
      }
    }
    omega[k] = m.speed_rad_s.empty() ? omega0 : m.speed_rad_s[i];
    if (k > 0) angle += 0.5 * (omega[k - 1] + omega[k]) * dt;
    theta[k] = angle;
    force[k] = {mass * a[0], mass * (a[1] + g)};
    moment[k] = {it * a[2] + omega[k] * ip * v[3], it * a[3] - omega[k] * ip * v[2]};
    for (size_t b = 0; b < 2; ++b) {
      const auto& ax = rig.aux[b];
      const double zb = ax.axial_m - zg;
      at_aux[k][b] = {q[i][0] + zb * q[i][2] - ax.centre_offset_x_m, q[i][1] + zb * q[i][3] - ax.centre_offset_y_m};
      out[k].radius_m[b] = std::hypot(at_aux[k][b][0], at_aux[k][b][1]);
    }
  }
  // Samples within the derivative fit's reach of a bearing near contact.
  std::vector<std::array<bool, 2>> near(n, {false, false});
  for (size_t k = 0; k < n; ++k)
    for (size_t b = 0; b < 2; ++b)
      if (out[k].radius_m[b] >= o.contact_radius_fraction * rig.aux[b].clearance_m)
        for (size_t j = k >= static_cast<size_t>(h) ? k - static_cast<size_t>(h) : 0; j <= std::min(n - 1, k + static_cast<size_t>(h)); ++j)
          near[j][b] = true;
  if (o.remove_synchronous && rate.size() == n && omega0 != 0.0) {
    // The rotor's unbalance accelerates its geometric centre, which the sensors see, by a
    // force U Omega^2 e^{i theta} and a moment V Omega^2 e^{i theta} that no contact exerts
    // (complex x + i y; theta the spin angle). Where it goes into the tangential forces, the
    // friction torque they imply, sum r T, disagrees with the one the speed channel measures,
    // -Ip dOmega/dt; where no bearing is near contact, the force itself is U Omega^2 e^{i theta}.
    // Least squares over both kinds of sample (force rows times the collar radius, N m) for
    // the four real unknowns (U, V).
    const double span = lb - la;
    const std::array<double, 2> alpha{lb / span, -la / span}, beta{-1.0 / span, 1.0 / span};
    const double r_mean = 0.5 * (rig.aux[0].collar_radius_m + rig.aux[1].collar_radius_m);
    Eigen::Matrix4d ata = Eigen::Matrix4d::Zero();
    Eigen::Vector4d atb = Eigen::Vector4d::Zero();
    Synchronous sy;
    const auto add = [&](const Eigen::Vector4d& row, double rhs) {
      ata += row * row.transpose();
      atb += row * rhs;
    };
    for (size_t k = 0; k < n; ++k) {
      const std::complex<double> e = omega[k] * omega[k] * std::polar(1.0, theta[k]);
      if (!near[k][0] && !near[k][1]) {
        // Free flight: F = U e, M = V e (x and y rows of each).
        add({r_mean * e.real(), -r_mean * e.imag(), 0.0, 0.0}, r_mean * force[k].real());
        add({r_mean * e.imag(), r_mean * e.real(), 0.0, 0.0}, r_mean * force[k].imag());
        add({0.0, 0.0, e.real(), -e.imag()}, moment[k].real());
        add({0.0, 0.0, e.imag(), e.real()}, moment[k].imag());
        ++sy.samples;
        continue;
      }
      // Contact: sum over the bearings near contact of r_b T_b (from the forces) against the
      // speed channel's friction torque.
      const std::complex<double> fb = (moment[k] - la * force[k]) / span;
      const std::array<std::complex<double>, 2> f{force[k] - fb, fb};
      double torque = 0.0;
      Eigen::Vector4d row = Eigen::Vector4d::Zero();
      for (size_t b = 0; b < 2; ++b) {
        if (!near[k][b] || !(out[k].radius_m[b] > 0.0)) continue;
        const std::complex<double> u(at_aux[k][b][0] / out[k].radius_m[b], at_aux[k][b][1] / out[k].radius_m[b]);
        const std::complex<double> w = -spin_sign * rig.aux[b].collar_radius_m * std::conj(std::complex<double>(0.0, 1.0) * u);
        torque += (w * f[b]).real();
        const std::complex<double> wa = w * e * alpha[b], wb = w * e * beta[b];
        row += Eigen::Vector4d(wa.real(), -wa.imag(), wb.real(), -wb.imag());
      }
      add(row, torque + spin_sign * ip * rate[k]);
      ++sy.samples;
    }
    const double rev_s = 2.0 * M_PI / std::abs(omega0);
    const Eigen::LDLT<Eigen::Matrix4d> ldlt(ata);
    if (static_cast<double>(n) * dt >= o.synchronous_min_revolutions * rev_s && ldlt.info() == Eigen::Success && ldlt.isPositive() &&
        ata.diagonal().minCoeff() > 0.0) {
      const Eigen::Vector4d x = ldlt.solve(atb);
      sy.force = {x(0), x(1)};
      sy.moment = {x(2), x(3)};
      sy.fitted = true;
      for (size_t k = 0; k < n; ++k) {
        const std::complex<double> e = omega[k] * omega[k] * std::polar(1.0, theta[k]);
        force[k] -= sy.force * e;
        moment[k] -= sy.moment * e;
      }
    }
    if (sync_out) *sync_out = sy;
  }
  std::vector<std::array<double, 4>> free_force(n);  // aux-plane forces (A x, y, B x, y), N
  for (size_t k = 0; k < n; ++k) {
    const std::array<double, 4> fs = split_force(force[k], moment[k], la, lb);
    const std::array<std::array<double, 2>, 2> f{{{fs[0], fs[1]}, {fs[2], fs[3]}}};
    free_force[k] = fs;
    for (size_t b = 0; b < 2; ++b) {
      const double r = out[k].radius_m[b];
      if (r <= 0.0) continue;
      const double ux = at_aux[k][b][0] / r, uy = at_aux[k][b][1] / r;
      out[k].normal_n[b] = -(f[b][0] * ux + f[b][1] * uy);
      // Counter-clockwise tangent (the +z spin's surface direction); friction opposes it.
      out[k].friction_n[b] = -spin_sign * (-uy * f[b][0] + ux * f[b][1]);
    }
  }
  if (free_out) {
    std::vector<std::array<bool, 2>> free(n);
    for (size_t k = 0; k < n; ++k) free[k] = {!near[k][0], !near[k][1]};
    free_out->force_rms_n = smoothed_rms(free_force, free, kFreeFlightAverage, &free_out->samples);
    // The board's probe noise through the same description, derivative fit and average
    // (white, per channel, fixed seed).
    model::GaussianRng rng(0x0f1e2d3cULL);
    std::vector<std::array<double, 4>> noise_planes(n + 2 * static_cast<size_t>(h));
    for (auto& pl : noise_planes) {
      std::array<double, 4> reading{};
      for (size_t c = 0; c < 4; ++c) reading[c] = rig.sensor[c].noise_rms_m * rng.normal();
      const auto p0 = view.at_sensor_plane(reading, 0), p1 = view.at_sensor_plane(reading, 1);
      pl = {p0[0], p0[1], p1[0], p1[1]};
    }
    if (flex) noise_planes = flex->rigid_part(noise_planes, dt, false);
    std::vector<std::array<double, 4>> noise_force(n);
    for (size_t k = 0; k < n; ++k) {
      std::array<double, 4> a{};
      for (int t = -h; t <= h; ++t) {
        const auto qq = rigid_coordinates(noise_planes[k + static_cast<size_t>(t + h)], zs0, zs1, zg);
        for (size_t c = 0; c < 4; ++c) a[c] += der.d2[static_cast<size_t>(t + h)] * qq[c];
      }
      noise_force[k] = split_force({mass * a[0], mass * a[1]}, {it * a[2], it * a[3]}, la, lb);
    }
    free_out->noise_rms_n = smoothed_rms(noise_force, {}, kFreeFlightAverage, nullptr);
  }
  return out;
}

struct Cluster {
  double mu = 0.0, se = 0.0;
  int used = 0;
  int clear = 0;  // sliding windows with no rolling neighbour (FrictionEstimateOptions::clear_neighbour_fraction)
};

// Window i lies next to a heavier rolling window: a neighbour in time (same bearing) whose
// ratio is below the sliding band [f mu, mu / f] and whose normal impulse is larger. At the
// lock-in into a rolling whirl the derivative fit smears that window's normal impulse, which
// carries no friction, across the edge: window i's ratio is biased low.
bool next_to_heavier_rolling(const std::vector<FrictionWindow>& w, size_t i, double mu, double f, double heavier = 1.0) {
  for (const auto& x : w)
    if (x.bearing == w[i].bearing && std::abs(std::abs(x.start_s - w[i].start_s) - w[i].length_s) < 0.25 * w[i].length_s &&
        x.ratio < f * mu && x.normal_impulse_n_s > heavier * w[i].normal_impulse_n_s)
      return true;
  return false;
}

// The sliding cluster of the window ratios: of the bands [f c, c / f] around each window's
// ratio c, the one holding the largest friction impulse (sliding windows carry the spin-down;
// a rolling whirl has large normal but tiny friction impulses, a stray window of a grazing
// touch small ones of both). A window at the lock-in into a rolling whirl (it slid, then
// rolled) has a ratio in between and often the largest friction impulse of all: with
// drop_next_to_rolling a band's windows next to a heavier rolling one do not count, as long
// as min_windows others remain in the band. Then the impulse-weighted ratio of the band,
// re-centred until it stays, those windows left out under the same condition.
Cluster upper_cluster(std::vector<FrictionWindow>& w, double sliding_fraction, bool drop_next_to_rolling, int min_windows,
                      double clear_fraction) {
  Cluster c;
  const auto in_band = [&](const FrictionWindow& x, double m) { return x.ratio >= sliding_fraction * m && x.ratio <= m / sliding_fraction; };
  double mu = 0.0, best = 0.0;
  for (const auto& cand : w) {
    if (!(cand.ratio > 0.0)) continue;
    double all = 0.0, interior = 0.0;
    int n_interior = 0;
    for (size_t i = 0; i < w.size(); ++i) {
      if (!in_band(w[i], cand.ratio)) continue;
      all += w[i].friction_impulse_n_s;
      if (drop_next_to_rolling && next_to_heavier_rolling(w, i, cand.ratio, sliding_fraction)) continue;
      interior += w[i].friction_impulse_n_s;
      ++n_interior;
    }
    const double st = drop_next_to_rolling && n_interior >= min_windows ? interior : all;
    if (st > best) {
      best = st;
      mu = cand.ratio;
    }
  }
  if (!(mu > 0.0)) return c;
  const auto recentre = [&](double start, bool drop_edges) {
    double m = start;
    for (int it = 0; it < 20; ++it) {
      double sn = 0.0, st = 0.0;
      for (size_t i = 0; i < w.size(); ++i) {
        w[i].next_to_rolling = drop_edges && in_band(w[i], m) && next_to_heavier_rolling(w, i, m, sliding_fraction);
        w[i].sliding = in_band(w[i], m) && !w[i].next_to_rolling;
        if (w[i].sliding) { sn += w[i].normal_impulse_n_s; st += w[i].friction_impulse_n_s; }
      }
      if (sn <= 0.0) break;
      const double next = st / sn;
      const bool same = std::abs(next - m) < 1e-12;
      m = next;
      if (same) break;
    }
    return m;
  };
  const double start = mu;
  mu = recentre(start, drop_next_to_rolling);
  const int used = static_cast<int>(std::count_if(w.begin(), w.end(), [](const FrictionWindow& x) { return x.sliding; }));
  if (drop_next_to_rolling && used < min_windows) mu = recentre(start, false);
  double sn = 0.0, sn2 = 0.0, var = 0.0;
  int k = 0;
  for (const auto& x : w)
    if (x.sliding) {
      sn += x.normal_impulse_n_s;
      sn2 += x.normal_impulse_n_s * x.normal_impulse_n_s;
      var += x.normal_impulse_n_s * (x.ratio - mu) * (x.ratio - mu);
      ++k;
    }
  c.mu = mu;
  c.used = k;
  for (size_t i = 0; i < w.size(); ++i)
    if (w[i].sliding && !(clear_fraction > 0.0 && next_to_heavier_rolling(w, i, mu, sliding_fraction, clear_fraction))) ++c.clear;
  // Weighted standard error: spread of the ratios / sqrt(effective number of windows).
  if (k >= 2 && sn > 0.0) {
    const double n_eff = sn * sn / sn2;
    c.se = std::sqrt(var / sn / std::max(1.0, n_eff - 1.0));
  }
  return c;
}

struct Pass {
  Cluster cluster;
  std::vector<FrictionWindow> windows;
  std::vector<ContactSample> samples;
  Synchronous synchronous;
  FreeFlight free_flight;
  /// dOmega/dt per sample through the derivative fit of the forces (matched_speed_filter and a
  /// speed channel), rad/s^2; empty otherwise.
  std::vector<double> speed_rate_rad_s2;
  size_t per_window = 0;

  /// Speed drop over samples [s, s + n) of the pass: matched or raw, rad/s.
  double speed_drop(const DropMeasurement& m, size_t first, size_t s, size_t n) const {
    if (speed_rate_rad_s2.empty()) return m.speed_rad_s[first + s] - m.speed_rad_s[first + s + n];
    double d = 0.0;
    for (size_t i = s; i < s + n; ++i) d -= speed_rate_rad_s2[i];
    return d / m.sample_rate_hz;
  }
};

// The per-sample part of a pass (contact forces, synchronous fit, speed rate) for half width h;
// it does not depend on the window length, so the window halving reuses it. The free-flight
// force and its noise level only when `free_flight` (they choose the rotor description; the
// half-width pass of the uncertainty does not need them).
Pass prepare_pass(const DropMeasurement& m, const model::PlantParams& rig, const FrictionEstimateOptions& o, size_t first,
                  size_t last, int h, const model::RigModel& rm, bool free_flight) {
  Pass p;
  const std::vector<double> rate = m.speed_rad_s.empty() ? std::vector<double>{} : spin_rate_rad_s2(m, first, last - first, h);
  p.samples = contact_forces(m, rig, first, last, h, rm, o, rate, &p.synchronous, free_flight ? &p.free_flight : nullptr);
  if (o.matched_speed_filter) p.speed_rate_rad_s2 = rate;
  return p;
}

// Windows of o.window_s over a prepared pass, and their sliding cluster.
Pass run_pass(Pass p, const DropMeasurement& m, const model::PlantParams& rig, const FrictionEstimateOptions& o, size_t first,
              const model::RigModel& rm) {
  p.windows.clear();
  const double dt = 1.0 / m.sample_rate_hz;
  p.per_window = std::max<size_t>(1, static_cast<size_t>(std::lround(o.window_s * m.sample_rate_hz)));
  std::vector<FrictionWindow> all;
  const bool spin = o.friction_from_speed && !m.speed_rad_s.empty();
  const double spin_sign = m.speed_at_trigger_hz >= 0.0 ? 1.0 : -1.0;
  // One window of n samples from sample s at bearing b (-1: both).
  const auto make = [&](size_t s, size_t n, int b) {
    FrictionWindow w;
    w.bearing = b;
    w.start_s = static_cast<double>(first + s - static_cast<size_t>(m.trigger_index)) * dt;
    w.length_s = static_cast<double>(n) * dt;
    for (int k = 0; k < 2; ++k) {
      if (b >= 0 && k != b) continue;
      const size_t kk = static_cast<size_t>(k);
      const double c = rig.aux[kk].clearance_m;
      for (size_t i = s; i < s + n; ++i) {
        const auto& cs = p.samples[i];
        if (cs.radius_m[kk] < o.contact_radius_fraction * c) continue;
        w.normal_impulse_n_s += cs.normal_n[kk] * dt;
        w.friction_impulse_n_s += cs.friction_n[kk] * dt;
      }
    }
    if (spin && b < 0) {
      // The friction impulse from the speed channel: Ip (Omega_start - Omega_end) / r, the
      // speed drop taken through the same derivative fit as the forces (matched_speed_filter).
      const double r_collar = 0.5 * (rig.aux[0].collar_radius_m + rig.aux[1].collar_radius_m);
      w.force_friction_impulse_n_s = w.friction_impulse_n_s;
      w.friction_impulse_n_s = spin_sign * p.speed_drop(m, first, s, n) * rm.rotor().polar_inertia_kg_m2 / r_collar;
    }
    if (w.normal_impulse_n_s > 0.0) w.ratio = w.friction_impulse_n_s / w.normal_impulse_n_s;
    return w;
  };
  for (size_t s = 0; s + p.per_window <= p.samples.size(); s += p.per_window)
    for (int b = 0; b < (o.per_bearing ? 2 : 1); ++b) all.push_back(make(s, p.per_window, o.per_bearing ? b : -1));
  double biggest = 0.0;
  for (const auto& w : all) biggest = std::max(biggest, w.normal_impulse_n_s);
  for (const auto& w : all)
    if (w.normal_impulse_n_s > o.min_impulse_fraction * biggest && w.normal_impulse_n_s > 0.0) p.windows.push_back(w);
  p.cluster = upper_cluster(p.windows, o.sliding_fraction, o.drop_next_to_rolling, o.min_sliding_windows, o.clear_neighbour_fraction);
  return p;
}

// The estimate from the per-sample part `base` of a description (bending_modes: 0 rigid):
// ratio windows (halved while too few slide or too few are clear of a rolling neighbour),
// the uncertainty (window scatter and the change at half the derivative fit's width) and the
// spin-down check.
FrictionEstimate finish_estimate(const Pass& base, const DropMeasurement& m, const model::PlantParams& rig,
                                 const FrictionEstimateOptions& o, int bending_modes, size_t first, size_t last, int h2,
                                 const model::RigModel& rm) {
  const double dt = 1.0 / m.sample_rate_hz;
  FrictionEstimate r;
  FrictionEstimateOptions ow = o;
  ow.bending_modes = bending_modes;
  r.bending_modes = bending_modes;
  Pass p = run_pass(base, m, rig, ow, first, rm);
  const auto too_few = [&](const Pass& q) { return q.cluster.used < o.min_sliding_windows || !(q.cluster.mu > 0.0); };
  const auto not_clear = [&](const Pass& q) { return o.clear_neighbour_fraction > 0.0 && q.cluster.clear < o.min_sliding_windows; };
  while ((too_few(p) || not_clear(p)) && 0.5 * ow.window_s >= o.min_window_s && o.min_window_s > 0.0) {
    FrictionEstimateOptions oh = ow;
    oh.window_s *= 0.5;
    Pass q = run_pass(base, m, rig, oh, first, rm);
    if (!too_few(p) && too_few(q)) break;  // halved only for clear windows, and the halved ones give too few
    ow = oh;
    p = std::move(q);
  }
  r.window_s = ow.window_s;
  r.synchronous_removed = p.synchronous.fitted;
  r.synchronous_fit_samples = p.synchronous.samples;
  if (p.synchronous.fitted) {
    const double w0 = 2.0 * M_PI * m.speed_at_trigger_hz;
    r.synchronous_force_n = std::abs(p.synchronous.force) * w0 * w0;
    r.synchronous_moment_n_m = std::abs(p.synchronous.moment) * w0 * w0;
  }
  r.windows = p.windows;
  r.windows_total = static_cast<int>(p.windows.size());
  r.windows_used = p.cluster.used;
  if (too_few(p)) {
    r.note = "sliding contact found in " + std::to_string(p.cluster.used) + " windows of " +
             std::to_string(ow.window_s * 1e3) + " ms, fewer than " + std::to_string(o.min_sliding_windows) +
             " (the ring spun up or the rotor locked into a rolling whirl at once)";
    r.friction = p.cluster.mu;
    return r;
  }
  if (ow.window_s < o.window_s)
    r.note = "too few sliding windows of " + std::to_string(o.window_s * 1e3) + " ms; " +
             std::to_string(ow.window_s * 1e3) + " ms windows used";
  r.valid = true;
  r.friction = p.cluster.mu;
  r.standard_error = p.cluster.se;
  const Pass p2 = run_pass(prepare_pass(m, rig, ow, first, last, h2, rm, false), m, rig, ow, first, rm);
  r.smoothing_change = p2.cluster.used > 0 ? p2.cluster.mu - p.cluster.mu : 0.0;
  r.uncertainty = std::sqrt(r.standard_error * r.standard_error + r.smoothing_change * r.smoothing_change);

  // Spin-down over the time windows in which a bearing slid: speed channel vs the torque of
  // the estimated friction forces (both bearings, all contact samples of those windows).
  const double sign = m.speed_at_trigger_hz >= 0.0 ? 1.0 : -1.0;
  double drop = 0.0, torque_impulse = 0.0, time = 0.0;
  std::vector<double> diff;  // per window: force torque impulse - Ip x speed drop, N m s
  std::vector<bool> seen(p.samples.size(), false);  // per_bearing: a time span once
  for (const auto& w : r.windows) {
    if (!w.sliding) continue;
    const size_t s = static_cast<size_t>(std::lround(w.start_s / dt)) + static_cast<size_t>(m.trigger_index) - first;
    const size_t n = static_cast<size_t>(std::lround(w.length_s / dt));
    if (seen[s]) continue;
    seen[s] = true;
    time += static_cast<double>(n) * dt;
    const double d = m.speed_rad_s.empty() ? 0.0 : sign * p.speed_drop(m, first, s, n);
    double tau = 0.0;
    for (size_t i = s; i < s + n; ++i)
      for (size_t b = 0; b < 2; ++b)
        if (p.samples[i].radius_m[b] >= o.contact_radius_fraction * rig.aux[b].clearance_m)
          tau += rig.aux[b].collar_radius_m * p.samples[i].friction_n[b] * dt;
    drop += d;
    torque_impulse += tau;
    diff.push_back(tau - rm.rotor().polar_inertia_kg_m2 * d);
  }
  r.sliding_time_s = time;
  if (!m.speed_rad_s.empty() && time > 0.0) {
    r.measured_spin_down_rad_s2 = drop / time;
    r.force_spin_down_rad_s2 = torque_impulse / rm.rotor().polar_inertia_kg_m2 / time;
    if (diff.size() >= 2) {
      double mean = 0.0, var = 0.0;
      for (const double d : diff) mean += d;
      mean /= static_cast<double>(diff.size());
      for (const double d : diff) var += (d - mean) * (d - mean);
      var /= static_cast<double>(diff.size() - 1);
      r.force_spin_down_scatter_rad_s2 = std::sqrt(var * static_cast<double>(diff.size())) / rm.rotor().polar_inertia_kg_m2 / time;
    }
  }
  return r;
}

}  // namespace

FrictionEstimate estimate_friction(const DropMeasurement& m, const model::PlantParams& rig, const FrictionEstimateOptions& o) {
  return estimate_friction(m, rig, model::RigModel(rig), o);
}

FrictionEstimate estimate_friction(const DropMeasurement& m, const model::PlantParams& rig, const model::RigModel& rm,
                                   const FrictionEstimateOptions& o) {
  rm.check_same_rig(rig, "friction estimate");
  if (const std::string e = o.check(); !e.empty()) throw std::invalid_argument("friction estimate: " + e);
  if (const std::string e = m.check(); !e.empty()) throw std::invalid_argument("friction estimate: " + e);
  if (rig.sensor.size() < 4 || rig.aux.size() < 2)
    throw std::invalid_argument("friction estimate: the rig needs two sensor pairs and two aux bearings");
  const int h = std::max(2, static_cast<int>(std::lround(o.smoothing_half_window_s * m.sample_rate_hz)));
  const int h2 = std::max(2, h / 2);
  const size_t first = static_cast<size_t>(m.trigger_index) + std::max(static_cast<size_t>(h), static_cast<size_t>(std::lround(o.skip_s * m.sample_rate_hz)));
  const size_t last = std::min(m.sensor_m.size() - static_cast<size_t>(h) - 1,
                               static_cast<size_t>(m.trigger_index) + static_cast<size_t>(std::lround(o.max_window_s * m.sample_rate_hz)));
  if (last <= first + static_cast<size_t>(std::lround(o.window_s * m.sample_rate_hz)))
    throw std::invalid_argument("friction estimate: " + m.source + ": record too short after the trigger");

  FrictionEstimateOptions o_rigid = o;
  o_rigid.bending_modes = 0;
  const Pass rigid_base = prepare_pass(m, rig, o_rigid, first, last, h, rm, true);
  FrictionEstimate rigid = finish_estimate(rigid_base, m, rig, o, 0, first, last, h2, rm);
  rigid.free_flight_samples = rigid_base.free_flight.samples;
  rigid.free_flight_force_rms_n = {rigid_base.free_flight.force_rms_n, 0.0};
  rigid.free_flight_noise_rms_n = {rigid_base.free_flight.noise_rms_n, 0.0};
  if (o.bending_modes == 0) return rigid;
  const Pass bent_base = prepare_pass(m, rig, o, first, last, h, rm, true);
  if (bent_base.free_flight.bending_modes == 0) return rigid;  // the inverse is not stable for this rig
  FrictionEstimate bent = finish_estimate(bent_base, m, rig, o, o.bending_modes, first, last, h2, rm);
  for (auto* e : {&rigid, &bent}) {
    e->free_flight_samples = rigid_base.free_flight.samples;
    e->free_flight_force_rms_n = {rigid_base.free_flight.force_rms_n, bent_base.free_flight.force_rms_n};
    e->free_flight_noise_rms_n = {rigid_base.free_flight.noise_rms_n, bent_base.free_flight.noise_rms_n};
  }
  // Rigid or bent. Evidence first: where no bearing is near contact the true force is zero,
  // and a description that misreads the rotor leaves a ringing force there beyond the probe
  // noise (the board's noise put through the same description and filters). Without such
  // evidence (too few free samples, or neither leaves a force beyond its noise), the
  // description whose windows agree better (the smaller uncertainty) is taken.
  const auto excess = [](const FreeFlight& f) {
    return std::sqrt(std::max(0.0, f.force_rms_n * f.force_rms_n - f.noise_rms_n * f.noise_rms_n));
  };
  const FreeFlight &fr = rigid_base.free_flight, &fb = bent_base.free_flight;
  const bool evidence = fr.samples >= o.min_free_flight_samples && (excess(fr) > fr.noise_rms_n || excess(fb) > fb.noise_rms_n);
  const bool take_bent = evidence ? excess(fb) < excess(fr) : bent.valid && (!rigid.valid || bent.uncertainty < rigid.uncertainty);
  FrictionEstimate& chosen = take_bent ? bent : rigid;
  chosen.rotor_choice = evidence ? "free_flight" : "uncertainty";
  return chosen;
}

}  // namespace amb::host::fit
