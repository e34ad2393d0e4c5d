// The firmware replays its own capture bit for bit: a SIL drop with the floating capture
// attached is stored as an AMBE v1 event, decoded, and replayed through a fresh supervisor
// configured from the board the event names (hal/replay backend). Every recorded
// current_demand_a, speed command, state, phase, fault, flags word and sample time is
// compared bit for bit; the replayed capture must trigger on the same sample with the same
// causes, and Phase B re-run on the replayed capture must give the recorded result.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "firmware/events/event_codec.hpp"
#include "host-tools/core/replay/event_board.hpp"
#include "host-tools/core/replay/event_replay.hpp"
#include "tests/replay/sil_capture_run.hpp"
#include "tests/support/test_paths.hpp"

namespace {
using namespace amb::host::replay;

amb::fw::EventRecord decode(const std::vector<uint8_t>& bytes) {
  amb::fw::EventRecord r;
  std::string err;
  EXPECT_TRUE(amb::fw::decode_event(bytes, r, err)) << err;
  return r;
}

void print(const char* what, const ReplayResult& r) {
  std::printf("[replay %s] mode %s, warm-up %llu steps (%s); %s\n%s", what, r.mode.c_str(),
              static_cast<unsigned long long>(r.warm_up.steps), r.warm_up.note.c_str(), r.compare_from_reason.c_str(),
              format_comparison(r.comparison).c_str());
  std::printf("  trigger: recorded sample %zu (%s, mask 0x%x), replayed %zu (%s, mask 0x%x); Phase B %s -> %s%s\n",
              r.trigger.recorded_index, r.trigger.recorded_cause.c_str(), r.trigger.recorded_cause_mask,
              r.trigger.replayed_index, r.trigger.replayed_cause.c_str(), r.trigger.replayed_cause_mask,
              amb::fw::diag::to_string(r.diagnosis.recorded.type), amb::fw::diag::to_string(r.diagnosis.replayed.type),
              r.diagnosis.bit_exact ? " (bit-exact)" : (" (first difference: " + r.diagnosis.first_difference + ")").c_str());
}


/// Keep the stored event files as artefacts (for amb-host replay / report by hand).
void keep(const std::vector<uint8_t>& bytes, const char* name) {
  std::filesystem::create_directories(amb::test::artefact_dir());
  std::ofstream(std::string(amb::test::artefact_dir()) + "/" + name, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

TEST(ReplayBitExact, FullHistoryWindowIsReproducedFromTheFirstSample) {
  const auto& run = amb::test::sil_capture();
  keep(run.event_full_history, "sil_event_full_history.ambe");
  keep(run.event_default, "sil_event.ambe");
  const amb::fw::EventRecord ev = decode(run.event_full_history);
  ASSERT_FALSE(ev.samples.empty());
  ASSERT_EQ(ev.samples.front().seq, 0u) << "the full-history window must reach back to configure";
  ASSERT_TRUE(ev.has_diagnosis);
  const auto board = board_for_event(ev);
  const ReplayResult r = replay_event(ev, board);
  print("full history", r);
  EXPECT_EQ(r.mode, "from_configure");
  EXPECT_EQ(r.comparison.compare_from, 0u);
  EXPECT_EQ(r.comparison.compared_samples, ev.samples.size());
  EXPECT_EQ(r.comparison.mismatched_samples, 0u);
  EXPECT_TRUE(r.comparison.bit_exact);
  EXPECT_GE(r.commands_posted, 2u) << "levitate and run are reconstructed from the lifecycle";
  // The whole replayed capture is the recorded one, byte for byte (seq, speed estimate included).
  ASSERT_EQ(r.replayed.size(), ev.samples.size());
  // The tachometer channel (AMBE v3 tach_hz) is fed as recorded, the recorded speed estimate
  // as the tracker's update (replay_input.hpp): every byte is the firmware's.
  size_t differing = 0;
  for (size_t i = 0; i < ev.samples.size(); ++i) {
    ASSERT_EQ(std::memcmp(&r.replayed[i].tach_hz, &ev.samples[i].tach_hz, sizeof(float)), 0) << i;
    if (std::memcmp(&r.replayed[i], &ev.samples[i], sizeof(amb::fw::LoopSample)) != 0) ++differing;
  }
  EXPECT_EQ(differing, 0u);
  EXPECT_TRUE(r.trigger.replayed_frozen);
  EXPECT_TRUE(r.trigger.reproduced);
  EXPECT_TRUE(r.diagnosis.recorded_available);
  EXPECT_TRUE(r.diagnosis.bit_exact) << r.diagnosis.first_difference;
}

// A board whose speed estimate is the tracker's (asynchronous, so not re-run in lockstep):
// the replay feeds the recorded tachometer as the tachometer (here none: -1) and the recorded estimate, with
// its confidence and lost flag, as the tracker's update (replay_input.hpp). The replayed
// capture is the recorded one byte for byte, the estimate's stretches of loss and staleness
// included.
TEST(ReplayBitExact, TrackerSpeedSourceIsReproducedWithTheTachometerAsRecorded) {
  amb::test::CaptureRunOptions o;
  o.tracker_speed_source = true;
  const auto run = amb::test::run_sil_capture(o);
  const amb::fw::EventRecord ev = decode(run.event_full_history);
  ASSERT_EQ(ev.samples.front().seq, 0u);
  // The recording is the tracker's (the simulated rig has no tachometer): off the speed
  // command at speed, lost for a while.
  size_t off_command = 0, lost = 0;
  for (const auto& smp : ev.samples) {
    if (smp.speed_command_hz > 1.0 && smp.speed_hz == smp.speed_hz && smp.speed_hz != smp.speed_command_hz) ++off_command;
    if ((smp.speed_quality & amb::fw::k_speed_lost_bit) != 0) ++lost;
  }
  ASSERT_GT(off_command, 1000u);
  ASSERT_GT(lost, 1000u);
  auto board = board_for_event(ev);
  board.tracker.enabled = true;
  board.tracker.speed_source = amb::fw::SpeedSource::tracker;
  const ReplayResult r = replay_event(ev, board);
  print("tracker speed source", r);
  EXPECT_TRUE(r.comparison.bit_exact);
  ASSERT_EQ(r.replayed.size(), ev.samples.size());
  size_t differing = 0;
  for (size_t i = 0; i < ev.samples.size(); ++i)
    if (std::memcmp(&r.replayed[i], &ev.samples[i], sizeof(amb::fw::LoopSample)) != 0) ++differing;
  EXPECT_EQ(differing, 0u);
  EXPECT_TRUE(r.trigger.reproduced);
}

TEST(ReplayBitExact, BoardWindowIsReproducedFromTheFirstSampleWithoutControllerState) {
  const auto& run = amb::test::sil_capture();
  const amb::fw::EventRecord ev = decode(run.event_default);
  ASSERT_GT(ev.samples.front().seq, 0u) << "the board's window starts mid-run";
  const auto board = board_for_event(ev);
  const ReplayResult r = replay_event(ev, board);
  print("board window", r);
  EXPECT_TRUE(r.warm_up.reached) << r.warm_up.note;
  EXPECT_EQ(r.mode, "after_warm_up");
  // The comparison starts where the amplifiers go off: after the trigger, before the end.
  ASSERT_NE(r.comparison.compare_from, k_no_index);
  EXPECT_GT(r.comparison.compare_from, ev.meta.trigger_index / 2);
  EXPECT_LT(r.comparison.compare_from, ev.samples.size());
  EXPECT_EQ(r.comparison.compared_samples, ev.samples.size() - r.comparison.compare_from);
  EXPECT_TRUE(r.comparison.bit_exact) << format_comparison(r.comparison);
  // Before it the controller state differs (integrators not in the event): that is why the
  // comparison cannot start earlier.
  EXPECT_GT(r.comparison.warm_up_differing_samples, 0u);
  EXPECT_TRUE(r.trigger.reproduced);
  EXPECT_TRUE(r.diagnosis.type_reproduced);
}

TEST(ReplayBitExact, OneUlpInOneRecordedInputIsFoundAndLocated) {
  const auto& run = amb::test::sil_capture();
  amb::fw::EventRecord ev = decode(run.event_full_history);
  // A sample while levitated at speed: the PID reacts on the same sample. One ulp of a
  // reading near zero moves the demand by less than one ulp of the recorded (float) demand,
  // which no comparison can see; so take the reading of largest magnitude among the first
  // 2000 samples at speed (one ulp of it is then ~1e-7 of the orbit, well above that).
  size_t first = 0;
  for (size_t i = 0; i < ev.samples.size(); ++i)
    if (ev.samples[i].phase == static_cast<uint8_t>(amb::fw::Phase::at_speed)) {
      first = i + 100;
      break;
    }
  ASSERT_GT(first, 0u);
  size_t k = first;
  for (size_t i = first; i < std::min(ev.samples.size(), first + 2000); ++i)
    if (ev.samples[i].phase == static_cast<uint8_t>(amb::fw::Phase::at_speed) &&
        std::abs(ev.samples[i].displacement_m[1]) > std::abs(ev.samples[k].displacement_m[1]))
      k = i;
  float& x = ev.samples[k].displacement_m[1];
  x = std::nextafter(x, 1.0f);
  const ReplayResult r = replay_event(ev, board_for_event(ev));
  EXPECT_FALSE(r.comparison.bit_exact);
  ASSERT_FALSE(r.comparison.differences.empty());
  EXPECT_EQ(r.comparison.differences.front().index, k);
  EXPECT_EQ(r.comparison.differences.front().channel.rfind("current_demand_a", 0), 0u);
  const std::string report = format_comparison(r.comparison);
  EXPECT_NE(report.find("sample " + std::to_string(k)), std::string::npos) << report;
}

TEST(ReplayBitExact, BoardThatDoesNotMatchTheEventIsRefusedWithAWayOut) {
  const auto& run = amb::test::sil_capture();
  amb::fw::EventRecord ev = decode(run.event_default);
  ev.meta.kp_n_per_m *= 1.01;
  try {
    (void)board_for_event(ev);
    FAIL() << "a board with other gains was accepted";
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("controller.kp_n_per_m"), std::string::npos) << m;
    EXPECT_NE(m.find("--board"), std::string::npos) << m;
  }
}

}  // namespace
