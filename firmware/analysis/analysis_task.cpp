#include "firmware/analysis/analysis_task.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "firmware/board/board.hpp"
#include "model/bearing/catalogue.hpp"

namespace amb::fw {

BearingTaskConfig bearing_task_config(const board::BoardConfig& b) {
  BearingTaskConfig c;
  const BearingParams& p = b.bearing;
  if (const auto g = model::bearing::find_bearing(p.monitored)) c.bearing = *g;
  c.radial_clearance_m = p.radial_clearance_m;
  c.min_speed_hz = p.min_speed_hz;
  c.max_speed_hz = p.max_speed_hz;
  c.aux_radial_clearance_m = std::min(b.plant.aux[0].clearance_m, b.plant.aux[1].clearance_m);
  c.aux_contact_constant_n_per_m1p5 = p.aux_contact_constant_n_per_m1p5;
  c.aux_dynamic_load_rating_n = p.aux_dynamic_load_rating_n;
  c.aux_spin_speed_hz = p.aux_spin_speed_hz;
  return c;
}

std::string AnalysisTask::configure(const board::BoardConfig& b, Supervisor* sup) {
  sup_ = sup;
  enabled_ = false;
  channel_ = b.tracker.channel;
  st_ = AnalysisStatus{};
  st_.tracked_speed_hz = std::numeric_limits<double>::quiet_NaN();
  seen_updates_ = 0;
  published_.store(st_);
  if (b.bearing.present && !bearing_.configure(bearing_task_config(b)))
    return "[bearing]: the bearing task refused the configuration (check the monitored bearing and the aux constants)";
  if (!b.tracker.enabled) return {};
  model::signal::SpeedTrackerOptions o = b.tracker.options;
  o.stft.sample_rate_hz = b.rate_hz;
  if (std::string err = tracker_.configure(o, b.tracker.max_gap_samples); !err.empty()) return "[tracker]: " + err;
  enabled_ = true;
  return {};
}

void AnalysisTask::on_sample(const LoopSample& s) {
  if (!enabled_ || !feeding_.load(std::memory_order_relaxed)) return;
  if ((s.flags & flag_read_failed) != 0) return;
  TrackerSample t;
  t.seq = s.seq;
  t.t_ns = s.t_ns;
  t.value = static_cast<double>(s.displacement_m[static_cast<size_t>(channel_)]);
  tracker_.offer(t);  // full: dropped and counted by the ring
}

size_t AnalysisTask::poll() {
  if (!enabled_) return 0;
  const size_t n = tracker_.poll();
  ++st_.polls;
  const SpeedTrackerTaskCounters& c = tracker_.counters();
  st_.samples = c.samples;
  st_.gaps = c.gaps;
  st_.resets = c.resets;
  st_.ring_drops = tracker_.ring_drops();
  const TrackedSpeed t = tracker_.latest();
  if (t.update_seq != seen_updates_) {
    seen_updates_ = t.update_seq;
    const bool lost = t.lost != 0 || !std::isfinite(t.speed_hz);
    st_.update_t_ns = t.t_ns;
    st_.tracked_speed_hz = lost ? std::numeric_limits<double>::quiet_NaN() : t.speed_hz;
    st_.confidence = t.confidence;
    st_.lost = lost ? 1 : 0;
    st_.below_min = t.below_min;
    st_.mode = t.mode;
    st_.tracker_updates = t.update_seq;
    if (sup_) sup_->publish_tracked_speed(t.speed_hz, t.confidence, lost);
    // Defect lines at the tracked speed; none (not the previous ones) while lost.
    st_.defects_valid = 0;
    if (!lost && bearing_.configured()) {
      const DefectUpdate d = bearing_.update_speed(t.speed_hz);
      if (d.valid) {
        st_.defects_valid = 1;
        st_.ftf_hz = d.ftf_hz;
        st_.bpfo_hz = d.bpfo_hz;
        st_.bpfi_hz = d.bpfi_hz;
        st_.bsf_hz = d.bsf_hz;
      }
    }
  }
  published_.store(st_);
  return n;
}

}  // namespace amb::fw
