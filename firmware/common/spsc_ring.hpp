#pragma once
// Lock-free single-producer / single-consumer ring of fixed-size records. The producer (the
// loop thread) never blocks: when the ring is full the record is dropped and counted.
#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>

namespace amb::fw {

template <typename T, size_t CapacityPow2>
class SpscRing {
  static_assert((CapacityPow2 & (CapacityPow2 - 1)) == 0, "capacity must be a power of two");
  static_assert(std::is_trivially_copyable_v<T>, "records must be trivially copyable");

 public:
  /// [RT, producer] Append; false (and a counted drop) if full.
  bool push(const T& v) {
    const uint64_t head = head_.load(std::memory_order_relaxed);
    if (head - tail_.load(std::memory_order_acquire) >= CapacityPow2) {
      dropped_.fetch_add(1, std::memory_order_relaxed);
      return false;
    }
    buf_[head & (CapacityPow2 - 1)] = v;
    head_.store(head + 1, std::memory_order_release);
    return true;
  }
  /// [consumer] Take the oldest record; false when empty.
  bool pop(T& v) {
    const uint64_t tail = tail_.load(std::memory_order_relaxed);
    if (tail == head_.load(std::memory_order_acquire)) return false;
    v = buf_[tail & (CapacityPow2 - 1)];
    tail_.store(tail + 1, std::memory_order_release);
    return true;
  }
  size_t size() const { return static_cast<size_t>(head_.load(std::memory_order_acquire) - tail_.load(std::memory_order_acquire)); }
  uint64_t dropped() const { return dropped_.load(std::memory_order_relaxed); }
  static constexpr size_t capacity() { return CapacityPow2; }

 private:
  alignas(64) std::atomic<uint64_t> head_{0};
  alignas(64) std::atomic<uint64_t> tail_{0};
  alignas(64) std::atomic<uint64_t> dropped_{0};
  std::array<T, CapacityPow2> buf_{};
};

/// Single-writer sequence lock: the loop publishes a snapshot without blocking; readers in
/// other threads retry until they get an untorn copy. Lock-free and allocation-free on both
/// sides; the writer never waits.
///
/// Data-race-free by the C++ memory model without fences (ThreadSanitizer does not model
/// atomic_thread_fence, so a fence-based seqlock cannot be checked by it): the payload is an
/// array of 64-bit atomics, stored with release and loaded with acquire.
///  - writer: seq = s+1 (odd, relaxed); each word stored with release, so a reader that sees
///    any new word also sees seq >= s+1; seq = s+2 (release).
///  - reader: s0 = seq (acquire; s0 even, so every word of generation s0 is visible); words
///    (acquire: the final seq load cannot move above them); s1 = seq (relaxed). If a word came
///    from a later store than generation s0, s1 >= s0+1 and the copy is discarded.
/// On x86-64 acquire/release loads and stores are plain moves; on AArch64 they are LDAR/STLR.
template <typename T>
class SeqLock {
  static_assert(std::is_trivially_copyable_v<T>);

 public:
  /// [RT, single writer]
  void store(const T& v) {
    const uint32_t s = seq_.load(std::memory_order_relaxed);
    seq_.store(s + 1, std::memory_order_relaxed);
    std::array<uint64_t, k_words> w{};
    std::memcpy(static_cast<void*>(w.data()), static_cast<const void*>(&v), sizeof(T));
    for (size_t i = 0; i < k_words; ++i) data_[i].store(w[i], std::memory_order_release);
    seq_.store(s + 2, std::memory_order_release);
  }
  /// Any thread. Spins only while a store is in progress (bounded by the writer's copy).
  T load() const {
    std::array<uint64_t, k_words> w{};
    for (;;) {
      const uint32_t s0 = seq_.load(std::memory_order_acquire);
      if (s0 & 1u) continue;
      for (size_t i = 0; i < k_words; ++i) w[i] = data_[i].load(std::memory_order_acquire);
      if (seq_.load(std::memory_order_relaxed) == s0) break;
    }
    T out;
    std::memcpy(static_cast<void*>(&out), static_cast<const void*>(w.data()), sizeof(T));
    return out;
  }

 private:
  static constexpr size_t k_words = (sizeof(T) + 7) / 8;
  std::atomic<uint32_t> seq_{0};
  std::array<std::atomic<uint64_t>, k_words> data_{};
};

}  // namespace amb::fw
