#pragma once
// Tachless shaft-speed tracker: the energy ridge of a streaming STFT (seed 003 sec. 4.3),
// made robust for on-board use:
//  - order comb: a candidate shaft speed f is scored by the prominence (dB above a robust
//    local noise floor) of the lines expected at orders o_k * f, with weights decreasing
//    with order and an anti-comb penalty for lines between the teeth (what a 2x or 3x error
//    would leave unexplained), so the tracker does not lock onto a harmonic or a bearing
//    line; while tracking, a multiple check moves a wrong lock to 1/3, 1/2, 2x or 3x;
//  - continuity: a forward Viterbi recursion over the candidate grid with a quadratic
//    jump penalty, gated by the largest plausible acceleration, and an exponential memory
//    of `horizon_frames` frames (a penalised ridge in the spirit of MATLAB tfridge);
//  - narrow-band search (seed 003 eq. 15) around the predicted speed while tracking, a
//    wide search over [min_speed_hz, max_speed_hz] while acquiring or after a loss;
//  - sub-bin refinement of every supporting line by the midpoint of its -6 dB crossings,
//    combined across orders with inverse-variance weights (order^2 * line SNR).
// Everything is sized in configure(); push() never allocates and runs in bounded time.
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "model/signal/streaming_stft.hpp"

namespace amb::model::signal {

/// Largest number of orders in the comb.
inline constexpr size_t k_max_orders = 8;
/// Largest number of chirp-rate hypotheses tried per frame (bounds the cost per hop).
inline constexpr size_t k_max_kappas = 7;

/// Settings of the speed tracker.
struct SpeedTrackerOptions {
  StftOptions stft{};                 ///< STFT (defaults: seed 003, Hamming 0.5 s, 90 %, 8192)
  /// Lowest speed the tracker reports, Hz; below it the update is flagged `below_min` and
  /// carries no speed. Raised internally to the resolvable limit
  /// 2 * main-lobe half width / (window_s * smallest order) (see stated_min_speed_hz()).
  /// [0, max_speed_hz)
  double min_speed_hz = 8.0;
  /// Highest shaft speed searched, Hz; (min_speed_hz, fs / (2 * largest order)).
  double max_speed_hz = 300.0;
  /// Predicted shaft speed at start (seed 003 eq. 15 f0), Hz; 0: unknown, wide search.
  /// If set, the first lock is searched within +/- search_half_band_hz of it.
  double initial_speed_hz = 0.0;
  /// Half-width of the narrow-band search around the predicted speed (seed 003 eq. 15
  /// Delta f), Hz; (0, 1000]. Internally limited to a third of the predicted speed so the
  /// band can never contain the half or the double of the tracked speed.
  double search_half_band_hz = 10.0;
  /// Largest |d speed / dt| the ridge may follow, Hz/s; (0, 1e5]. Gates the Viterbi jumps.
  double max_accel_hz_per_s = 150.0;
  /// Memory of the Viterbi recursion, frames; [1, 1000]. Scores of older frames decay as
  /// (1 - 1/horizon_frames)^age.
  double horizon_frames = 6.0;
  /// Score penalty for a jump of the largest allowed size between frames, dB; [0, 100].
  /// Quadratic in the jump.
  double jump_penalty_db = 6.0;
  /// Orders (multiples of shaft speed) of the lines the comb expects; first n_orders used.
  /// Default 1x..4x. Non-integer orders (bearing lines, e.g. BPFO/shaft) are allowed.
  std::array<double, k_max_orders> orders{1.0, 2.0, 3.0, 4.0, 0, 0, 0, 0};
  /// Weight of each order in score and confidence; > 0. Decreasing weights make the
  /// fundamental win over its own subharmonic.
  std::array<double, k_max_orders> order_weights{1.0, 0.7, 0.5, 0.35, 0, 0, 0, 0};
  size_t n_orders = 4;                ///< number of orders used; [1, k_max_orders]
  /// Weight of the anti-comb penalty: lines between the comb teeth, at (k + 1/3, 1/2, 2/3)
  /// times the first order, which a candidate at 2x or 3x the true speed would leave
  /// unexplained; [0, 1].
  double half_order_penalty = 0.5;
  /// A line's prominence is clamped to this value, dB, so that one strong line cannot
  /// outvote several harmonics; [3, 100].
  double line_cap_db = 25.0;
  /// Prominence at which a line starts to count as present (confidence 0), dB; [0, 50).
  /// Default 6 dB: the strongest of a few hundred noise-only bins sits about 6-8 dB above
  /// the median floor (exponential power statistics), so noise alone scores near 0.
  double presence_lo_db = 6.0;
  /// Prominence at which a line counts as fully present (confidence 1), dB; (lo, 60].
  double presence_hi_db = 18.0;
  /// Updates with confidence below this are weak; [0, 1).
  double lost_confidence = 0.15;
  /// Consecutive weak updates after which the track is declared lost; [1, 1000].
  size_t lost_after_frames = 4;
  /// Confidence needed to (re)acquire a lock; [lost_confidence, 1].
  double acquire_confidence = 0.3;
  /// Consecutive confident, mutually consistent updates needed to (re)acquire; [1, 100].
  size_t acquire_frames = 2;
  /// While tracking, warp each frame along the predicted speed ramp (computed order
  /// tracking, see StreamingStft::set_warp_rate) so lines of an accelerating shaft stay
  /// narrow. false: plain STFT as in seed 003.
  bool order_tracking = true;
  /// Step between the chirp-rate hypotheses tried around the predicted rate while tracking,
  /// Hz/s; (0, max_accel_hz_per_s].
  double rate_step_hz_per_s = 30.0;
  /// While tracking, the track moves to 1/3, 1/2, 2 or 3 times itself when that speed's comb
  /// score beats the track's by this margin for acquire_frames consecutive updates, dB;
  /// [0, 50].
  double multiple_margin_db = 3.0;
  /// Width of the noise-floor median blocks, bins; [8, 4096]. Raised internally to 16
  /// main-lobe half-widths so a line never lifts its own floor.
  size_t floor_block_bins = 64;

