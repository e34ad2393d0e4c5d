#pragma once
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"  // malloc/free back new/delete here on purpose
// Counts heap allocations in this test binary (replaces global operator new). Include from
// exactly one translation unit per executable with AMB_DEFINE_ALLOC_COUNTER defined.
#include <atomic>
#include <cstdlib>
#include <new>

namespace amb::test {
inline std::atomic<long> g_allocations{0};
inline std::atomic<long long> g_bytes{0};  ///< bytes requested from operator new, summed
inline long allocations() { return g_allocations.load(); }
inline long long bytes_requested() { return g_bytes.load(); }
}  // namespace amb::test

#ifdef AMB_DEFINE_ALLOC_COUNTER
void* operator new(std::size_t n) {
  amb::test::g_allocations.fetch_add(1);
  amb::test::g_bytes.fetch_add(static_cast<long long>(n));
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) {
  amb::test::g_allocations.fetch_add(1);
  amb::test::g_bytes.fetch_add(static_cast<long long>(n));
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void* operator new(std::size_t n, std::align_val_t al) {
  amb::test::g_allocations.fetch_add(1);
  amb::test::g_bytes.fetch_add(static_cast<long long>(n));
  if (void* p = std::aligned_alloc(static_cast<std::size_t>(al), (n + static_cast<std::size_t>(al) - 1) / static_cast<std::size_t>(al) * static_cast<std::size_t>(al))) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
#endif
