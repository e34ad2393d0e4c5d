#include "host-tools/core/tracking/track_speed.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "model/signal/fir_decimator.hpp"

namespace amb::host {
namespace sig = model::signal;

std::string TrackSpeedOptions::validate(double fs_hz) const {
  if (!(fs_hz > 0.0 && std::isfinite(fs_hz)))
    return "fs must be a positive sample rate in Hz, got " + std::to_string(fs_hz);
  if (decimate > 4096) return "decimate must be 0 (auto) or in [1, 4096], got " + std::to_string(decimate);
  sig::SpeedTrackerOptions t = tracker;
  const size_t m = decimate == 0 ? auto_decimation(*this, fs_hz) : decimate;
  t.stft.sample_rate_hz = fs_hz / static_cast<double>(m);
  if (std::string err = t.validate(); !err.empty())
    return err + " (tracker rate " + std::to_string(t.stft.sample_rate_hz) + " Hz after decimation by " +
           std::to_string(m) + ")";
  return {};
}

size_t auto_decimation(const TrackSpeedOptions& options, double fs_hz) {
  const sig::SpeedTrackerOptions& t = options.tracker;
  double o_max = 0.0;
  for (size_t k = 0; k < std::min(t.n_orders, sig::k_max_orders); ++k) o_max = std::max(o_max, t.orders[k]);
  const double f_top = o_max * t.max_speed_hz + 2.0 * t.search_half_band_hz;
  if (!(f_top > 0.0) || !(fs_hz > 0.0)) return 1;
  auto m = static_cast<size_t>(std::floor(fs_hz / (2.5 * f_top)));
  // Keep seed 003's zero padding (5000-sample window in 8192 points, about 1.6): more
  // decimation would only interpolate the spectrum further and shrink the floor blocks
  // relative to the main lobe. The window must also fit into nfft.
  const double win_samples = t.stft.window_s * fs_hz;
  const auto m_pad = static_cast<size_t>(std::floor(win_samples / (0.61 * static_cast<double>(t.stft.nfft))));
  const auto m_fit = static_cast<size_t>(std::ceil(win_samples / static_cast<double>(t.stft.nfft)));
  m = std::min<size_t>({m, std::max<size_t>(m_pad, 1), 4096});
  if (m < 2) m = 1;
  return std::max<size_t>({m, m_fit, 1});
}

TrackSpeedResult track_speed(const std::vector<double>& x, double fs_hz, const TrackSpeedOptions& options) {
  if (std::string err = options.validate(fs_hz); !err.empty()) throw std::invalid_argument(err);
  if (x.empty()) throw std::invalid_argument("the signal is empty");
  for (size_t i = 0; i < x.size(); ++i)
    if (!std::isfinite(x[i]))
      throw std::invalid_argument("the signal has a non-finite sample at index " + std::to_string(i));

  TrackSpeedResult r;
  r.decimation = options.decimate == 0 ? auto_decimation(options, fs_hz) : options.decimate;
  sig::FirDecimator dec;
  sig::FirDecimatorOptions dopt;
  dopt.input_rate_hz = fs_hz;
  dopt.factor = r.decimation;
  if (std::string err = dec.configure(dopt); !err.empty()) throw std::invalid_argument("decimator: " + err);

  sig::SpeedTrackerOptions topt = options.tracker;
  topt.stft.sample_rate_hz = dec.output_rate_hz();
  r.tracker_rate_hz = topt.stft.sample_rate_hz;
  r.window_s = topt.stft.window_s;
  const double needed_s = topt.stft.window_s;
  if (static_cast<double>(x.size()) / fs_hz < needed_s)
    throw std::invalid_argument("the record (" + std::to_string(static_cast<double>(x.size()) / fs_hz) +
                                " s) is shorter than one window (window_s " + std::to_string(needed_s) + " s)");
  sig::SpeedRidgeTracker tracker;
  if (std::string err = tracker.configure(topt); !err.empty()) throw std::invalid_argument(err);

  // Output sample j of the decimator describes input time ((j+1) M - 1)/fs - delay.
  const double t_offset_s =
      (static_cast<double>(r.decimation) - 1.0) / fs_hz - (r.decimation > 1 ? dec.delay_s() : 0.0);
  auto record = [&](const sig::SpeedEstimate& e) {
    r.t_s.push_back(e.t_s + t_offset_s);
    r.speed_hz.push_back(e.speed_hz);
    r.confidence.push_back(e.confidence);
    r.lost.push_back(e.lost);
    r.below_min.push_back(e.below_min);
  };
  double y = 0.0;
  for (double v : x) {
    if (dec.push(v, y) && tracker.push(y)) record(tracker.latest());
  }
  r.summary = tracker.summary();
  return r;
}

TrackSpeedResult track_speed_with_profile(const std::vector<double>& x, double fs_hz, const MachineProfile& profile,
                                          const ProfileRunConstants& constants) {
  if (!(fs_hz > 0.0 && std::isfinite(fs_hz))) throw std::invalid_argument("fs must be a positive sample rate in Hz");
  if (x.empty()) throw std::invalid_argument("the signal is empty");
  for (size_t i = 0; i < x.size(); ++i)
    if (!std::isfinite(x[i]))
      throw std::invalid_argument("the signal has a non-finite sample at index " + std::to_string(i));
  const double rec_s = static_cast<double>(x.size()) / fs_hz;
  // Discovery on a decimated copy: orders up to 8 of the highest speed, Nyquist margin 2.5.
  const int max_order = 8;
  const double o_top = profile.discover_orders ? max_order
                                               : *std::max_element(profile.orders.begin(), profile.orders.end());
  auto m = static_cast<size_t>(std::floor(fs_hz / (2.5 * o_top * profile.max_speed_hz)));
  m = std::clamp<size_t>(m, 1, 4096);
  sig::FirDecimator dec;
  sig::FirDecimatorOptions dopt;
  dopt.input_rate_hz = fs_hz;
  dopt.factor = m;
  if (std::string err = dec.configure(dopt); !err.empty()) throw std::invalid_argument("decimator: " + err);
  std::vector<double> xd;
  xd.reserve(x.size() / m + 1);
  double y = 0.0;
  for (double v : x)
    if (dec.push(v, y)) xd.push_back(y);
  const size_t skip = std::min(xd.size() / 4, static_cast<size_t>(std::ceil(dec.delay_s() * dec.output_rate_hz())));
  const std::vector<double> xs(xd.begin() + static_cast<std::ptrdiff_t>(skip), xd.end());
  OrderDiscoveryOptions dop;
  dop.min_speed_hz = profile.min_speed_hz;
  dop.max_speed_hz = profile.max_speed_hz;
  dop.max_order = max_order;
  dop.max_accel_hz_per_s = profile.max_accel_hz_per_s;
  dop.ambiguity_ratio = constants.ambiguity_ratio;
  dop.target_prominence_db = constants.target_prominence_db;
  dop.false_alarm = constants.false_alarm;
  if (!profile.from_file) dop.ambiguity_ratio = 0.0;  // no prior: any unrelated family is a doubt
  // Segments as long as the tracker's longest window: a line that the tracker can see sharp.
  dop.segment_s = std::max(0.5, std::min({0.5 * rec_s, std::sqrt(8.0 / profile.max_accel_hz_per_s), 4.0}));
  dop.line_tolerance = std::min(0.01, profile.max_accel_hz_per_s * dop.segment_s / profile.max_speed_hz);
  // Longest window: half the record, 4 s, and the drift limit sqrt(8 / max_accel) (a drift at the
  // limit moves a line by at most 8 / T... i.e. a few resolution widths, which the tracker's warp
  // follows) -- but never shorter than what resolves the lowest expected speed (12 / min_hz).
  const double max_window_s = std::min(
      {0.5 * rec_s, 4.0, std::max(std::sqrt(8.0 / profile.max_accel_hz_per_s), 12.0 / profile.max_speed_hz)});
  OrderDiscovery disc = discover_orders(xs, dec.output_rate_hz(), dop, max_window_s);

  TrackSpeedOptions opt;
  sig::SpeedTrackerOptions& t = opt.tracker;
  t.min_speed_hz = profile.min_speed_hz;
  t.max_speed_hz = profile.max_speed_hz;
  t.max_accel_hz_per_s = profile.max_accel_hz_per_s;
  t.rate_step_hz_per_s = std::min(t.rate_step_hz_per_s, 0.5 * profile.max_accel_hz_per_s);
  std::vector<double> orders = profile.discover_orders ? disc.orders : profile.orders;
  if (orders.empty()) orders = {1.0};
  t.n_orders = std::min(orders.size(), sig::k_max_orders);
  for (size_t k = 0; k < t.n_orders; ++k) {
    t.orders[k] = orders[k];
    t.order_weights[k] = 1.0 - 0.1 * static_cast<double>(k);
  }
  t.stft.window_s = disc.found ? disc.window_s : 0.5;
  if (rec_s < t.stft.window_s) t.stft.window_s = std::max(0.05, 0.5 * rec_s);
  // Short records (fewer than ~20 windows): denser updates.
  t.stft.overlap = rec_s < 20.0 * t.stft.window_s ? 0.95 : 0.9;
  if (disc.found && !disc.ambiguous)
    t.initial_speed_hz = std::clamp(disc.speed_hz, profile.min_speed_hz, profile.max_speed_hz);
  // The tracker's own grid must be able to reach its largest order below Nyquist.
  TrackSpeedResult r = track_speed(x, fs_hz, opt);
  r.profiled = true;
  r.discovery = disc;
  r.window_s = t.stft.window_s;
  auto drop = [&](size_t i) {
    if (!r.lost[i]) ++r.rejected_updates;
    r.lost[i] = true;
    r.speed_hz[i] = std::nan("");
  };
  if (!disc.found || disc.ambiguous || !disc.resolved) {
    r.status = !disc.found ? "no_line" : disc.ambiguous ? "ambiguous" : "unresolved";
    for (size_t i = 0; i < r.t_s.size(); ++i) drop(i);
    r.rejected_updates = 0;
    return r;
  }
  r.status = "ok";
  const double t_mid = 0.5 * rec_s;
  // Coarse-track times are relative to the first kept decimated sample (index `skip`), which
  // describes input time ((skip + 1) M - 1) / fs - FIR delay.
  const double t_shift = (static_cast<double>((skip + 1) * m) - 1.0) / fs_hz - (m > 1 ? dec.delay_s() : 0.0);
  const auto& ct = disc.coarse_t_s;
  const auto& cf = disc.coarse_hz;
  for (size_t i = 0; i < r.t_s.size(); ++i) {
    if (r.lost[i]) continue;
    const double allowed = profile.max_accel_hz_per_s * std::abs(r.t_s[i] - t_mid) + 0.01 * disc.speed_hz +
                           2.0 * disc.bin_hz;
    if (std::abs(r.speed_hz[i] - disc.speed_hz) > allowed) {
      drop(i);
      continue;
    }
    // Independent coarse estimate (the segment spectra of the discovery): the nearest segment
    // centre within half a segment; disagreement beyond 1 % + one resolution width of the
    // segment (1/T_seg) + the drift over the time offset means one of the two is wrong: lost.
    size_t best = ct.size();
    double best_dt = 0.5 * disc.segment_s;
    for (size_t k = 0; k < ct.size(); ++k) {
      const double dt = std::abs(ct[k] + t_shift - r.t_s[i]);
      if (dt <= best_dt) {
        best_dt = dt;
        best = k;
      }
    }
    if (best == ct.size()) continue;
    const double tol = 0.01 * cf[best] + 1.0 / disc.segment_s + profile.max_accel_hz_per_s * best_dt;
    if (std::abs(r.speed_hz[i] - cf[best]) > tol) drop(i);
  }
  return r;
}

double median_speed_hz(const TrackSpeedResult& r) {
  std::vector<double> v;
  for (size_t i = 0; i < r.speed_hz.size(); ++i)
    if (!r.lost[i] && std::isfinite(r.speed_hz[i])) v.push_back(r.speed_hz[i]);
  if (v.empty()) return std::nan("");
  const size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid), v.end());
  double m = v[mid];
  if (v.size() % 2 == 0) {
    const double lo = *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid));
    m = 0.5 * (m + lo);
  }
  return m;
}