  /// Empty if valid; otherwise a message naming the bad field and its allowed range.
  std::string validate() const;
};

/// Tracker mode.
enum class TrackMode : uint8_t {
  kUnconfigured,
  kAcquiring,   ///< wide search, no lock yet (or after a loss)
  kTracking,    ///< locked; narrow-band search around the prediction
  kBelowMin,    ///< last track went below the stated minimum speed; wide search for re-acquisition
};

/// One tracker update (one STFT frame).
struct SpeedEstimate {
  double t_s = 0.0;           ///< centre of the analysed window, s since the first sample
  /// Shaft speed, Hz (= rev/s); NaN when lost or below the minimum (no guess is made).
  double speed_hz = std::numeric_limits<double>::quiet_NaN();
  /// Ridge confidence in [0, 1]: the weighted fraction of the expected comb lines that
  /// stand above the local noise floor, each line counted by
  /// clamp((prominence_db - presence_lo_db)/(presence_hi_db - presence_lo_db), 0, 1).
  double confidence = 0.0;
  double prominence_db = 0.0;  ///< weighted mean line prominence of the ridge, dB
  double rate_hz_per_s = 0.0;  ///< ridge slope (recent estimates), Hz/s
  double warp_rate_per_s = 0.0;  ///< relative chirp rate the frame was warped with, 1/s
  bool lost = true;            ///< true: no valid speed this update (acquiring, lost or below min)
  bool below_min = false;      ///< true: the track fell below stated_min_speed_hz()
  uint64_t frame = 0;          ///< frame counter since configure/reset
};

/// Running summary of the tracker.
struct SpeedTrackerSummary {
  TrackMode mode = TrackMode::kUnconfigured;
  uint64_t updates = 0;          ///< number of updates produced
  uint64_t lost_updates = 0;     ///< updates with lost == true
  uint64_t acquisitions = 0;     ///< number of times a lock was (re)acquired
  uint64_t losses = 0;           ///< number of times a lock was lost (incl. going below min)
  uint64_t relocks = 0;          ///< times the track moved to a multiple (1/3, 1/2, 2, 3) of itself
  double stated_min_speed_hz = 0.0;  ///< lowest speed reported, Hz
  double update_rate_hz = 0.0;   ///< updates per second of signal, Hz
  double latency_s = 0.0;        ///< delay from the window centre to the update, s (T/2)
  double bin_hz = 0.0;           ///< STFT bin spacing, Hz
  size_t candidates = 0;         ///< size of the shaft-speed candidate grid
  SpeedEstimate last{};          ///< newest update
};

/// Streaming speed tracker over one channel. Not copyable; configure() allocates, push()
/// does not.
class SpeedRidgeTracker {
 public:
  SpeedRidgeTracker() = default;
  SpeedRidgeTracker(const SpeedRidgeTracker&) = delete;
  SpeedRidgeTracker& operator=(const SpeedRidgeTracker&) = delete;

