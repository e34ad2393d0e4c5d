#include "firmware/budget/board_budget.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "firmware/app/loop_sample.hpp"
#include "firmware/board/board.hpp"
#include "firmware/capture/floating_capture.hpp"
#include "firmware/events/event_codec.hpp"
#include "firmware/persistence/generation_store.hpp"
#include "firmware/tracking/speed_tracker_task.hpp"
#include "firmware/wear/wear_record.hpp"
#include "model/signal/speed_ridge_tracker.hpp"

namespace amb::fw {

namespace {
std::string fmt(const char* f, double a, double b = 0.0, double c = 0.0) {
  char s[200];
  std::snprintf(s, sizeof s, f, a, b, c);
  return s;
}
/// Heap bytes of the speed tracker the analysis task configures for this board (the same
/// options), 0 if the board's tracker is disabled or refused.
uint64_t tracker_heap_bytes(const board::BoardConfig& b) {
  if (!b.tracker.enabled) return 0;
  model::signal::SpeedTrackerOptions o = b.tracker.options;
  o.stft.sample_rate_hz = b.rate_hz;
  model::signal::SpeedRidgeTracker t;
  if (!t.configure(o).empty()) return 0;
  return t.heap_bytes();
}
}  // namespace

int service_threads(const BudgetOptions& o) { return 3 + (o.analysis_thread ? 1 : 0); }

std::vector<BufferBudget> buffer_budget(const board::BoardConfig& b, const BudgetOptions& o) {
  const CaptureSizes cs = capture_sizes(b.capture, b.rate_hz);
  const uint64_t window = cs.window_samples();
  const uint64_t sample = sizeof(LoopSample);
  const uint64_t file = event_file_bytes(window, true);
  const bool tracker = o.analysis_thread && b.tracker.enabled;
  const double rate = b.rate_hz;
  std::vector<BufferBudget> t;
  t.push_back({"capture ring", cs.ring_samples * sample,
               fmt("2^ceil(log2(pre + post + 1)) = %.0f samples x %.0f B (pre_trigger_s + post_trigger_s at %.0f Hz)",
                   static_cast<double>(cs.ring_samples), static_cast<double>(sample), rate),
               true});
  t.push_back({"frozen-event buffers", static_cast<uint64_t>(b.capture.event_buffers) * window * sample,
               fmt("event_buffers %.0f x %.0f samples x %.0f B", b.capture.event_buffers, static_cast<double>(window),
                   static_cast<double>(sample)),
               true});
  t.push_back({"tracker hand-off ring", tracker ? k_tracker_ring_capacity * sizeof(TrackerSample) : 0,
               fmt("%.0f samples x %.0f B (fixed: 3.3 s at 10 kHz), analysis thread only",
                   static_cast<double>(k_tracker_ring_capacity), static_cast<double>(sizeof(TrackerSample))),
               true});
  t.push_back({"tracker STFT and ridge search", tracker ? tracker_heap_bytes(b) : 0,
               fmt("window %.0f samples, nfft %.0f: window, history, FFT in/out, spectrum, per-bin and per-candidate scores",
                   std::round(b.tracker.options.stft.window_s * rate), static_cast<double>(b.tracker.options.stft.nfft)),
               true});
  t.push_back({"wear-record write-back staging", wear_record_size(), "one AMBW v1 record", true});
  t.push_back({"thread stacks", static_cast<uint64_t>(service_threads(o)) * o.thread_stack_bytes,
               fmt("%.0f threads x %.0f KiB (loop, Modbus, event writer", service_threads(o),
                   static_cast<double>(o.thread_stack_bytes) / 1024.0) +
                   (o.analysis_thread ? ", analysis)" : ")"),
               true});
  t.push_back({"event record copy", window * sample,
               fmt("%.0f samples x %.0f B (the writer copies the window out and frees the buffer)",
                   static_cast<double>(window), static_cast<double>(sample)),
               false});
  t.push_back({"quick-look orbit (bearing task)", 4 * window * sizeof(double),
               fmt("x, y at the two aux planes: 4 x %.0f samples x 8 B", static_cast<double>(window)), false});
  t.push_back({"event file image", file, fmt("AMBE v3: 1164 B + %.0f samples x 84 B", static_cast<double>(window)),
               false});
  t.push_back({"event retry queue (storage faults only)", static_cast<uint64_t>(std::max(1, o.writer_max_pending)) * file,
               fmt("max_pending %.0f x one event file", std::max(1, o.writer_max_pending)), false});
  t.push_back({"event download window (Modbus)", file, "one event file, while the host downloads it", false});
  // The loop-sensitivity sweep (issue 35): its record buffer is allocated at configure (held
  // whether or not a sweep runs); the event thread copies it out and encodes it once per sweep.
  const SweepParams& sw = b.sweep;
  const uint64_t per_axis = static_cast<uint64_t>(sw.recorded_periods) * sw.samples_per_period;
  const uint64_t sweep_buffer = sw.enabled ? 16 * sw.axis_count() * per_axis : 0;
  t.push_back({"sweep record buffer", sweep_buffer,
               fmt("16 B (e, u_c, u, y as f32) x %.0f axes x %.0f recorded periods x N", sw.axis_count(),
                   sw.recorded_periods) + fmt(" %.0f ([sweep]; 0 when disabled)", sw.samples_per_period),
               true});
  t.push_back({"sweep record copy and event image", sw.enabled ? 2 * sweep_buffer + 4096 : 0,
               "the writer's copy of the record and the AMBE v4 image (the record + headers and lines), per sweep", false});
  return t;
}

uint64_t resident_buffer_bytes(const std::vector<BufferBudget>& table) {
  uint64_t n = 0;
  for (const BufferBudget& e : table)
    if (e.resident) n += e.bytes;
  return n;
}

StorageBudget storage_budget(const board::BoardConfig& b) {
  StorageBudget s;
  const CaptureSizes cs = capture_sizes(b.capture, b.rate_hz);
  s.window_samples = cs.window_samples();
  s.event_bytes_worst = event_file_bytes(s.window_samples, true);
  s.capacity_bytes = b.capture.storage_capacity_bytes;
  s.max_events = static_cast<uint64_t>(std::max(0, b.capture.max_events));
  s.events_kept = std::min(s.max_events, s.capacity_bytes / s.event_bytes_worst);
  s.wear_record_bytes = 2 * (k_generation_header_bytes + wear_record_size());
  s.policy = b.capture.storage_policy == StoragePolicy::drop_oldest ? "drop_oldest" : "refuse_new";
  return s;
}

}  // namespace amb::fw
