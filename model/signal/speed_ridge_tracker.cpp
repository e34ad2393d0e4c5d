#include "model/signal/speed_ridge_tracker.hpp"

#include <algorithm>
#include <cmath>

#include "model/signal/spectral_floor.hpp"

namespace amb::model::signal {
namespace {
constexpr double k_nan = std::numeric_limits<double>::quiet_NaN();
constexpr double k_excluded = -1e9;  // score of a candidate outside the search band
// Lines weaker than this (dB above floor) do not take part in the sub-bin refinement:
// their -6 dB crossings would be noise crossings.
constexpr double k_refine_min_db = 6.0;
std::string range_msg(const char* field, const std::string& range, double got) {
  return std::string(field) + " must be in " + range + ", got " + std::to_string(got);
}
}  // namespace

std::string SpeedTrackerOptions::validate() const {
  if (std::string err = stft.validate(); !err.empty()) return "stft." + err;
  if (n_orders < 1 || n_orders > k_max_orders)
    return range_msg("n_orders", "[1, " + std::to_string(k_max_orders) + "]",
                     static_cast<double>(n_orders));
  double o_max = 0.0;
  for (size_t k = 0; k < n_orders; ++k) {
    if (!(orders[k] > 0.0 && orders[k] <= 100.0))
      return range_msg(("orders[" + std::to_string(k) + "]").c_str(), "(0, 100]", orders[k]);
    if (!(order_weights[k] > 0.0 && order_weights[k] <= 1e3))
      return range_msg(("order_weights[" + std::to_string(k) + "]").c_str(), "(0, 1000]",
                       order_weights[k]);
    o_max = std::max(o_max, orders[k]);
  }
  const double nyquist = 0.5 * stft.sample_rate_hz;
  if (!(max_speed_hz > 0.0 && max_speed_hz * o_max < nyquist))
    return range_msg("max_speed_hz",
                     "(0, fs/2 / largest order) = (0, " + std::to_string(nyquist / o_max) + ") Hz",
                     max_speed_hz);
  if (!(min_speed_hz >= 0.0 && min_speed_hz < max_speed_hz))
    return range_msg("min_speed_hz", "[0, max_speed_hz=" + std::to_string(max_speed_hz) + ") Hz",
                     min_speed_hz);
  if (!(initial_speed_hz == 0.0 ||
        (initial_speed_hz >= min_speed_hz && initial_speed_hz <= max_speed_hz)))
    return range_msg("initial_speed_hz", "0 (unknown) or [min_speed_hz, max_speed_hz] Hz",
                     initial_speed_hz);
  if (!(search_half_band_hz > 0.0 && search_half_band_hz <= 1000.0))
    return range_msg("search_half_band_hz", "(0, 1000] Hz", search_half_band_hz);
  if (!(max_accel_hz_per_s > 0.0 && max_accel_hz_per_s <= 1e5))
    return range_msg("max_accel_hz_per_s", "(0, 1e5] Hz/s", max_accel_hz_per_s);
  if (!(horizon_frames >= 1.0 && horizon_frames <= 1000.0))
    return range_msg("horizon_frames", "[1, 1000]", horizon_frames);
  if (!(jump_penalty_db >= 0.0 && jump_penalty_db <= 100.0))
    return range_msg("jump_penalty_db", "[0, 100] dB", jump_penalty_db);
  if (!(half_order_penalty >= 0.0 && half_order_penalty <= 1.0))
    return range_msg("half_order_penalty", "[0, 1]", half_order_penalty);
  if (!(line_cap_db >= 3.0 && line_cap_db <= 100.0))
    return range_msg("line_cap_db", "[3, 100] dB", line_cap_db);
  if (!(presence_lo_db >= 0.0 && presence_lo_db < 50.0))
    return range_msg("presence_lo_db", "[0, 50) dB", presence_lo_db);
  if (!(presence_hi_db > presence_lo_db && presence_hi_db <= 60.0))
    return range_msg("presence_hi_db", "(presence_lo_db, 60] dB", presence_hi_db);
  if (!(lost_confidence >= 0.0 && lost_confidence < 1.0))
    return range_msg("lost_confidence", "[0, 1)", lost_confidence);
  if (lost_after_frames < 1 || lost_after_frames > 1000)
    return range_msg("lost_after_frames", "[1, 1000]", static_cast<double>(lost_after_frames));
  if (!(acquire_confidence >= lost_confidence && acquire_confidence <= 1.0))
    return range_msg("acquire_confidence", "[lost_confidence, 1]", acquire_confidence);
  if (acquire_frames < 1 || acquire_frames > 100)
    return range_msg("acquire_frames", "[1, 100]", static_cast<double>(acquire_frames));
  if (!(rate_step_hz_per_s > 0.0 && rate_step_hz_per_s <= max_accel_hz_per_s))
    return range_msg("rate_step_hz_per_s", "(0, max_accel_hz_per_s] Hz/s", rate_step_hz_per_s);
  if (!(multiple_margin_db >= 0.0 && multiple_margin_db <= 50.0))
    return range_msg("multiple_margin_db", "[0, 50] dB", multiple_margin_db);
  if (floor_block_bins < 8 || floor_block_bins > 4096)
    return range_msg("floor_block_bins", "[8, 4096]", static_cast<double>(floor_block_bins));
  return {};
}

std::string SpeedRidgeTracker::configure(const SpeedTrackerOptions& options) {
  mode_ = TrackMode::kUnconfigured;
  if (std::string err = options.validate(); !err.empty()) return err;
  if (std::string err = stft_.configure(options.stft); !err.empty()) return "stft." + err;
  options_ = options;
  const StftOptions& so = options.stft;
  bin_hz_ = stft_.bin_hz();
  hop_s_ = static_cast<double>(so.hop_samples()) / so.sample_rate_hz;
  const double window_s = static_cast<double>(so.window_samples()) / so.sample_rate_hz;
  const double lobe_hz = main_lobe_half_width_bins(so.window) / window_s;
  lobe_hz_ = lobe_hz;
  // The lowest comb line must sit two main-lobe half-widths above DC, or it merges with
  // the demeaning residue.
  double o_min = options.orders[0];
  for (size_t k = 0; k < options.n_orders; ++k) o_min = std::min(o_min, options.orders[k]);
  stated_min_hz_ = std::max(options.min_speed_hz, 2.0 * lobe_hz / o_min);
  if (stated_min_hz_ >= options.max_speed_hz)
    return "min_speed_hz: the resolvable minimum " + std::to_string(stated_min_hz_) +
           " Hz (2 main-lobe half-widths of a " + std::to_string(window_s) +
           " s window) must be below max_speed_hz " + std::to_string(options.max_speed_hz);
  // Candidate spacing: a quarter of the main-lobe half-width is enough for the comb; the
  // precision comes from the refinement.
  grid_hz_ = std::max(bin_hz_, 0.25 * lobe_hz);
  grid_lo_hz_ = stated_min_hz_;
  const size_t n_cand =
      static_cast<size_t>(std::floor((options.max_speed_hz - grid_lo_hz_) / grid_hz_)) + 1;
  max_jump_ = static_cast<size_t>(std::ceil(options.max_accel_hz_per_s * hop_s_ / grid_hz_)) + 1;
  double o_max = 0.0;
  for (size_t k = 0; k < options.n_orders; ++k) o_max = std::max(o_max, options.orders[k]);
  const double smear_hz = options.max_accel_hz_per_s * window_s;  // chirp sweep per window
  const double f_reach = o_max * (options.max_speed_hz + grid_hz_ + smear_hz) + 4.0 * lobe_hz;
  // A floor block must be much wider than a line's main lobe, or the line lifts its own
  // floor: at least 16 main-lobe half-widths.
  floor_block_ = std::max(options.floor_block_bins,
                          static_cast<size_t>(std::ceil(16.0 * lobe_hz / bin_hz_)));
  n_bins_used_ = std::min(so.nfft / 2 + 1,
                          static_cast<size_t>(std::ceil(f_reach / bin_hz_)) + floor_block_);
  level_db_.assign(n_bins_used_, 0.0);
  floor_db_.assign(n_bins_used_, 0.0);
  prom_db_.assign(n_bins_used_, 0.0);
  scratch_.assign(floor_block_, 0.0);
  medians_.assign((n_bins_used_ + floor_block_ - 1) / floor_block_, 0.0);
  score_.assign(n_cand, 0.0);
  best_score_.assign(n_cand, 0.0);
  best_level_db_.assign(n_bins_used_, 0.0);
  best_prom_db_.assign(n_bins_used_, 0.0);
  delta_.assign(n_cand, 0.0);
  delta_next_.assign(n_cand, 0.0);
  reset();
  return {};
}

void SpeedRidgeTracker::reset() {
  stft_.reset();
  std::fill(delta_.begin(), delta_.end(), 0.0);
  hist_n_ = 0;
  weak_count_ = 0;
  acquire_count_ = 0;
  track_hz_ = 0.0;
  track_t_s_ = 0.0;
  have_prior_ = options_.initial_speed_hz > 0.0;
  latest_ = SpeedEstimate{};
  updates_ = lost_updates_ = acquisitions_ = losses_ = relocks_ = 0;
  multiple_count_ = 0;
  multiple_ratio_ = 1.0;
  mode_ = TrackMode::kAcquiring;
}

SpeedTrackerSummary SpeedRidgeTracker::summary() const {
  SpeedTrackerSummary s;
  s.mode = mode_;
  s.updates = updates_;
  s.lost_updates = lost_updates_;
  s.acquisitions = acquisitions_;
  s.losses = losses_;
  s.relocks = relocks_;
  s.stated_min_speed_hz = stated_min_hz_;
  s.update_rate_hz = hop_s_ > 0.0 ? 1.0 / hop_s_ : 0.0;
  s.latency_s = 0.5 * options_.stft.window_s;
  s.bin_hz = bin_hz_;
  s.candidates = score_.size();
  s.last = latest_;
  return s;
}

bool SpeedRidgeTracker::push(double x) {
  if (mode_ == TrackMode::kUnconfigured) return false;
  if (!stft_.push(x)) return false;
  process_frame();
  return true;
}

double SpeedRidgeTracker::line_prominence(double f_hz, double half_width_hz) const {
  const double lo = (f_hz - half_width_hz) / bin_hz_;
  const double hi = (f_hz + half_width_hz) / bin_hz_;
  if (hi < 1.0) return 0.0;
  const size_t b0 = static_cast<size_t>(std::max(1.0, std::floor(lo)));
  const size_t b1 = std::min(n_bins_used_ - 1, static_cast<size_t>(std::ceil(hi)));
  double best = 0.0;
  for (size_t b = b0; b <= b1; ++b) best = std::max(best, prom_db_[b]);
  return best;
}

double SpeedRidgeTracker::comb_height_db(double f) const {
  // Each tooth's line is looked for within a main-lobe half-width of it: the best candidate
  // of a clean line can sit anywhere on the capped top of its main lobe.
  const SpeedTrackerOptions& o = options_;
  double s = 0.0, w_sum = 0.0;
  for (size_t k = 0; k < o.n_orders; ++k) {
    const double ok = o.orders[k];
    const double hw = 0.5 * ok * grid_hz_ + lobe_hz_;
    const double lo = (ok * f - hw) / bin_hz_;
    const double hi = (ok * f + hw) / bin_hz_;
    w_sum += o.order_weights[k];
    if (hi < 1.0) continue;
    const size_t b0 = static_cast<size_t>(std::max(1.0, std::floor(lo)));
    const size_t b1 = std::min(n_bins_used_ - 1, static_cast<size_t>(std::ceil(hi)));
    double best = 0.0;
    for (size_t b = b0; b <= b1; ++b) best = std::max(best, level_db_[b] - floor_db_[b]);
    s += o.order_weights[k] * best;
  }
  return w_sum > 0.0 ? s / w_sum : 0.0;
}

double SpeedRidgeTracker::comb_score(double f) const {
  const SpeedTrackerOptions& o = options_;
  double s = 0.0, w_sum = 0.0;
  for (size_t k = 0; k < o.n_orders; ++k) {
    const double ok = o.orders[k];
    w_sum += o.order_weights[k];
    s += o.order_weights[k] * line_prominence(ok * f, 0.5 * ok * grid_hz_ + 0.5 * bin_hz_);
  }
  // Anti-comb: a candidate at m times the true speed (m = 2, 3, ...) sees its teeth on every
  // m-th true line and finds the other true lines between its teeth, at fractional orders
  // (k + 1/3, k + 1/2, k + 2/3) o_1. The true speed has (normally) nothing there. Each gap
  // below tooth k costs its strongest fractional line, weighted like the tooth.
  if (o.half_order_penalty > 0.0) {
    static constexpr std::array<double, 3> k_fractions{1.0 / 3.0, 0.5, 2.0 / 3.0};
    for (size_t k = 0; k < o.n_orders; ++k) {
      double worst = 0.0;
      for (double fr : k_fractions) {
        const double oh = (static_cast<double>(k) + fr) * o.orders[0];
        worst = std::max(worst, line_prominence(oh * f, 0.5 * oh * grid_hz_ + 0.5 * bin_hz_));
      }
      s -= o.half_order_penalty * o.order_weights[k] * worst;
    }
  }
  return s / w_sum;
}

void SpeedRidgeTracker::score_candidates(bool narrow, double centre_hz, double half_band_hz) {
  for (size_t c = 0; c < score_.size(); ++c) {
    const double f = grid_lo_hz_ + grid_hz_ * static_cast<double>(c);
    score_[c] = narrow && std::abs(f - centre_hz) > half_band_hz ? k_excluded : comb_score(f);
  }
}

size_t SpeedRidgeTracker::peak_bin(double f_hz, double half_width_hz) const {
  const double lo = (f_hz - half_width_hz) / bin_hz_;
  const double hi = (f_hz + half_width_hz) / bin_hz_;
  if (hi < 1.0 || lo > static_cast<double>(n_bins_used_ - 2)) return 0;
  const size_t b0 = static_cast<size_t>(std::max(1.0, std::floor(lo)));
  const size_t b1 = std::min(n_bins_used_ - 2, static_cast<size_t>(std::ceil(hi)));
  size_t b = b0;
  for (size_t i = b0; i <= b1; ++i)
    if (level_db_[i] > level_db_[b]) b = i;
  return b;
}

bool SpeedRidgeTracker::refine(double f_candidate_hz, double& f_hz, double& prominence_db,
                               double& confidence) const {
  const SpeedTrackerOptions& o = options_;
  const StftOptions& so = o.stft;
  const double window_s = static_cast<double>(so.window_samples()) / so.sample_rate_hz;
  const double lobe_bins = main_lobe_half_width_bins(so.window) / window_s / bin_hz_;
  const double smear_bins = o.max_accel_hz_per_s * window_s / bin_hz_;
  double w_sum = 0.0, conf = 0.0, prom = 0.0, f_acc = 0.0, f_w = 0.0;
  for (size_t k = 0; k < o.n_orders; ++k) {
    const double ok = o.orders[k];
    const double wk = o.order_weights[k];
    w_sum += wk;
    // Strongest bin near the expected line, then uphill to the top of its bump (a chirp
    // smears the line over up to ok * smear_bins bins).
    size_t b = peak_bin(ok * f_candidate_hz, 0.5 * ok * grid_hz_ + 1.5 * bin_hz_);
    if (b == 0) continue;
    const size_t climb = static_cast<size_t>(lobe_bins + ok * smear_bins) + 1;
    for (size_t s = 0; s < climb; ++s) {
      if (b + 2 < n_bins_used_ && level_db_[b + 1] > level_db_[b]) {
        ++b;
      } else if (b > 1 && level_db_[b - 1] > level_db_[b]) {
        --b;
      } else {
        break;
      }
    }
    const double p = prom_db_[b];
    prom += wk * p;
    conf += wk * std::clamp((p - o.presence_lo_db) / (o.presence_hi_db - o.presence_lo_db), 0.0,
                            1.0);
    if (p < k_refine_min_db) continue;
    // Midpoint of the -6 dB crossings: exact for a symmetric main lobe and for the
    // window-shaped bump of a linear chirp (whose centre is the speed at the window centre).
    const double drop = level_db_[b] - 6.0;
    const size_t walk = static_cast<size_t>(3.0 * lobe_bins + ok * smear_bins) + 2;
    size_t l = b;
    while (l > 1 && b - l < walk && level_db_[l - 1] > drop) --l;
    size_t r = b;
    while (r + 2 < n_bins_used_ && r - b < walk && level_db_[r + 1] > drop) ++r;
    if (level_db_[l - 1] > drop || level_db_[r + 1] > drop) continue;  // no clean crossing
    const double xl = static_cast<double>(l) -
                      (level_db_[l] - drop) / (level_db_[l] - level_db_[l - 1]);
    const double xr = static_cast<double>(r) +
                      (level_db_[r] - drop) / (level_db_[r] - level_db_[r + 1]);
    const double f_line = 0.5 * (xl + xr) * bin_hz_ / ok;
    if (std::abs(f_line - f_candidate_hz) > 2.0 * grid_hz_ + smear_bins * bin_hz_) continue;
    // Frequency variance of a line ~ 1/SNR; divided by the order for the shaft speed.
    const double weight = ok * ok * std::pow(10.0, 0.1 * std::min(p, o.line_cap_db));
    f_acc += weight * f_line;
    f_w += weight;
  }
  prominence_db = w_sum > 0.0 ? prom / w_sum : 0.0;
  confidence = w_sum > 0.0 ? conf / w_sum : 0.0;
  f_hz = f_w > 0.0 ? f_acc / f_w : f_candidate_hz;
  return f_w > 0.0;
}

double SpeedRidgeTracker::estimate_rate() const {
  if (hist_n_ < 2) return 0.0;
  const size_t n = std::min(hist_n_, k_history);
  double mt = 0.0, mf = 0.0;
  for (size_t i = 0; i < n; ++i) {
    mt += hist_t_s_[i];
    mf += hist_f_hz_[i];
  }
  mt /= static_cast<double>(n);
  mf /= static_cast<double>(n);
  double stt = 0.0, stf = 0.0;
  for (size_t i = 0; i < n; ++i) {
    stt += (hist_t_s_[i] - mt) * (hist_t_s_[i] - mt);
    stf += (hist_t_s_[i] - mt) * (hist_f_hz_[i] - mf);
  }
  if (stt <= 0.0) return 0.0;
  return std::clamp(stf / stt, -options_.max_accel_hz_per_s, options_.max_accel_hz_per_s);
}

void SpeedRidgeTracker::enter_search(TrackMode mode) {
  mode_ = mode;
  std::fill(delta_.begin(), delta_.end(), 0.0);
  hist_n_ = 0;
  weak_count_ = 0;
  acquire_count_ = 0;
}

void SpeedRidgeTracker::analyse_spectrum() {
  const SpeedTrackerOptions& o = options_;
  const std::span<const double> power = stft_.power();
  for (size_t k = 0; k < n_bins_used_; ++k) level_db_[k] = 10.0 * std::log10(power[k] + 1e-300);
  block_median_floor(level_db_, floor_block_, scratch_, medians_, floor_db_);
  for (size_t k = 0; k < n_bins_used_; ++k)
    prom_db_[k] = std::clamp(level_db_[k] - floor_db_[k], 0.0, o.line_cap_db);
}

void SpeedRidgeTracker::process_frame() {
  const SpeedTrackerOptions& o = options_;
  const double t_s = stft_.frame_centre_s();

  // Where to search: eq. 15 narrow band around the prediction, or wide.
  // Slope: the chirp rate that won the previous frame while tracking (reacts within one
  // hop at the start and end of a ramp), else the slope of the recent estimates.
  const double rate = mode_ == TrackMode::kTracking && o.order_tracking
                          ? std::clamp(stft_.warp_rate() * track_hz_, -o.max_accel_hz_per_s,
                                       o.max_accel_hz_per_s)
                          : estimate_rate();
  bool narrow = false;
  double f0 = 0.0;
  if (mode_ == TrackMode::kTracking) {
    narrow = true;
    f0 = track_hz_ + rate * (t_s - track_t_s_);
  } else if (have_prior_) {
    narrow = true;
    f0 = o.initial_speed_hz;
  }
  const double half_band = std::min(o.search_half_band_hz, f0 / 3.0);

  // Chirp-rate hypotheses for the frame warp: the predicted rate, one and two steps either
  // side and no warp while tracking (catches the start and end of ramps at once); none, a moderate
  // acceleration and a moderate deceleration while searching. The hypothesis whose best
  // comb candidate scores highest wins the frame (its lines are the sharpest).
  std::array<double, k_max_kappas> kappas{};
  size_t n_kappa = 1;
  if (o.order_tracking) {
    if (mode_ == TrackMode::kTracking && f0 > stated_min_hz_) {
      const double dk = o.rate_step_hz_per_s / f0;
      const double k0 = stft_.warp_rate();
      kappas = {k0, k0 - dk, k0 + dk, k0 - 2.0 * dk, k0 + 2.0 * dk, 0.0, 0.0};
      n_kappa = 5;
      // Steady speed is always a hypothesis: the steps around k0 need not land on 0, and a
      // warp left over from a ramp biases a steady line (the window's centre in warped time
      // is not its centre in time).
      if (k0 != 0.0) n_kappa = 6;
    } else {
      // Relative rates (1/s) of typical run-ups and run-downs, up to the warp limit.
      const double t = o.stft.window_s;
      kappas = {0.0, -0.25 / t, 0.25 / t, -0.6 / t, 0.6 / t, -1.2 / t, 1.2 / t};
      n_kappa = 7;
    }
  }
  // The hypothesis that focuses the lines best wins: the highest uncapped line height above
  // the floor at its best comb candidate. (Not the capped comb score: a clean line stands
  // above line_cap_db in every hypothesis, and a line smeared by a wrong warp is a wide
  // plateau of capped candidates among which one always finds noise-free anti-comb gaps, so
  // a warp kept after the end of a ramp won every frame and read a steady line far off.)
  double best_kappa_height = -std::numeric_limits<double>::infinity();
  double kappa_used = kappas[0];
  for (size_t i = 0; i < n_kappa; ++i) {
    if (i > 0 || stft_.warp_rate() != kappas[0]) stft_.recompute(kappas[i]);
    analyse_spectrum();
    score_candidates(narrow, f0, half_band);
    const auto top_it = std::max_element(score_.begin(), score_.end());
    const double f_top = grid_lo_hz_ + grid_hz_ * static_cast<double>(top_it - score_.begin());
    const double height = comb_height_db(f_top);
    if (height > best_kappa_height) {
      best_kappa_height = height;
      kappa_used = kappas[i];
      // Keep this hypothesis' spectrum and scores (swaps storage, no allocation).
      level_db_.swap(best_level_db_);
      prom_db_.swap(best_prom_db_);
      score_.swap(best_score_);
    }
  }
  level_db_.swap(best_level_db_);
  prom_db_.swap(best_prom_db_);
  score_.swap(best_score_);
  stft_.set_warp_rate(kappa_used);

  // Forward Viterbi step with exponential memory and a quadratic, gated jump penalty.
  const double alpha = 1.0 - 1.0 / o.horizon_frames;
  const auto n = static_cast<std::ptrdiff_t>(score_.size());
  const auto jmax = static_cast<std::ptrdiff_t>(max_jump_);
  const double pen_scale = o.jump_penalty_db / static_cast<double>(max_jump_ * max_jump_);
  // While tracking, the jump is penalised relative to the drift the slope predicts
  // (constant-acceleration motion is free), so the ridge does not lag on ramps.
  const double drift = mode_ == TrackMode::kTracking ? rate * hop_s_ / grid_hz_ : 0.0;
  const auto drift_c = static_cast<std::ptrdiff_t>(std::lround(drift));
  double best = -std::numeric_limits<double>::infinity();
  std::ptrdiff_t c_best = 0;
  for (std::ptrdiff_t c = 0; c < n; ++c) {
    double prev = -std::numeric_limits<double>::infinity();
    // Previous state p = c + j moved by -j; allowed when |-j - drift| <= jmax.
    const std::ptrdiff_t j0 = std::max<std::ptrdiff_t>(-jmax - drift_c, -c);
    const std::ptrdiff_t j1 = std::min<std::ptrdiff_t>(jmax - drift_c, n - 1 - c);
    for (std::ptrdiff_t j = j0; j <= j1; ++j) {
      const double dev = static_cast<double>(j) + drift;
      const double v = alpha * delta_[static_cast<size_t>(c + j)] - pen_scale * dev * dev;
      prev = std::max(prev, v);
    }
    const double d = score_[static_cast<size_t>(c)] + prev;
    delta_next_[static_cast<size_t>(c)] = d;
    if (d > best) {
      best = d;
      c_best = c;
    }
  }
  // Keep the accumulated scores bounded (only differences matter).
  for (std::ptrdiff_t c = 0; c < n; ++c)
    delta_[static_cast<size_t>(c)] = std::max(delta_next_[static_cast<size_t>(c)] - best, k_excluded);

  const double f_cand = grid_lo_hz_ + grid_hz_ * static_cast<double>(c_best);
  double f_hat = f_cand, prom = 0.0, conf = 0.0;
  refine(f_cand, f_hat, prom, conf);

  SpeedEstimate e;
  e.t_s = t_s;
  e.frame = stft_.frames();
  e.confidence = conf;
  e.prominence_db = prom;
  e.rate_hz_per_s = rate;
  e.warp_rate_per_s = kappa_used;
  auto accept = [&](double f) {
    track_hz_ = f;
    track_t_s_ = t_s;
    const size_t slot = hist_n_ % k_history;
    hist_t_s_[slot] = t_s;
    hist_f_hz_[slot] = f;
    ++hist_n_;
    e.speed_hz = f;
    e.lost = false;
  };

  if (mode_ == TrackMode::kTracking) {
    if (f_hat < stated_min_hz_ || f0 < stated_min_hz_) {
      ++losses_;
      enter_search(TrackMode::kBelowMin);
      e.below_min = true;
    } else if (conf < o.lost_confidence) {
      if (++weak_count_ >= o.lost_after_frames) {
        ++losses_;
        enter_search(TrackMode::kAcquiring);
      } else {
        // Coast on the prediction for a few weak frames; the confidence says so.
        e.speed_hz = f0;
        e.lost = false;
        track_hz_ = f0;
        track_t_s_ = t_s;
      }
    } else {
      weak_count_ = 0;
      // Multiple check: the narrow band cannot leave a lock on 2x/3x (or 1/2, 1/3) of the
      // true speed, e.g. taken at a low speed where the lower lines were still buried.
      // If a multiple explains the spectrum clearly better for a few frames, move there.
      static constexpr std::array<double, 4> k_ratios{1.0 / 3.0, 0.5, 2.0, 3.0};
      const double own = comb_score(f_hat);
      double best_ratio = 1.0, best_alt = own + o.multiple_margin_db;
      for (double ratio : k_ratios) {
        const double fa = ratio * f_hat;
        if (fa < stated_min_hz_ || fa > o.max_speed_hz) continue;
        const double sa = comb_score(fa);
        if (sa > best_alt) {
          best_alt = sa;
          best_ratio = ratio;
        }
      }
      if (best_ratio != 1.0 && best_ratio == multiple_ratio_) {
        ++multiple_count_;
      } else {
        multiple_count_ = best_ratio != 1.0 ? 1 : 0;
      }
      multiple_ratio_ = best_ratio;
      if (multiple_count_ >= 2 * o.acquire_frames) {
        double f_new = f_hat * best_ratio, p2 = 0.0, c2 = 0.0;
        refine(f_new, f_new, p2, c2);
        for (size_t i = 0; i < k_history; ++i) hist_f_hz_[i] *= best_ratio;
        std::fill(delta_.begin(), delta_.end(), 0.0);
        multiple_count_ = 0;
        multiple_ratio_ = 1.0;
        ++relocks_;
        f_hat = f_new;
        e.confidence = c2;
        e.prominence_db = p2;
      }
      accept(f_hat);
    }
  } else {
    const double step_hz = o.max_accel_hz_per_s * hop_s_ + 2.0 * grid_hz_;
    const bool good = conf >= o.acquire_confidence && f_hat >= stated_min_hz_;
    if (good && acquire_count_ > 0 && std::abs(f_hat - acquire_last_hz_) <= step_hz) {
      ++acquire_count_;
    } else {
      acquire_count_ = good ? 1 : 0;
    }
    acquire_last_hz_ = f_hat;
    if (good) {
      // Keep the acquisition frames in the slope history.
      const size_t slot = hist_n_ % k_history;
      hist_t_s_[slot] = t_s;
      hist_f_hz_[slot] = f_hat;
      ++hist_n_;
    } else {
      hist_n_ = 0;
    }
    if (acquire_count_ >= o.acquire_frames) {
      mode_ = TrackMode::kTracking;
      have_prior_ = false;
      weak_count_ = 0;
      ++acquisitions_;
      --hist_n_;  // accept() re-adds this frame
      accept(f_hat);
    } else {
      e.below_min = mode_ == TrackMode::kBelowMin;
    }
  }
  // Warp of the next frame: the winning chirp rate of this one while tracking; none while
  // searching.
  if (mode_ == TrackMode::kTracking && o.order_tracking) {
    const double r = kappa_used * track_hz_;
    const double f_next = track_hz_ + r * hop_s_;
    stft_.set_warp_rate(f_next > stated_min_hz_ ? r / f_next : 0.0);
  } else {
    stft_.set_warp_rate(0.0);
  }
  if (e.lost) {
    e.speed_hz = k_nan;
    ++lost_updates_;
  }
  ++updates_;
  latest_ = e;
}

size_t SpeedRidgeTracker::heap_bytes() const {
  size_t doubles = 0;
  for (const std::vector<double>* v : {&level_db_, &floor_db_, &prom_db_, &scratch_, &medians_, &score_, &best_score_,
                                       &best_level_db_, &best_prom_db_, &delta_, &delta_next_})
    doubles += v->capacity();
  return stft_.heap_bytes() + sizeof(double) * doubles;
}

}  // namespace amb::model::signal
