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
  };
  return j;
}

}  // namespace amb::host