double lost_fraction(const TrackSpeedResult& r) {
  if (r.lost.empty()) return 0.0;
  const auto n = static_cast<double>(std::count(r.lost.begin(), r.lost.end(), true));
  return n / static_cast<double>(r.lost.size());
}

nlohmann::json to_json(const TrackSpeedResult& r) {
  nlohmann::json j;
  j["t_s"] = r.t_s;
  nlohmann::json speed = nlohmann::json::array();
  for (double v : r.speed_hz) speed.push_back(std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr));
  j["speed_hz"] = std::move(speed);
  j["confidence"] = r.confidence;
  j["lost"] = r.lost;
  j["below_min"] = r.below_min;
  const double med = median_speed_hz(r);
  j["summary"] = {
      {"update_rate_hz", r.summary.update_rate_hz},
      {"median_speed_hz", std::isfinite(med) ? nlohmann::json(med) : nlohmann::json(nullptr)},
      {"lost_fraction", lost_fraction(r)},
      {"stated_min_speed_hz", r.summary.stated_min_speed_hz},
      {"latency_s", r.summary.latency_s},
      {"decimation", r.decimation},
      {"tracker_rate_hz", r.tracker_rate_hz},
      {"acquisitions", r.summary.acquisitions},
      {"losses", r.summary.losses},
      {"status", r.status},
      {"window_s", r.window_s},
  };
  if (r.profiled) {
    const auto& d = r.discovery;
    j["summary"]["discovery"] = {
        {"found", d.found},
        {"ambiguous", d.ambiguous},
        {"speed_hz", d.found ? nlohmann::json(d.speed_hz) : nlohmann::json(nullptr)},
        {"orders", d.orders},
        {"prominence_db", d.prominence_db},
        {"threshold_db", d.threshold_db},
        {"runner_up_hz", d.runner_up_hz > 0 ? nlohmann::json(d.runner_up_hz) : nlohmann::json(nullptr)},
        {"score", d.score},
        {"runner_up_score", d.runner_up_score},
        {"reason", d.reason},
    };
    j["summary"]["rejected_updates"] = r.rejected_updates;
  }
  return j;
}

}  // namespace amb::host
