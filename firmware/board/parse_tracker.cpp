#include "firmware/board/parse_tracker.hpp"

namespace amb::board {

void parse_tracker(TableReader r, fw::TrackerParams& t, double rate_hz) {
  using model::signal::WindowType;
  auto& o = t.options;
  t.enabled = r.boolean_or("enabled", true);
  t.channel = static_cast<int>(r.integer_or("channel", 0, 0, 3));
  t.max_gap_samples = static_cast<size_t>(r.integer_or("max_gap_samples", 8, 0, 100000));
  o.stft.sample_rate_hz = rate_hz;
  const std::string w = r.string_or("window", "hamming");
  if (w == "hamming") o.stft.window = WindowType::kHamming;
  else if (w == "hann") o.stft.window = WindowType::kHann;
  else if (w == "blackman") o.stft.window = WindowType::kBlackman;
  else if (w == "rectangular") o.stft.window = WindowType::kRectangular;
  else r.fail("window", "must be one of \"hamming\", \"hann\", \"blackman\", \"rectangular\"");
  o.stft.window_s = r.number_or("window_s", o.stft.window_s, 0.01, 10.0);
  o.stft.overlap = r.number_or("overlap", o.stft.overlap, 0.0, 0.99);
  o.stft.nfft = static_cast<size_t>(r.integer_or("nfft", static_cast<long long>(o.stft.nfft), 64, 1 << 20));
  o.min_speed_hz = r.number_or("min_speed_hz", o.min_speed_hz, 0.1, 5000.0);
  o.max_speed_hz = r.number_or("max_speed_hz", o.max_speed_hz, o.min_speed_hz, 0.5 * rate_hz);
  o.search_half_band_hz = r.number_or("search_half_band_hz", o.search_half_band_hz, 0.1, 1000.0);
  o.max_accel_hz_per_s = r.number_or("max_accel_hz_per_s", o.max_accel_hz_per_s, 0.01, 10000.0);
  if (r.has("orders")) {
    const auto orders = r.numbers("orders", -1, 0.1, 100.0);
    if (orders.empty() || orders.size() > o.orders.size())
      r.fail("orders", "must list 1 to " + std::to_string(o.orders.size()) + " orders");
    o.n_orders = orders.size();
    for (size_t i = 0; i < o.orders.size(); ++i) {
      o.orders[i] = i < orders.size() ? orders[i] : 0.0;
      o.order_weights[i] = i < orders.size() ? 1.0 / (1.0 + 0.5 * static_cast<double>(i)) : 0.0;
    }
  }
  const std::string src = r.string_or("speed_source", "tach");
  if (src == "tach") t.speed_source = fw::SpeedSource::tach;
  else if (src == "tracker") t.speed_source = fw::SpeedSource::tracker;
  else if (src == "command") t.speed_source = fw::SpeedSource::command;
  else r.fail("speed_source", "must be one of \"tach\", \"tracker\", \"command\"");
  if (t.speed_source == fw::SpeedSource::tracker && !t.enabled)
    r.fail("speed_source", "\"tracker\" needs the tracker enabled (enabled = true)");
  t.min_confidence = r.number_or("min_confidence", t.min_confidence, 0.0, 1.0);
  t.tach_disagreement_fraction = r.number_or("tach_disagreement_fraction", t.tach_disagreement_fraction, 0.001, 1.0);
  t.poll_period_s = r.number_or("poll_period_s", t.poll_period_s, 0.001, 1.0);
  t.status_frame_period_s = r.number_or("status_frame_period_s", t.status_frame_period_s, 0.01, 10.0);
  // A lock older than a few tracker hops is stale; never shorter than the analysis period.
  t.stale_after_s = r.number_or("stale_after_s", t.stale_after_s, 2.0 * t.poll_period_s, 60.0);
  const std::string err = o.validate();
  if (!err.empty()) r.fail("", err);
  r.finish();
}

}  // namespace amb::board