  /// Validate and allocate. Returns empty on success, else the validation message.
  std::string configure(const SpeedTrackerOptions& options);
  /// Forget the signal history and any lock (keeps allocation).
  void reset();

  /// Push one sample (any unit: g, m/s^2, m). Returns true if an update was produced;
  /// latest() holds it. Bounded time (one STFT frame + comb + Viterbi per hop), no allocation.
  bool push(double x);
  /// Push a block; calls on_update(const SpeedEstimate&) for each update produced.
  template <class OnUpdate>
  void push_block(std::span<const double> x, OnUpdate&& on_update) {
    for (double v : x)
      if (push(v)) on_update(latest_);
  }

  const SpeedEstimate& latest() const { return latest_; }
  SpeedTrackerSummary summary() const;
  const SpeedTrackerOptions& options() const { return options_; }
  /// Lowest speed the tracker will report, Hz:
  /// max(min_speed_hz, 2 * main-lobe half-width / (window_s * smallest order)).
  double stated_min_speed_hz() const { return stated_min_hz_; }
  /// Heap bytes held after configure(): the STFT's buffers and the ridge search's (spectrum
  /// levels, floor, candidate scores, Viterbi state), bytes.
  size_t heap_bytes() const;

 private:
  void process_frame();
  void analyse_spectrum();
  void score_candidates(bool narrow, double centre_hz, double half_band_hz);
  size_t peak_bin(double f_hz, double half_width_hz) const;
  double line_prominence(double f_hz, double half_width_hz) const;
  double comb_score(double f_hz) const;
  /// Weighted mean uncapped height above the floor of the comb lines of f_hz (each the
  /// highest bin within a main-lobe half-width of its tooth), dB.
  double comb_height_db(double f_hz) const;
  bool refine(double f_candidate_hz, double& f_hz, double& prominence_db,
              double& confidence) const;
  double estimate_rate() const;
  void enter_search(TrackMode mode);

  SpeedTrackerOptions options_{};
  StreamingStft stft_{};
  double stated_min_hz_ = 0.0;
  double bin_hz_ = 0.0;
  double lobe_hz_ = 0.0;          // window main-lobe half-width, Hz
  double grid_hz_ = 0.0;          // candidate spacing
  double grid_lo_hz_ = 0.0;       // first candidate
  size_t n_bins_used_ = 0;        // bins of the spectrum the comb can reach
  size_t floor_block_ = 0;        // floor median block, bins
  size_t max_jump_ = 0;           // candidates per hop at max_accel
  double hop_s_ = 0.0;
  std::vector<double> level_db_;  // n_bins_used_
  std::vector<double> floor_db_;  // n_bins_used_
  std::vector<double> prom_db_;   // n_bins_used_, level - floor, clamped to [0, cap]
  std::vector<double> scratch_;   // floor_block_bins
  std::vector<double> medians_;   // blocks
  std::vector<double> score_;     // candidates, this frame
  std::vector<double> best_score_;     // scratch of the chirp-rate hypothesis search
  std::vector<double> best_level_db_;
  std::vector<double> best_prom_db_;
  std::vector<double> delta_;     // candidates, Viterbi accumulated score
  std::vector<double> delta_next_;
  static constexpr size_t k_history = 5;
  std::array<double, k_history> hist_t_s_{};  // recent valid estimates, for the slope
  std::array<double, k_history> hist_f_hz_{};
  size_t hist_n_ = 0;
  TrackMode mode_ = TrackMode::kUnconfigured;
  size_t weak_count_ = 0;
  size_t acquire_count_ = 0;
  double acquire_last_hz_ = 0.0;
  double track_hz_ = 0.0;          // last accepted speed
  double track_t_s_ = 0.0;
  bool have_prior_ = false;        // initial_speed_hz given and not yet used
  SpeedEstimate latest_{};
  uint64_t updates_ = 0;
  uint64_t lost_updates_ = 0;
  uint64_t acquisitions_ = 0;
  uint64_t losses_ = 0;
  uint64_t relocks_ = 0;
  size_t multiple_count_ = 0;
  double multiple_ratio_ = 1.0;
};

}  // namespace amb::model::signal
