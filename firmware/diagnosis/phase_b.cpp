#include "firmware/diagnosis/phase_b.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <complex>
#include <cstdio>
#include <numbers>
#include <vector>

#include "firmware/control/axis_transform.hpp"

namespace amb::fw::diag {

const char* to_string(FaultType t) {
  switch (t) {
    case FaultType::not_modeled: return "not_modeled";
    case FaultType::channel_cutoff: return "channel_cutoff";
    case FaultType::current_disturbance: return "current_disturbance";
    case FaultType::changing_unbalance: return "changing_unbalance";
    case FaultType::misalignment: return "misalignment";
    case FaultType::not_evaluated: return "not_evaluated";
  }
  return "unknown";
}

namespace {

constexpr double k_two_pi = 2.0 * std::numbers::pi;

/// 0.5 at the threshold, towards 1 far above it, towards 0 far below: a monotone confidence.
double score(double value, double threshold) {
  if (!(threshold > 0.0)) return value > 0.0 ? 1.0 : 0.0;
  const double v = std::max(0.0, value);
  return v / (v + threshold);
}

bool amps_on(const LoopSample& s) { return (s.flags & flag_amplifiers_enabled) != 0; }

// ---- 1. channel cut-off --------------------------------------------------------------
struct CutoffResult {
  uint8_t mask = 0;
  size_t best_run = 0;
};

CutoffResult find_cutoff(std::span<const LoopSample> s, const DiagnosisOptions& o, double rate_hz) {
  CutoffResult r;
  const auto min_run = static_cast<size_t>(std::max(1.0, std::ceil(o.cutoff_min_run_s * rate_hz)));
  for (size_t k = 0; k < 4; ++k) {
    size_t run = 0, best = 0;
    for (const LoopSample& x : s) {
      const double dem = std::abs(x.current_demand_a[k]), meas = std::abs(x.coil_current_a[k]);
      const bool dead = amps_on(x) && dem > o.cutoff_min_demand_a && meas < std::max(o.cutoff_zero_a, o.cutoff_ratio * dem);
      run = dead ? run + 1 : 0;
      best = std::max(best, run);
    }
    if (best >= min_run) r.mask = static_cast<uint8_t>(r.mask | (1u << k));
    if (best >= min_run) r.best_run = std::max(r.best_run, best);
  }
  return r;
}

// ---- 2. disturbance ------------------------------------------------------------------
using Channels = std::array<std::vector<double>, 4>;

/// First sample index in [from, to) where the moving RMS (over `w` samples) of the largest
/// baseline-normalised deviation exceeds `thr`; `to` if none.
size_t onset(const Channels& ch, size_t nb, size_t from, size_t to, size_t w, double thr, double sigma_floor) {
  std::array<double, 4> mu{}, sd{};
  for (size_t k = 0; k < 4; ++k) {
    double m = 0.0, q = 0.0;
    for (size_t i = 0; i < nb; ++i) m += ch[k][i];
    m /= static_cast<double>(nb);
    for (size_t i = 0; i < nb; ++i) q += (ch[k][i] - m) * (ch[k][i] - m);
    mu[k] = m;
    sd[k] = std::max(sigma_floor, std::sqrt(q / static_cast<double>(nb)));
  }
  std::vector<double> z(to, 0.0);
  for (size_t i = 0; i < to; ++i) {
    double m = 0.0;
    for (size_t k = 0; k < 4; ++k) m = std::max(m, std::pow((ch[k][i] - mu[k]) / sd[k], 2));
    z[i] = m;
  }
  double acc = 0.0;
  for (size_t i = 0; i < to; ++i) {
    acc += z[i];
    if (i >= w) acc -= z[i - w];
    if (i >= from && i + 1 >= w && std::sqrt(acc / static_cast<double>(w)) > thr) return i;
  }
  return to;
}

/// Windowed single-frequency DFT: complex amplitude of `f_hz` in `x` (Hann window).
std::complex<double> tone(const std::vector<double>& x, const std::vector<double>& w, double wsum, double f_hz,
                          double rate_hz) {
  // Goertzel recurrence: O(n) per frequency, no tables.
  const double om = k_two_pi * f_hz / rate_hz;
  const double c = 2.0 * std::cos(om);
  double s1 = 0.0, s2 = 0.0;
  for (size_t i = 0; i < x.size(); ++i) {
    const double s0 = w[i] * x[i] + c * s1 - s2;
    s2 = s1;
    s1 = s0;
  }
  const std::complex<double> y = s1 - std::polar(1.0, -om) * s2;
  return 2.0 * y / wsum;
}

struct Spectrum {
  double f_hz = 0.0;
  std::array<double, 4> amp_a{};
  double explained = 0.0;
  double length_s = 0.0;
};

/// The frequency at which the currents in [a, b) carry the most power (after removing each
/// channel's linear trend), its per-channel amplitudes and the fraction of variance explained.
Spectrum dominant_tone(const Channels& ch, size_t a, size_t b, double rate_hz, const DiagnosisOptions& o) {
  Spectrum sp;
  const size_t n = b - a;
  sp.length_s = static_cast<double>(n) / rate_hz;
  if (n < 16) return sp;
  std::array<std::vector<double>, 4> seg;
  double var_total = 0.0;
  const double tm = 0.5 * static_cast<double>(n - 1);
  for (size_t k = 0; k < 4; ++k) {
    seg[k].assign(ch[k].begin() + static_cast<long>(a), ch[k].begin() + static_cast<long>(b));
    double m = 0.0, st = 0.0, tt = 0.0;
    for (size_t i = 0; i < n; ++i) m += seg[k][i];
    m /= static_cast<double>(n);
    for (size_t i = 0; i < n; ++i) {
      st += (static_cast<double>(i) - tm) * (seg[k][i] - m);
      tt += (static_cast<double>(i) - tm) * (static_cast<double>(i) - tm);
    }
    const double slope = tt > 0.0 ? st / tt : 0.0;
    for (size_t i = 0; i < n; ++i) {
      seg[k][i] -= m + slope * (static_cast<double>(i) - tm);
      var_total += seg[k][i] * seg[k][i] / static_cast<double>(n);
    }
  }
  std::vector<double> w(n);
  double wsum = 0.0;
  for (size_t i = 0; i < n; ++i) {
    w[i] = 0.5 - 0.5 * std::cos(k_two_pi * static_cast<double>(i) / static_cast<double>(n - 1));
    wsum += w[i];
  }
  const double f_lo = std::max(o.disturbance_min_hz, 2.0 / sp.length_s);
  const double f_hi = std::min(o.disturbance_max_hz, 0.45 * rate_hz);
  if (!(f_hi > f_lo)) return sp;
  auto power = [&](double f) {
    double p = 0.0;
    for (size_t k = 0; k < 4; ++k) p += std::norm(tone(seg[k], w, wsum, f, rate_hz));
    return p;
  };
  // Coarse scan at a quarter of the resolution bandwidth (bounded number of frequencies),
  // then a fine scan around the best.
  const double df = std::max(0.25 / sp.length_s, (f_hi - f_lo) / 4000.0);
  double best_f = f_lo, best_p = -1.0;
  for (double f = f_lo; f <= f_hi; f += df) {
    const double p = power(f);
    if (p > best_p) { best_p = p; best_f = f; }
  }
  const double c = best_f;
  for (int i = -20; i <= 20; ++i) {
    const double f = c + df * i / 20.0;
    if (f < f_lo || f > f_hi) continue;
    const double p = power(f);
    if (p > best_p) { best_p = p; best_f = f; }
  }
  sp.f_hz = best_f;
  double explained = 0.0;
  for (size_t k = 0; k < 4; ++k) {
    // Amplitude from the Hann-windowed DFT (unbiased for a tone on the bin).
    sp.amp_a[k] = std::abs(tone(seg[k], w, wsum, best_f, rate_hz));
    explained += 0.5 * sp.amp_a[k] * sp.amp_a[k];
  }
  sp.explained = var_total > 0.0 ? std::min(1.0, explained / var_total) : 0.0;
  return sp;
}

// ---- 3./4. orbit windows -------------------------------------------------------------
struct OrbitWindow {
  double t_s = 0.0;                       ///< window centre, s
  std::array<double, 2> cx{}, cy{};       ///< orbit centre per plane, m
  std::array<double, 2> r1{};             ///< 1x radius per plane (speed-normalised), m
};

/// Least-squares line through (t, v): values at t_first and t_last.
std::pair<double, double> line_ends(const std::vector<double>& t, const std::vector<double>& v) {
  const size_t n = t.size();
  double mt = 0.0, mv = 0.0;
  for (size_t i = 0; i < n; ++i) { mt += t[i]; mv += v[i]; }
  mt /= static_cast<double>(n);
  mv /= static_cast<double>(n);
  double st = 0.0, tt = 0.0;
  for (size_t i = 0; i < n; ++i) { st += (t[i] - mt) * (v[i] - mv); tt += (t[i] - mt) * (t[i] - mt); }
  const double b = tt > 0.0 ? st / tt : 0.0;
  return {mv + b * (t.front() - mt), mv + b * (t.back() - mt)};
}

}  // namespace

Diagnosis diagnose(const DiagnosisInput& in, const DiagnosisOptions& o) {
  Diagnosis d;
  const auto s = in.samples;
  const double fs = in.rate_hz;
  char buf[256];
  if (s.empty() || !(fs > 0.0)) {
    d.summary = "not evaluated: empty window";
    return d;
  }

  // 1. Cut-off of one or more channels: evaluated piecewise over the whole window.
  const CutoffResult cut = find_cutoff(s, o, fs);
  const double min_run_n = std::max(1.0, std::ceil(o.cutoff_min_run_s * fs));
  if (cut.mask) {
    d.type = FaultType::channel_cutoff;
    d.cutoff_channels = cut.mask;
    for (size_t k = 0; k < 4; ++k)
      if (cut.mask & (1u << k)) d.current_factor[k] = 0.0;
    d.confidence = score(static_cast<double>(cut.best_run), min_run_n / 3.0);
    std::snprintf(buf, sizeof buf, "channel cut-off on axes%s%s%s%s (current factor 0), %.1f ms without current",
                  (cut.mask & 1) ? " 0" : "", (cut.mask & 2) ? " 1" : "", (cut.mask & 4) ? " 2" : "",
                  (cut.mask & 8) ? " 3" : "", 1e3 * static_cast<double>(cut.best_run) / fs);
    d.summary = buf;
    return d;
  }

  const size_t T = std::min(in.trigger_index, s.size() - 1);
  const auto min_hist = static_cast<size_t>(std::max(100.0, 0.1 * fs));
  if (T < min_hist) {
    std::snprintf(buf, sizeof buf, "not evaluated: %zu pre-trigger samples, %zu needed", T, min_hist);
    d.summary = buf;
    return d;
  }

  // Signals: measured control currents, raw sensor readings, x/y per plane, speed.
  const size_t n = s.size();
  Channels cur, res, dis;
  std::array<std::vector<double>, 2> x, y;
  for (size_t k = 0; k < 4; ++k) { cur[k].resize(n); res[k].resize(n); dis[k].resize(n); }
  for (size_t b = 0; b < 2; ++b) { x[b].resize(n); y[b].resize(n); }
  std::array<AxisTransform, 2> xf;
  for (size_t b = 0; b < 2; ++b)
    xf[b].configure({in.sensor_angle_deg[2 * b], in.sensor_angle_deg[2 * b + 1]},
                    {in.sensor_angle_deg[2 * b], in.sensor_angle_deg[2 * b + 1]});
  for (size_t i = 0; i < n; ++i) {
    for (size_t k = 0; k < 4; ++k) {
      cur[k][i] = s[i].coil_current_a[k];
      res[k][i] = static_cast<double>(s[i].coil_current_a[k]) - static_cast<double>(s[i].current_demand_a[k]);
      dis[k][i] = s[i].displacement_m[k];
    }
    for (size_t b = 0; b < 2; ++b) {
      const auto xy = xf[b].sensors_to_xy({s[i].displacement_m[2 * b], s[i].displacement_m[2 * b + 1]});
      x[b][i] = xy[0];
      y[b][i] = xy[1];
    }
  }
  // Mean speed over the samples that carry one (a tracker that lost the line stamps NaN).
  // With a speed on fewer than half of them the orders are unknown: not treated as spinning.
  double speed = 0.0;
  size_t with_speed = 0;
  for (size_t i = 0; i < T; ++i)
    if (std::isfinite(s[i].speed_hz)) {
      speed += s[i].speed_hz;
      ++with_speed;
    }
  speed = 2 * with_speed >= T && with_speed > 0 ? speed / static_cast<double>(with_speed)
                                                : std::numeric_limits<double>::quiet_NaN();
  d.speed_hz = speed;
  const bool spinning = speed >= o.min_speed_hz;

  // 2. Disturbance of the control currents: a change in the currents BEFORE the deflection,
  // at a frequency that is not the rotor's (Fig. 2: evaluation of the frequency domain).
  const size_t nb = std::max<size_t>(20, static_cast<size_t>(o.baseline_fraction * static_cast<double>(T)));
  size_t end_on = std::min(n, T + static_cast<size_t>(o.onset_margin_s * fs));
  for (size_t i = T; i < end_on; ++i)
    if (!amps_on(s[i])) { end_on = i; break; }
  const auto w = static_cast<size_t>(std::max(2.0, o.onset_window_s * fs));
  // The currents' change: in the measured current itself, or in the part of it the controller
  // did not ask for (measured - demand), whichever shows first. The second is far less noisy
  // (the controller's derivative term puts the sensor noise into the demand) and is exactly
  // what a disturbance of the amplifier adds.
  const size_t on_c = std::min(onset(cur, nb, nb, end_on, w, o.onset_threshold, 1e-4),
                               onset(res, nb, nb, end_on, w, o.onset_threshold, 1e-4));
  const size_t on_d = onset(dis, nb, nb, end_on, w, o.onset_threshold, 1e-8);
  double dist_score = 0.0;
  if (on_c < end_on) {
    d.current_lead_s = (static_cast<double>(on_d) - static_cast<double>(on_c)) / fs;
    const size_t a = on_c >= w ? on_c - w : 0;
    size_t b = std::min(n, a + static_cast<size_t>(o.max_spectrum_s * fs));
    for (size_t i = a; i < b; ++i)
      if (!amps_on(s[i])) { b = i; break; }
    const Spectrum sp = dominant_tone(res, a, b, fs, o);
    const double sync_tol_hz = std::max(1.0, 1.5 / std::max(sp.length_s, 1e-3));
    const bool synchronous = spinning && std::abs(sp.f_hz - speed) < sync_tol_hz;
    const bool leads = d.current_lead_s >= o.min_current_lead_s;
    if (sp.f_hz > 0.0 && leads && !synchronous && sp.explained >= o.min_explained) {
      d.type = FaultType::current_disturbance;
      d.disturbance_frequency_hz = sp.f_hz;
      const double amax = *std::max_element(sp.amp_a.begin(), sp.amp_a.end());
      d.disturbance_amplitude_a = amax;
      for (size_t k = 0; k < 4; ++k)
        if (sp.amp_a[k] > 0.3 * amax) d.disturbance_channels = static_cast<uint8_t>(d.disturbance_channels | (1u << k));
      d.confidence = std::min(score(d.current_lead_s, o.min_current_lead_s), score(sp.explained, o.min_explained));
      std::snprintf(buf, sizeof buf,
                    "disturbance of the control currents at %.2f Hz (amplitude ~%.3f A), currents changed %.1f ms "
                    "before the deflection",
                    sp.f_hz, amax, 1e3 * d.current_lead_s);
      d.summary = buf;
      return d;
    }
    if (leads && !synchronous) dist_score = score(sp.explained, o.min_explained) * 0.5;
  }

  // 3./4. Orbit windows over the pre-trigger history: whole revolutions when spinning.
  std::vector<OrbitWindow> wins;
  {
    size_t len = static_cast<size_t>(o.window_s * fs);
    if (spinning) {
      const double rev = fs / speed;
      const double revs = static_cast<double>(T) / rev;
      const double k = std::max(2.0, std::floor(revs / 6.0));
      len = static_cast<size_t>(std::llround(k * rev));
    }
    len = std::max<size_t>(len, 8);
    const double f_end = std::max(std::isfinite(s[T].speed_hz) ? static_cast<double>(s[T].speed_hz) : speed, o.min_speed_hz);
    for (size_t a = T % len; a + len <= T; a += len) {
      OrbitWindow ow;
      ow.t_s = (static_cast<double>(a) + 0.5 * static_cast<double>(len)) / fs;
      double fw = 0.0;
      size_t nw = 0;
      for (size_t i = a; i < a + len; ++i)
        if (std::isfinite(s[i].speed_hz)) {
          fw += s[i].speed_hz;
          ++nw;
        }
      fw = nw > 0 ? fw / static_cast<double>(nw) : speed;
      for (size_t b = 0; b < 2; ++b) {
        double mx = 0.0, my = 0.0;
        for (size_t i = a; i < a + len; ++i) { mx += x[b][i]; my += y[b][i]; }
        mx /= static_cast<double>(len);
        my /= static_cast<double>(len);
        ow.cx[b] = mx;
        ow.cy[b] = my;
        if (spinning && fw > 0.0) {
          // 1x: DFT at the window's mean speed of the mean-free orbit; the radius is normalised
          // to the trigger speed by f^2 (unbalance response below the first bending mode) so a
          // speed ramp alone does not look like a changing unbalance.
          // The window's linear trend is removed first: a moving centre would otherwise leak
          // into the 1x bin and look like a changing radius.
          const double tm = 0.5 * static_cast<double>(len - 1);
          double sx = 0.0, sy = 0.0, tt = 0.0;
          for (size_t i = a; i < a + len; ++i) {
            const double u = static_cast<double>(i - a) - tm;
            sx += u * (x[b][i] - mx);
            sy += u * (y[b][i] - my);
            tt += u * u;
          }
          const double bx = sx / tt, by = sy / tt;
          std::complex<double> X, Y;
          for (size_t i = a; i < a + len; ++i) {
            const double u = static_cast<double>(i - a) - tm;
            const std::complex<double> e = std::polar(1.0, -k_two_pi * fw * static_cast<double>(i - a) / fs);
            X += (x[b][i] - mx - bx * u) * e;
            Y += (y[b][i] - my - by * u) * e;
          }
          X *= 2.0 / static_cast<double>(len);
          Y *= 2.0 / static_cast<double>(len);
          const double r = std::sqrt(0.5 * (std::norm(X) + std::norm(Y)));
          ow.r1[b] = r * (f_end * f_end) / (fw * fw);
        }
      }
      wins.push_back(ow);
    }
  }
  if (wins.size() < 3) {
    std::snprintf(buf, sizeof buf, "not evaluated: %zu orbit windows in the history, 3 needed", wins.size());
    d.type = FaultType::not_evaluated;
    d.summary = buf;
    return d;
  }
  std::vector<double> t;
  for (const auto& ow : wins) t.push_back(ow.t_s);
  double unb_best = 0.0;
  int unb_plane = -1;
  std::array<double, 2> rel{};
  for (size_t b = 0; b < 2; ++b) {
    std::vector<double> r;
    for (const auto& ow : wins) r.push_back(ow.r1[b]);
    const auto [r0, r1] = line_ends(t, r);
    d.radius_1x_start_m[b] = std::max(0.0, r0);
    d.radius_1x_end_m[b] = std::max(0.0, r1);
    const double growth = r1 - r0;
    rel[b] = (r1 - r0) / std::max(std::abs(r0), 1e-7);
    if (spinning && growth > o.unbalance_min_growth_m) {
      const double m = std::min(growth / o.unbalance_min_growth_m, rel[b] / o.unbalance_min_relative);
      if (m > unb_best) { unb_best = m; unb_plane = static_cast<int>(b); }
    }
  }
  if (unb_plane >= 0 && unb_best >= 1.0) {
    d.type = FaultType::changing_unbalance;
    d.confidence = score(unb_best, 1.0);
    const auto b = static_cast<size_t>(unb_plane);
    std::snprintf(buf, sizeof buf,
                  "changing unbalance: 1x orbit radius at plane %c rose from %.1f to %.1f um over %.2f s at %.1f Hz",
                  b == 0 ? 'A' : 'B', 1e6 * d.radius_1x_start_m[b], 1e6 * d.radius_1x_end_m[b], t.back() - t.front(),
                  speed);
    d.summary = buf;
    return d;
  }

  // 4. Misalignment: the centre of the mean orbit moves while the radius stays.
  double mis_best = 0.0;
  for (size_t b = 0; b < 2; ++b) {
    std::vector<double> cx, cy;
    for (const auto& ow : wins) { cx.push_back(ow.cx[b]); cy.push_back(ow.cy[b]); }
    const auto [x0, x1] = line_ends(t, cx);
    const auto [y0, y1] = line_ends(t, cy);
    const double dx = x1 - x0, dy = y1 - y0;
    d.centre_shift_m[b] = std::hypot(dx, dy);
    const bool radius_stays = !spinning || std::abs(rel[b]) <= o.misalignment_max_radius_relative ||
                              std::abs(d.radius_1x_end_m[b] - d.radius_1x_start_m[b]) < o.unbalance_min_growth_m;
    const double m = d.centre_shift_m[b] / o.misalignment_min_shift_m;
    if (radius_stays && m > mis_best) {
      mis_best = m;
      d.misalignment_plane = static_cast<int>(b);
      d.misalignment_direction_deg = std::atan2(dx, dy) * 180.0 / std::numbers::pi;
    }
  }
  if (mis_best >= 1.0) {
    d.type = FaultType::misalignment;
    d.confidence = score(mis_best, 1.0);
    const auto b = static_cast<size_t>(d.misalignment_plane);
    std::snprintf(buf, sizeof buf,
                  "misalignment: orbit centre at plane %c moved %.1f um towards %.0f deg while the 1x radius stayed",
                  b == 0 ? 'A' : 'B', 1e6 * d.centre_shift_m[b], d.misalignment_direction_deg);
    d.summary = buf;
    return d;
  }
  d.misalignment_plane = -1;
  d.misalignment_direction_deg = 0.0;

  // 5. Nothing embedded fits: the confidence is how clearly every test stayed below its threshold.
  d.type = FaultType::not_modeled;
  const double worst = std::max({dist_score, score(unb_best, 1.0), score(mis_best, 1.0)});
  d.confidence = std::clamp(1.0 - worst, 0.0, 1.0);
  std::snprintf(buf, sizeof buf,
                "not a modeled fault: no channel cut-off, no current change ahead of the deflection, 1x radius "
                "change %.0f %%, centre shift %.1f um",
                100.0 * std::max(rel[0], rel[1]), 1e6 * std::max(d.centre_shift_m[0], d.centre_shift_m[1]));
  d.summary = buf;
  return d;
}

}  // namespace amb::fw::diag
