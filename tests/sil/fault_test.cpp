// Faults and load while the loop runs (tests/sil/fault_rig.hpp), short windows: every fault
// is survived with no event lost within the storage policy, no record torn, and is reported
// by its counter; loop faults end in the safe state with the right reason and the rotor can
// be lifted again over Modbus (armed) afterwards. Latency figures are printed, not asserted
// (this machine is shared); docs/hardening.md has the table from amb-fault-rig.
#include <gtest/gtest.h>

#include <cstdio>

#include "tests/sil/fault_rig.hpp"

namespace {

namespace f = amb::sil::faults;

f::RigResult run(f::Fault fault) {
  f::RigOptions o;
  o.fault = fault;
  o.window_s = 1.5;
  o.recovery_s = 1.0;
  o.flood_max_requests = 200'000;
  const f::RigResult r = f::run_fault_rig(o);
  std::printf("[ figures ] %-20s p99 quiet %.1f us, fault %.1f us; overruns %llu / %llu; events frozen %llu written %llu "
              "refused %llu dropped %llu lost %llu; torn %llu/%d; %s -> %s\n",
              f::to_string(fault), r.quiet.p99_us, r.faulted.p99_us, static_cast<unsigned long long>(r.quiet.overruns),
              static_cast<unsigned long long>(r.faulted.overruns), static_cast<unsigned long long>(r.events_frozen),
              static_cast<unsigned long long>(r.written), static_cast<unsigned long long>(r.refused),
              static_cast<unsigned long long>(r.dropped_oldest), static_cast<unsigned long long>(r.events_lost),
              static_cast<unsigned long long>(r.events_torn), r.wear_corrupt_slots, r.state_after_fault.c_str(),
              r.state_at_end.c_str());
  EXPECT_EQ(r.events_lost, 0u) << "capture (no free buffer) " << r.capture_lost << ", writer (retry queue) " << r.writer_lost;
  EXPECT_EQ(r.events_torn, 0u);
  EXPECT_EQ(r.wear_corrupt_slots, 0);
  EXPECT_EQ(r.pending_at_end, 0u);
  EXPECT_GT(r.events_frozen, 2u);
  EXPECT_EQ(r.events_frozen, r.written + r.refused) << "every frozen event stored or refused by the policy";
  EXPECT_GT(r.quiet.periods, 5000u) << "the loop ran (sanitizer builds overrun and skip periods)";
  EXPECT_EQ(r.state_at_end, r.levitated ? "levitating" : "inactive");
  return r;
}

uint64_t c(const f::RigResult& r, const char* name) { return r.counters.count(name) ? r.counters.at(name) : 0; }

TEST(Faults, QuietRun) {
  const auto r = run(f::Fault::none);
  EXPECT_EQ(r.writebacks, (std::vector<std::string>{"refused_unsafe", "refused_unsafe", "refused_unsafe"}))
      << "wear-record commits are refused while levitated";
  EXPECT_EQ(r.state_after_fault, "levitating");
}

TEST(Faults, ModbusFlood) {
  const auto r = run(f::Fault::modbus_flood);
  std::printf("[ figures ] modbus counters: bad_frames %llu, refused_not_armed %llu, arm_key_mismatch %llu, illegal_address %llu, "
              "wrong_unit %llu\n",
              static_cast<unsigned long long>(c(r, "modbus.bad_frames")), static_cast<unsigned long long>(c(r, "modbus.refused_not_armed")),
              static_cast<unsigned long long>(c(r, "modbus.arm_key_mismatch")), static_cast<unsigned long long>(c(r, "modbus.illegal_address")),
              static_cast<unsigned long long>(c(r, "modbus.wrong_unit")));
  EXPECT_EQ(r.state_after_fault, "levitating");
  EXPECT_GT(c(r, "modbus.bad_frames"), 0u);
  EXPECT_GT(c(r, "modbus.refused_not_armed"), 0u);
  EXPECT_GT(c(r, "modbus.arm_key_mismatch"), 0u);
  EXPECT_GT(c(r, "modbus.illegal_address"), 0u);
  EXPECT_GT(c(r, "modbus.wrong_unit"), 0u);
  EXPECT_EQ(r.writebacks[1], "refused_unsafe") << "the operator's armed commit was answered through the flood";
  EXPECT_EQ(r.command_failures, 0u) << "every armed capture command got through: the flood cannot cancel an arm";
}

TEST(Faults, CanErrorFrames) {
  const auto r = run(f::Fault::can_errors);
  EXPECT_EQ(r.state_after_fault, "levitating");
  EXPECT_GT(c(r, "can.error_frames"), 10000u);
  EXPECT_GT(c(r, "fieldbus.malformed"), 2000u);
}

// A loop fault: the safe state for `reason`, and the rotor lifted again over Modbus afterwards.
void expect_safe_state_then_relevitated(const f::RigResult& r, const char* reason) {
  EXPECT_EQ(r.state_after_fault, "fault");
  EXPECT_EQ(r.fault_reason_after_fault, reason);
  EXPECT_TRUE(r.relevitated);
}

TEST(Faults, CanBabblingNodeEndsInTheSafeState) {
  const auto r = run(f::Fault::can_babble);
  expect_safe_state_then_relevitated(r, "sensor_invalid");
  EXPECT_GT(c(r, "can.rx_dropped"), 0u);
  EXPECT_GT(c(r, "faults.read_failures"), 10u);
}

TEST(Faults, SilentSensorNodeEndsInTheSafeState) {
  const auto r = run(f::Fault::sensor_silent);
  // No samples: the supervisor's sample check (10 periods, 1 ms) is the first to act; the node
  // timeout (node_timeout_ms, 50 ms) follows and is counted once.
  expect_safe_state_then_relevitated(r, "sensor_invalid");
  EXPECT_EQ(c(r, "fieldbus.node_timeouts"), 1u);
  EXPECT_EQ(c(r, "faults.safe_state_entries"), 1u);
}

TEST(Faults, StaleSensorNodeEndsInTheSafeState) {
  const auto r = run(f::Fault::sensor_stale);
  expect_safe_state_then_relevitated(r, "sensor_invalid");
  EXPECT_GT(c(r, "fieldbus.stale_periods"), 10u);
  EXPECT_EQ(c(r, "fieldbus.node_timeouts"), 0u) << "it was heard every 2 ms";
}

TEST(Faults, StorageFull) {
  const auto r = run(f::Fault::storage_full);
  EXPECT_GT(c(r, "storage.dropped_oldest"), 0u) << "drop_oldest made room";
  EXPECT_EQ(r.refused, 0u);
  // The wear commit competes for the space the dropped events gave back: accepted or
  // storage_failed (then committed again after the fault); never torn.
  EXPECT_EQ(r.writebacks.back(), "accepted");
  EXPECT_GE(r.wear_sequence, 2u);
}

// A storage fault during the wear commit: the commit fails once (storage_failed) and the same
// record is committed again after the fault.
void expect_commit_failed_then_retried(const f::RigResult& r) {
  EXPECT_EQ(r.writebacks, (std::vector<std::string>{"accepted", "storage_failed", "accepted"}));
  EXPECT_EQ(r.wear_sequence, 2u) << "the failed commit's record, committed again after the fault";
}

TEST(Faults, StorageFullOfOtherFiles) {
  const auto r = run(f::Fault::storage_full_other);
  EXPECT_GT(c(r, "storage.no_space"), 0u) << "counted, kept, retried";
  EXPECT_GT(c(r, "storage.retries"), 0u);
  EXPECT_LE(c(r, "storage.dropped_oldest"), 1u) << "one removal that gave no space back stops the dropping";
  EXPECT_EQ(r.refused, 0u);
  expect_commit_failed_then_retried(r);
}

TEST(Faults, StorageEio) {
  const auto r = run(f::Fault::storage_eio);
  EXPECT_GT(c(r, "storage.write_errors"), 0u);
  EXPECT_GT(c(r, "storage.retries"), 0u);
  expect_commit_failed_then_retried(r);
  EXPECT_EQ(r.refused, 0u);
}

TEST(Faults, StorageReadOnly) {
  const auto r = run(f::Fault::storage_read_only);
  EXPECT_GT(c(r, "storage.write_errors"), 0u);
  expect_commit_failed_then_retried(r);
  EXPECT_EQ(r.refused, 0u);
}

TEST(Faults, StorageSlowFsync) {
  const auto r = run(f::Fault::storage_slow_fsync);
  EXPECT_EQ(r.writebacks, (std::vector<std::string>{"accepted", "accepted", "accepted"}));
  EXPECT_EQ(r.wear_sequence, 3u);
  EXPECT_EQ(r.refused, 0u);
}

}  // namespace
