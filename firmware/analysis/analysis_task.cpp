#include "firmware/analysis/analysis_task.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "firmware/board/board.hpp"
#include "model/bearing/catalogue.hpp"

namespace amb::fw {

RigidRotorProperties rigid_rotor_properties(const model::RotorParams& r) {
  // Beam elements (solid or hollow cylinders, left to right) and rigid disks; first moments
  // for the centre of mass, then transverse inertias about it (parallel axes).
  RigidRotorProperties p;
  double z = 0.0, m = 0.0, mz = 0.0;
  struct Part { double m, z, i_own; };
  std::vector<Part> parts;
  parts.reserve(r.elements.size() + r.disks.size());
  for (const model::BeamElement& e : r.elements) {
    const double ro = 0.5 * e.outer_diameter_m, ri = 0.5 * e.inner_diameter_m, l = e.length_m;
    const double me = e.density_kg_m3 * M_PI * (ro * ro - ri * ri) * l;
    parts.push_back({me, z + 0.5 * l, me * (3.0 * (ro * ro + ri * ri) + l * l) / 12.0});
    z += l;
  }
  for (const model::RigidDisk& d : r.disks) parts.push_back({d.mass_kg, d.axial_m, d.transverse_inertia_kg_m2});
  for (const Part& q : parts) {
    m += q.m;
    mz += q.m * q.z;
  }
  if (!(m > 0)) return p;
  p.mass_kg = m;
  p.cm_axial_m = mz / m;
  for (const Part& q : parts) p.transverse_inertia_kg_m2 += q.i_own + q.m * (q.z - p.cm_axial_m) * (q.z - p.cm_axial_m);
  return p;
}

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
  c.aux_axial_m = {b.plant.aux[0].axial_m, b.plant.aux[1].axial_m};
  const RigidRotorProperties rr = rigid_rotor_properties(b.plant.rotor);
  c.rotor_mass_kg = rr.mass_kg;
  c.rotor_transverse_inertia_kg_m2 = rr.transverse_inertia_kg_m2;
  c.rotor_cm_axial_m = rr.cm_axial_m;
  c.gravity_m_s2 = b.plant.gravity_m_s2;
  return c;
}

std::string AnalysisTask::configure(const board::BoardConfig& b, Supervisor* sup) {
  sup_ = sup;
  enabled_ = false;
  channel_ = b.tracker.channel;
  min_confidence_ = b.tracker.min_confidence;
  st_ = AnalysisStatus{};
  st_.tracked_speed_hz = std::numeric_limits<double>::quiet_NaN();
  seen_updates_ = 0;
  published_.store(st_);
  if (b.bearing.present && !bearing_.configure(bearing_task_config(b)))
    return "[bearing]: the bearing task refused the configuration (check the monitored bearing and the aux constants)";
  coast_start_ns_.store(-1, std::memory_order_relaxed);
  drive_on_ = false;
  last_driven_speed_hz_ = 0.0;
  if (!b.tracker.enabled) return {};
  model::signal::SpeedTrackerOptions o = b.tracker.options;
  half_window_ns_ = static_cast<int64_t>(0.5 * o.stft.window_s * 1e9);
  o.stft.sample_rate_hz = b.rate_hz;
  if (std::string err = tracker_.configure(o, b.tracker.max_gap_samples); !err.empty()) return "[tracker]: " + err;
  enabled_ = true;
  return {};
}

void AnalysisTask::on_sample(const LoopSample& s) {
  if (!enabled_) return;
  const bool drive_on = s.speed_command_hz > 0.0f;
  if (drive_on != drive_on_) {
    coast_start_ns_.store(drive_on ? -1 : s.t_ns, std::memory_order_relaxed);
    drive_on_ = drive_on;
  }
  if (!feeding_.load(std::memory_order_relaxed)) return;
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
    // Lost: the tracker says so, or has nothing, or is not sure enough (coasting on noise
    // once the line has left its range): never a guess presented as a speed.
    bool lost = t.lost != 0 || !std::isfinite(t.speed_hz) || !(t.confidence >= min_confidence_);
    bool rejected = false;
    // Coasting (see k_coast_rise_fraction): the window reaches past the drive's stop.
    const int64_t coast = coast_start_ns_.load(std::memory_order_relaxed);
    st_.coasting = coast >= 0 && t.t_ns + half_window_ns_ > coast ? 1 : 0;
    if (!st_.coasting) {
      st_.coast_ceiling_hz = 0.0;
      if (!lost) last_driven_speed_hz_ = t.speed_hz;
    } else {
      if (st_.coast_ceiling_hz == 0.0 && last_driven_speed_hz_ > 0.0)
        st_.coast_ceiling_hz = last_driven_speed_hz_ * (1.0 + k_coast_rise_fraction);
      // A window that straddles the stop mixes the driven and the coasting spin: refused.
      if (!lost && t.t_ns - half_window_ns_ < coast) {
        lost = true;
        rejected = true;
        ++st_.coast_rejections;
      } else if (!lost && st_.coast_ceiling_hz > 0.0) {
        if (t.speed_hz > st_.coast_ceiling_hz) {
          lost = true;
          rejected = true;
          ++st_.coast_rejections;
        } else {
          st_.coast_ceiling_hz = std::min(st_.coast_ceiling_hz, t.speed_hz * (1.0 + k_coast_rise_fraction));
        }
      }
    }
    st_.update_t_ns = t.t_ns;
    st_.tracked_speed_hz = lost ? std::numeric_limits<double>::quiet_NaN() : t.speed_hz;
    // A refused update is "not tracked": its confidence is published as 0 (below the threshold).
    const double confidence = rejected ? 0.0 : t.confidence;
    st_.confidence = confidence;
    st_.lost = lost ? 1 : 0;
    st_.below_min = t.below_min;
    st_.mode = t.mode;
    st_.tracker_updates = t.update_seq;
    if (sup_) sup_->publish_tracked_speed(t.speed_hz, confidence, lost);
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
