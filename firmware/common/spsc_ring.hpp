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
/// other threads retry until they get an untorn copy.
template <typename T>
class SeqLock {
  static_assert(std::is_trivially_copyable_v<T>);

 public:
  /// [RT, single writer]
  void store(const T& v) {
    const uint32_t s = seq_.load(std::memory_order_relaxed);
    seq_.store(s + 1, std::memory_order_relaxed);
    std::atomic_thread_fence(std::memory_order_release);
    copy_words(v);
    seq_.store(s + 2, std::memory_order_release);
  }
  /// Any thread.
  T load() const {
    T out;
    for (;;) {
      const uint32_t s0 = seq_.load(std::memory_order_acquire);
      if (s0 & 1u) continue;
      read_words(out);
      std::atomic_thread_fence(std::memory_order_acquire);
      if (seq_.load(std::memory_order_relaxed) == s0) return out;
    }
  }

 private:
  static constexpr size_t k_words = (sizeof(T) + 7) / 8;
  // Word-wise relaxed atomics avoid a data race on the payload (the C++ memory model forbids
  // plain concurrent read/write even when the sequence check discards torn copies).
  void copy_words(const T& v) {
    std::array<uint64_t, k_words> w{};
    std::memcpy(static_cast<void*>(w.data()), static_cast<const void*>(&v), sizeof(T));
    for (size_t i = 0; i < k_words; ++i) data_[i].store(w[i], std::memory_order_relaxed);
  }
  void read_words(T& v) const {
    std::array<uint64_t, k_words> w{};
    for (size_t i = 0; i < k_words; ++i) w[i] = data_[i].load(std::memory_order_relaxed);
    std::memcpy(static_cast<void*>(&v), static_cast<const void*>(w.data()), sizeof(T));
  }
  std::atomic<uint32_t> seq_{0};
  std::array<std::atomic<uint64_t>, k_words> data_{};
};

}  // namespace amb::fw
