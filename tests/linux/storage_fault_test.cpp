// Storage faults on the real FileStorage, injected through its fault seam (FsFaultHook, no
// LD_PRELOAD): a full file system (ENOSPC after a short write), EIO on fsync and on the
// directory fsync, a read-only file system (EROFS), a slow fsync. For each: the item holds its
// old content or its new one, never a mix; no temporary is left; the wear record's previous
// generation stays the newest; the event writer keeps failed events and retries them in order,
// so none is lost within its retry queue, and a full queue is counted, never silent.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <thread>

#include "firmware/board/board.hpp"
#include "firmware/capture/floating_capture.hpp"
#include "firmware/events/event_codec.hpp"
#include "firmware/events/event_writer.hpp"
#include "firmware/persistence/wear_store.hpp"
#include "hal/linux/file_storage.hpp"
#include "tests/capture/synthetic_samples.hpp"

namespace {

namespace lx = amb::hal::linux_hw;
using lx::FsOp;

/// Fails one kind of call with one errno (or delays it) while armed.
class Inject final : public lx::FsFaultHook {
 public:
  Inject(FsOp o, int err, int delay = 0) : op(o), error(err), delay_ms(delay) {}
  FsOp op = FsOp::fsync;
  int error = 0;        ///< errno to inject (0: none)
  int delay_ms = 0;     ///< sleep before `op`
  int calls = 0;        ///< injected so far
  int before(FsOp o, std::string_view, uint64_t) override {
    if (o != op) return 0;
    if (delay_ms > 0) std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms));
    if (error != 0) ++calls;
    return error;
  }
};

std::string fresh_dir(const std::string& tag) {
  auto p = std::filesystem::temp_directory_path() / ("amb-storage-fault-" + tag + "-" + std::to_string(::getpid()));
  std::filesystem::remove_all(p);
  return p.string();
}

int temporaries(const std::string& dir) {
  int n = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().filename().string().starts_with(".")) ++n;
  return n;
}

struct Case {
  const char* name;
  FsOp op;
  int error;
};
// What each fault looks like to write_atomic; fsync_dir fails after the rename (the new
// content is in place: reported as a failure, the caller writes again).
const Case k_cases[] = {
    {"ENOSPC on write (short write)", FsOp::write, ENOSPC}, {"EIO on fsync", FsOp::fsync, EIO},
    {"EROFS on create", FsOp::create, EROFS},                {"EROFS on rename", FsOp::rename, EROFS},
    {"EIO on the directory fsync", FsOp::fsync_dir, EIO},
};

TEST(StorageFaults, AFailedWriteLeavesTheOldOrTheNewItemAndNoTemporary) {
  for (const Case& c : k_cases) {
    SCOPED_TRACE(c.name);
    const std::string dir = fresh_dir("item");
    lx::FileStorage fs(dir);
    std::string err;
    const std::vector<uint8_t> old_bytes(5000, 0x11), new_bytes(7000, 0x22);
    ASSERT_TRUE(fs.write_atomic("item", old_bytes, err)) << err;
    Inject inj(c.op, c.error);
    fs.set_fault_hook(&inj);
    EXPECT_FALSE(fs.write_atomic("item", new_bytes, err));
    EXPECT_NE(err.find(std::strerror(c.error)), std::string::npos) << err;
    EXPECT_EQ(inj.calls, 1);
    fs.set_fault_hook(nullptr);
    std::vector<uint8_t> now;
    ASSERT_TRUE(fs.read("item", now, err)) << err;
    EXPECT_TRUE(now == old_bytes || (c.op == FsOp::fsync_dir && now == new_bytes)) << "a mix: " << now.size();
    EXPECT_EQ(temporaries(dir), 0);
    std::filesystem::remove_all(dir);
  }
}

amb::fw::WearRecord wear_record(uint32_t seq) {
  amb::fw::WearRecord r;
  r.sequence = seq;
  r.board_name = "bath-amb-rig";
  r.life_model = "storage-fault-test";
  r.event_count = seq;
  return r;
}

TEST(StorageFaults, TheWearRecordKeepsItsPreviousGenerationThroughEveryFault) {
  for (const Case& c : k_cases) {
    SCOPED_TRACE(c.name);
    const std::string dir = fresh_dir("wear");
    {
      lx::FileStorage fs(dir);
      amb::fw::WearStore w(fs, "bath-amb-rig");
      w.open();
      std::string detail;
      ASSERT_EQ(w.accept(amb::fw::encode_wear_record(wear_record(1)), detail), amb::fw::WriteBackResult::accepted);
      Inject inj(c.op, c.error);
      fs.set_fault_hook(&inj);
      EXPECT_EQ(w.accept(amb::fw::encode_wear_record(wear_record(2)), detail), amb::fw::WriteBackResult::storage_failed);
      EXPECT_EQ(w.record().sequence, 1u) << "the board keeps serving the stored record";
      fs.set_fault_hook(nullptr);
      EXPECT_EQ(w.accept(amb::fw::encode_wear_record(wear_record(2)), detail), amb::fw::WriteBackResult::accepted)
          << "the same record again once the storage works: " << detail;
    }
    lx::FileStorage fs(dir);
    amb::fw::WearStore again(fs, "bath-amb-rig");
    const auto rep = again.open();
    EXPECT_EQ(rep.corrupt_slots, 0) << rep.detail;
    EXPECT_EQ(again.record().sequence, 2u);
    std::filesystem::remove_all(dir);
  }
}

