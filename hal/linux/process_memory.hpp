#pragma once
// The process's memory set-up and what it costs, on Linux (glibc). configure_process_memory()
// runs once at the start of configure, before any thread is created: it bounds the malloc
// arenas and their thresholds and sets the stack size of every thread created afterwards
// (std::thread included). read_process_memory() and thread_cpu_ns() are for a supervision
// thread (they read /proc or make system calls): never call them from the loop step.
#include <pthread.h>

#include <cstddef>
#include <cstdint>
#include <string>

namespace amb::hal::linux_hw {

struct ProcessMemoryOptions {
  /// malloc arenas at most (M_ARENA_MAX). Each extra arena reserves 64 MiB of address space
  /// (PROT_NONE) that mlockall counts as locked; the loop never allocates, so the other
  /// threads can share one arena. 0: glibc's default (8 x CPUs).
  int malloc_arenas = 1;
  /// Allocations of at least this many bytes get their own mapping and go back to the system
  /// on free (M_MMAP_THRESHOLD, fixed: glibc's dynamic threshold would otherwise grow to the
  /// largest freed block and keep it in the heap). 0: glibc's default.
  size_t mmap_threshold_bytes = 128 * 1024;
  /// Free memory at the top of the heap above this is returned (M_TRIM_THRESHOLD). 0: default.
  size_t trim_threshold_bytes = 256 * 1024;
  /// Stack of every thread created afterwards (pthread_setattr_default_np), bytes; 0: keep
  /// glibc's default (RLIMIT_STACK, typically 8 MiB, all of it locked by mlockall).
  size_t thread_stack_bytes = 512 * 1024;
};

/// What was applied; `warnings` says what was refused (not fatal).
struct ProcessMemoryReport {
  bool malloc_bounded = false;
  bool stack_size_set = false;
  std::string warnings;
};

ProcessMemoryReport configure_process_memory(const ProcessMemoryOptions& options);

/// /proc/self/status figures, kB (all 0 if it could not be read).
struct ProcessMemory {
  uint64_t locked_kb = 0;     ///< VmLck: memory locked by mlock/mlockall
  uint64_t resident_kb = 0;   ///< VmRSS: resident now
  uint64_t peak_resident_kb = 0;  ///< VmHWM: highest resident so far
  uint64_t virtual_kb = 0;    ///< VmSize: address space mapped
};
ProcessMemory read_process_memory();

/// CPU time a thread of this process has used so far, ns (its CLOCK_THREAD_CPUTIME clock via
/// pthread_getcpuclockid); -1 if the thread is gone or the clock cannot be read.
int64_t thread_cpu_ns(pthread_t thread);

/// Time since the process started, ns: CLOCK_BOOTTIME now minus /proc/self/stat's starttime
/// (counted from boot); -1 if unknown. Resolution: the kernel's clock tick (USER_HZ, 10 ms).
int64_t ns_since_process_start();

}  // namespace amb::hal::linux_hw
