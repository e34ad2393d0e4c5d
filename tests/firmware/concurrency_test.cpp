// The lock-free exchanges between the loop and the other threads, under real concurrency (and
// under ThreadSanitizer: scripts/sanitizers.sh tsan): the SeqLock never hands out a torn
// snapshot, the SPSC ring delivers every record it accepted in order and counts what it
// refused, the writer side of both never waits. Host only (threads; see tests/linux/CMakeLists).
#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <cstdint>
#include <thread>
#include <vector>

#include "firmware/app/loop_runner.hpp"
#include "firmware/common/spsc_ring.hpp"

namespace {

/// A snapshot whose fields are all derived from one counter: any mix of two stores shows.
struct Snapshot {
  uint64_t k = 0;
  std::array<uint64_t, 9> f{};
  double d = 0.0;
  uint32_t tail = 0;
};
Snapshot make(uint64_t k) {
  Snapshot s;
  s.k = k;
  for (size_t i = 0; i < s.f.size(); ++i) s.f[i] = k * 2654435761u + i;
  s.d = static_cast<double>(k) * 0.5;
  s.tail = static_cast<uint32_t>(k ^ 0xA5A5A5A5u);
  return s;
}
bool intact(const Snapshot& s) {
  const Snapshot r = make(s.k);
  return r.f == s.f && r.d == s.d && r.tail == s.tail;
}

/// The loop does its work between two publications; a writer storing back to back would keep
/// every reader of a large snapshot retrying (a reader only succeeds between two stores), so the
/// writer leaves a gap after each store. It starts short, shorter than a reader's copy is likely
/// to need on a loaded host, so that reads overlap stores. When no read completed over the last
/// 1024 stores, the gap doubles: a reader slower than the gap (TSan's instrumentation, a starved
/// CPU) would otherwise retry for ever while the writer waits for its reads, a livelock of the
/// test (a TSan smoke run once spent about an hour in LoopStatsThroughTheSeqLock), not of the
/// seqlock, whose firmware writer stores only every 16 loop periods.
class WriterGap {
 public:
  void after_store(uint64_t reads_so_far) {
    if (++stores_ % 1024 == 0) {
      if (reads_so_far == reads_at_check_ && spins_ < (1 << 20)) spins_ *= 2;
      reads_at_check_ = reads_so_far;
    }
    std::atomic<int> spin{0};
    for (int i = 0; i < spins_; ++i) spin.fetch_add(1, std::memory_order_relaxed);
  }
  int spins() const { return spins_; }

 private:
  int spins_ = 64;
  uint64_t stores_ = 0, reads_at_check_ = 0;
};

TEST(Concurrency, SeqLockNeverHandsOutATornSnapshot) {
  amb::fw::SeqLock<Snapshot> lock;
  lock.store(make(0));
  std::atomic<bool> done{false};
  std::atomic<uint64_t> reads{0}, torn{0}, backwards{0};
  std::atomic<int> started{0};
  std::vector<std::thread> readers;
  for (int r = 0; r < 2; ++r)
    readers.emplace_back([&] {
      started.fetch_add(1);
      uint64_t last = 0;
      while (!done.load(std::memory_order_relaxed)) {
        const Snapshot s = lock.load();
        if (!intact(s)) torn.fetch_add(1);
        if (s.k < last) backwards.fetch_add(1);
        last = s.k;
        reads.fetch_add(1, std::memory_order_relaxed);
      }
    });
  // The writer starts once both readers run and goes on until they have overlapped it for a
  // good number of reads (a loaded machine may schedule the readers late: without this the
  // stores could all be over before the first read, and the test would check nothing).
  while (started.load() < 2) std::this_thread::yield();
  constexpr uint64_t k_min_stores = 300'000;
  constexpr uint64_t k_max_stores = 200'000'000;
  uint64_t k_stores = 0;
  WriterGap gap;
  for (uint64_t k = 1; k <= k_max_stores; ++k) {
    lock.store(make(k));
    k_stores = k;
    gap.after_store(reads.load(std::memory_order_relaxed));
    if (k >= k_min_stores && reads.load(std::memory_order_relaxed) >= 20'000) break;
  }
  done = true;
  for (auto& t : readers) t.join();
  EXPECT_EQ(torn.load(), 0u);
  EXPECT_EQ(backwards.load(), 0u) << "a reader saw an older snapshot after a newer one";
  EXPECT_GE(reads.load(), 20'000u) << "the readers hardly overlapped the writer";
  EXPECT_EQ(lock.load().k, k_stores);
}

TEST(Concurrency, LoopStatsThroughTheSeqLock) {
  // The loop statistics (a 64-bin histogram) as run_linux publishes them every 16 periods.
  amb::fw::SeqLock<amb::fw::LoopStats> lock;
  std::atomic<bool> done{false};
  std::atomic<uint64_t> bad{0}, reads{0};
  std::atomic<bool> started{false};
  std::thread reader([&] {
    started = true;
    while (!done.load(std::memory_order_relaxed)) {
      const amb::fw::LoopStats s = lock.load();
      uint64_t sum = 0;
      for (uint64_t h : s.latency_hist) sum += h;
      if (sum != s.periods) bad.fetch_add(1);
      reads.fetch_add(1, std::memory_order_relaxed);
    }
  });
  while (!started.load()) std::this_thread::yield();
  amb::fw::LoopStats s;
  WriterGap gap;
  for (uint64_t p = 1; p <= 100'000'000; ++p) {
    ++s.periods;
    ++s.latency_hist[p % amb::fw::LoopStats::k_bins];
    lock.store(s);
    gap.after_store(reads.load(std::memory_order_relaxed));
    if (p >= 200'000 && reads.load(std::memory_order_relaxed) >= 5'000) break;
  }
  done = true;
  reader.join();
  EXPECT_EQ(bad.load(), 0u);
  EXPECT_GE(reads.load(), 5'000u) << "the reader hardly overlapped the writer";
}

TEST(Concurrency, SpscRingDeliversInOrderAndCountsWhatItRefused) {
  struct Record {
    uint64_t seq;
    std::array<uint32_t, 6> payload;
  };
  auto ring = std::make_unique<amb::fw::SpscRing<Record, 256>>();
  constexpr uint64_t k_records = 1'000'000;
  std::atomic<bool> produced{false};
  uint64_t accepted = 0;
  std::thread producer([&] {
    for (uint64_t i = 0; i < k_records; ++i) {
      Record r{i, {}};
      r.payload.fill(static_cast<uint32_t>(i * 7));
      if (ring->push(r)) ++accepted;  // never waits: a full ring drops and counts
    }
    produced = true;
  });
  uint64_t received = 0, out_of_order = 0, damaged = 0, last = 0;
  bool first = true;
  Record r{};
  for (;;) {
    const bool done = produced.load(std::memory_order_acquire);
    while (ring->pop(r)) {
      if (!first && r.seq <= last) ++out_of_order;
      for (uint32_t v : r.payload) damaged += v != static_cast<uint32_t>(r.seq * 7);
      last = r.seq;
      first = false;
      ++received;
    }
    if (done && ring->size() == 0) break;
  }
  producer.join();
  EXPECT_EQ(out_of_order, 0u);
  EXPECT_EQ(damaged, 0u);
  EXPECT_EQ(received, accepted);
  EXPECT_EQ(accepted + ring->dropped(), k_records);
  std::printf("[ figures ] SPSC ring (256): %llu of %llu records delivered, %llu dropped (producer never waited)\n",
              static_cast<unsigned long long>(received), static_cast<unsigned long long>(k_records),
              static_cast<unsigned long long>(ring->dropped()));
}

}  // namespace
