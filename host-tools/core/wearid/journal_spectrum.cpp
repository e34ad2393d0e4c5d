#include "host-tools/core/wearid/journal_spectrum.hpp"

#include <cmath>
#include <stdexcept>

#include "model/amb/amb_force.hpp"

namespace amb::host::wearid {
namespace {
constexpr double k_two_pi = 2.0 * M_PI;

double angle_diff_deg(double a, double b) {
  double d = std::fmod(a - b, 360.0);
  if (d > 180.0) d -= 360.0;
  if (d < -180.0) d += 360.0;
  return std::abs(d);
}

// Single-frequency DFT over [first, first + n): (2/n) sum x e^{-j 2 pi f t}, t from the event start.
cplx dft(const std::vector<double>& x, const std::vector<double>& t, size_t first, size_t n, double f_hz) {
  double mean = 0.0;
  for (size_t k = first; k < first + n; ++k) mean += x[k];
  mean /= static_cast<double>(n);
  cplx s = 0.0;
  for (size_t k = first; k < first + n; ++k) s += (x[k] - mean) * std::exp(cplx(0.0, -k_two_pi * f_hz * t[k]));
  return 2.0 / static_cast<double>(n) * s;
}
}  // namespace

JournalMeasurement measure_journal(const LoadedEvent& ev, const board::BoardConfig& board, double window_s) {
  if (!board.journal.present)
    throw std::invalid_argument("wear-id: board '" + board.name + "' has no [journal_bearing]");
  const auto& jb = board.journal;
  const LoadedChannel* probe[2] = {nullptr, nullptr};
  for (const auto& c : ev.displacement) {
    if (std::abs(c.axial_m - jb.axial_m) > board.capture.match_axial_tolerance_m) continue;
    for (size_t k = 0; k < 2; ++k)
      if (angle_diff_deg(c.angle_deg, jb.probe_angle_deg[k]) <= board.capture.match_angle_tolerance_deg) probe[k] = &c;
  }
  for (size_t k = 0; k < 2; ++k)
    if (probe[k] == nullptr)
      throw std::invalid_argument("wear-id: event has no displacement channel at the journal plane (" +
                                  std::to_string(jb.axial_m) + " m) along " + std::to_string(jb.probe_angle_deg[k]) +
                                  " deg");
  const LoadedChannel* kp = nullptr;
  for (const auto& c : ev.other)
    if (c.name == "keyphasor" && c.quantity == "voltage") kp = &c;
  if (kp == nullptr) throw std::invalid_argument("wear-id: event has no 'keyphasor' voltage channel (needed as phase reference)");
  const size_t n_all = ev.samples();
  if (n_all < 100 || !(ev.sample_rate_hz > 0.0)) throw std::invalid_argument("wear-id: event too short");

  JournalMeasurement m;
  // Speed: mean of the speed channel over the record's second half, else the trigger speed.
  if (!ev.speed_hz.empty()) {
    double s = 0.0;
    size_t c = 0;
    for (size_t k = n_all / 2; k < n_all; ++k) {
      s += ev.speed_hz[k];
      ++c;
    }
    m.speed_hz = s / static_cast<double>(c);
  } else if (ev.speed_at_trigger_hz) {
    m.speed_hz = *ev.speed_at_trigger_hz;
  }
  if (!(m.speed_hz > 1.0)) throw std::invalid_argument("wear-id: event has no usable speed (channel or speed_rpm)");

  // Whole revolutions at the end of the record, within window_s and after the trigger.
  const double avail_s = static_cast<double>(n_all - ev.trigger_index) / ev.sample_rate_hz;
  const double use_s = std::min(window_s, avail_s);
  m.available_s = avail_s;
  m.revolutions = static_cast<int>(std::floor(use_s * m.speed_hz));
  if (m.revolutions < 8) throw std::invalid_argument("wear-id: fewer than 8 revolutions of steady data after the trigger");
  const size_t n = static_cast<size_t>(std::llround(m.revolutions / m.speed_hz * ev.sample_rate_hz));
  const size_t first = n_all - n;
  m.window_s = static_cast<double>(n) / ev.sample_rate_hz;

  // Key phasor: fundamental phase and pulse width (duty) give the time of spin angle 0.
  double hi = 0.0, lo = 1e300, high_mean = 0.0;
  for (size_t k = first; k < n_all; ++k) {
    hi = std::max(hi, kp->values[k]);
    lo = std::min(lo, kp->values[k]);
  }
  if (!(hi - lo > 0.0)) throw std::invalid_argument("wear-id: keyphasor channel is flat");
  size_t high = 0;
  for (size_t k = first; k < n_all; ++k) high += kp->values[k] > 0.5 * (hi + lo) ? 1 : 0;
  high_mean = static_cast<double>(high) / static_cast<double>(n);
  const double width_rad = k_two_pi * high_mean;
  const cplx kf = dft(kp->values, ev.t_s, first, n, m.speed_hz);
  // A pulse on [0, w) of spin angle has its fundamental at angle w/2: kf ~ e^{-j W t0} e^{-j w/2}.
  const cplx ref = kf / std::abs(kf) * std::exp(cplx(0.0, 0.5 * width_rad));  // = e^{-j W t0}

  cplx xp = dft(probe[0]->values, ev.t_s, first, n, m.speed_hz) * std::conj(ref);
  cplx yp = dft(probe[1]->values, ev.t_s, first, n, m.speed_hz) * std::conj(ref);
  const cplx j(0.0, 1.0);
  m.spectrum = {0.5 * (xp + j * yp), 0.5 * std::conj(xp - j * yp)};
  // Second harmonic, referred to twice the spin angle (ref^2 = e^{-j 2 W t0}).
  const cplx x2 = dft(probe[0]->values, ev.t_s, first, n, 2.0 * m.speed_hz) * std::conj(ref * ref);
  const cplx y2 = dft(probe[1]->values, ev.t_s, first, n, 2.0 * m.speed_hz) * std::conj(ref * ref);
  m.second_harmonic = {0.5 * (x2 + j * y2), 0.5 * std::conj(x2 - j * y2)};

  // The AMB sensor planes, when the event has all four sensor channels (matched to the rig).
  const LoadedChannel* sens[4] = {nullptr, nullptr, nullptr, nullptr};
  for (const auto& c : ev.displacement)
    if (c.rig_index >= 0 && c.rig_index < 4) sens[c.rig_index] = &c;
  if (sens[0] && sens[1] && sens[2] && sens[3]) {
    m.has_amb_planes = true;
    for (size_t p = 0; p < 2; ++p) {
      const cplx a = dft(sens[2 * p]->values, ev.t_s, first, n, m.speed_hz) * std::conj(ref);
      const cplx c = dft(sens[2 * p + 1]->values, ev.t_s, first, n, m.speed_hz) * std::conj(ref);
      m.amb_planes[p] = {0.5 * (a + j * c), 0.5 * std::conj(a - j * c)};
    }
  }

  // Noise of one full-spectrum component: off-bin DFTs of the complex signal x' + j y'.
  double ss = 0.0;
  int cnt = 0;
  for (int b = 3; b <= 10; ++b)
    for (int sgn : {-1, 1}) {
      const double f = m.speed_hz + sgn * b / m.window_s;
      const cplx a = dft(probe[0]->values, ev.t_s, first, n, f), c = dft(probe[1]->values, ev.t_s, first, n, f);
      ss += std::norm(0.5 * (a + j * c));
      ++cnt;
    }
  m.noise_m = std::sqrt(ss / cnt);
  ss = 0.0;
  cnt = 0;
  for (int b = 3; b <= 10; ++b)
    for (int sgn : {-1, 1}) {
      const double f = 2.0 * m.speed_hz + sgn * b / m.window_s;
      const cplx a = dft(probe[0]->values, ev.t_s, first, n, f), c = dft(probe[1]->values, ev.t_s, first, n, f);
      ss += std::norm(0.5 * (a + j * c));
      ++cnt;
    }
  m.noise_2x_m = std::sqrt(ss / cnt);

  // Static position: probe means along their directions (solve the 2 x 2 projection).
  double mean[2] = {0.0, 0.0};
  for (size_t k = 0; k < 2; ++k) {
    for (size_t i = first; i < n_all; ++i) mean[k] += probe[k]->values[i];
    mean[k] /= static_cast<double>(n);
  }
  const auto d0 = model::magnet::axis_direction(jb.probe_angle_deg[0]);
  const auto d1 = model::magnet::axis_direction(jb.probe_angle_deg[1]);
  const double det = d0[0] * d1[1] - d0[1] * d1[0];
  if (std::abs(det) < 0.5) throw std::invalid_argument("wear-id: journal probes are not close to orthogonal");
  m.journal.x_m = (mean[0] * d1[1] - mean[1] * d0[1]) / det;
  m.journal.y_m = (d0[0] * mean[1] - d1[0] * mean[0]) / det;
  m.eccentricity = std::hypot(m.journal.x_m, m.journal.y_m) / jb.geometry.clearance_m;
  if (!(m.eccentricity < 0.98)) throw std::invalid_argument("wear-id: static journal position is at the bore (eccentricity >= 0.98)");
  return m;
}

}  // namespace amb::host::wearid