/// A frozen event every `n` calls, through the real capture (manual trigger, short windows).
struct EventSource {
  amb::board::BoardConfig board = [] {
    auto b = amb::board::load_board("bath-amb-rig");
    b.capture.pre_trigger_s = 0.01;
    b.capture.post_trigger_s = 0.01;
    b.capture.rearm_hold_s = 0.001;
    b.capture.event_buffers = 8;
    return b;
  }();
  amb::fw::FloatingCapture capture;
  uint64_t seq = 0;
  EventSource() { amb::fw::configure_capture(capture, board); }
  /// Run the capture until one more event is frozen.
  void one_event() {
    const uint64_t frozen = capture.counters().events_frozen;
    for (int i = 0; i < 2000 && capture.mode() != amb::fw::FloatingCapture::Mode::armed; ++i)
      capture.on_sample(amb::test::synthetic_sample(seq++));  // re-armed after the hold
    capture.request_manual_trigger();
    for (int i = 0; i < 2000 && capture.counters().events_frozen == frozen; ++i) {
      capture.on_sample(amb::test::synthetic_sample(seq++));
    }
    ASSERT_GT(capture.counters().events_frozen, frozen);
  }
};

/// An event writer without diagnosis that retries after 1 ms and holds `max_pending` events.
amb::fw::WriterOptions retrying_writer(int max_pending) {
  amb::fw::WriterOptions wo;
  wo.run_diagnosis = false;
  wo.retry_initial_ms = 1;
  wo.retry_max_ms = 1;
  wo.max_pending = max_pending;
  return wo;
}

/// `n` events frozen one after the other, the writer polled after each.
void freeze_and_poll(EventSource& src, amb::fw::EventWriter& writer, int n) {
  for (int i = 0; i < n; ++i) {
    src.one_event();
    writer.poll();
  }
}

TEST(StorageFaults, EventsAreKeptAndRetriedInOrderWhileTheStorageFails) {
  const std::string dir = fresh_dir("events");
  EventSource src;
  lx::FileStorage fs(dir);
  amb::fw::EventWriter writer(src.capture, fs, src.board, retrying_writer(4));
  Inject inj(FsOp::create, EROFS);
  fs.set_fault_hook(&inj);
  freeze_and_poll(src, writer, 3);
  auto k = writer.store_counters();
  EXPECT_EQ(k.written, 0u);
  EXPECT_EQ(k.pending, 3u);
  EXPECT_GE(k.write_errors, 1u);  // the first attempt; later ones wait for the backoff
  EXPECT_EQ(k.lost, 0u);
  EXPECT_EQ(fs.list().size(), 0u);
  // The storage recovers: the three go out, oldest first, with the numbers they were given.
  fs.set_fault_hook(nullptr);
  std::this_thread::sleep_for(std::chrono::milliseconds(5));
  writer.poll();
  k = writer.store_counters();
  EXPECT_EQ(k.written, 3u);
  EXPECT_EQ(k.pending, 0u);
  EXPECT_GE(k.retries, 3u);
  const auto names = fs.list();
  ASSERT_EQ(names.size(), 3u);
  EXPECT_EQ(names[0], "event_00000001.ambe");
  EXPECT_EQ(names[2], "event_00000003.ambe");
  for (const auto& n : names) {
    std::vector<uint8_t> b;
    std::string e;
    amb::fw::EventRecord r;
    ASSERT_TRUE(fs.read(n, b, e));
    EXPECT_TRUE(amb::fw::decode_event(b, r, e)) << n << ": " << e;
  }
  std::filesystem::remove_all(dir);
}

TEST(StorageFaults, AFullRetryQueueIsCountedAsLostPerThePolicy) {
  for (auto policy : {amb::fw::StoragePolicy::drop_oldest, amb::fw::StoragePolicy::refuse_new}) {
    const std::string dir = fresh_dir("queue");
    EventSource src;
    src.board.capture.storage_policy = policy;
    lx::FileStorage fs(dir);
    amb::fw::EventWriter writer(src.capture, fs, src.board, retrying_writer(2));
    Inject inj(FsOp::fsync, EIO);
    fs.set_fault_hook(&inj);
    freeze_and_poll(src, writer, 5);
    EXPECT_EQ(writer.store_counters().lost, 3u);
    EXPECT_EQ(writer.store_counters().pending, 2u);
    EXPECT_NE(writer.last_error().find("retry queue full"), std::string::npos) << writer.last_error();
    fs.set_fault_hook(nullptr);
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    writer.poll();
    const auto names = fs.list();
    ASSERT_EQ(names.size(), 2u);
    // drop_oldest gives up the oldest waiting events (keeps 4, 5); refuse_new keeps 1, 2.
    if (policy == amb::fw::StoragePolicy::drop_oldest) EXPECT_EQ(names[0], "event_00000004.ambe");
    else EXPECT_EQ(names[0], "event_00000001.ambe");
    std::filesystem::remove_all(dir);
  }
}

TEST(StorageFaults, ASlowFsyncDelaysButLosesNothing) {
  const std::string dir = fresh_dir("slow");
  lx::FileStorage fs(dir);
  Inject inj(FsOp::fsync, 0, 50);
  fs.set_fault_hook(&inj);
  std::string err;
  const auto t0 = std::chrono::steady_clock::now();
  ASSERT_TRUE(fs.write_atomic("item", std::vector<uint8_t>(100, 1), err)) << err;
  EXPECT_GE(std::chrono::steady_clock::now() - t0, std::chrono::milliseconds(50));
  std::filesystem::remove_all(dir);
}

}  // namespace
