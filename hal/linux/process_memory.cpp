#include "hal/linux/process_memory.hpp"

#include <malloc.h>
#include <pthread.h>
#include <time.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>

namespace amb::hal::linux_hw {

namespace {
void add(std::string& w, const std::string& s) { w += (w.empty() ? "" : "; ") + s; }
}  // namespace

ProcessMemoryReport configure_process_memory(const ProcessMemoryOptions& o) {
  ProcessMemoryReport r;
  bool ok = true;
  // mallopt returns 1 on success, 0 on error.
  if (o.malloc_arenas > 0 && ::mallopt(M_ARENA_MAX, o.malloc_arenas) != 1) {
    ok = false;
    add(r.warnings, "mallopt(M_ARENA_MAX, " + std::to_string(o.malloc_arenas) + ") refused");
  }
  if (o.mmap_threshold_bytes > 0 && ::mallopt(M_MMAP_THRESHOLD, static_cast<int>(o.mmap_threshold_bytes)) != 1) {
    ok = false;
    add(r.warnings, "mallopt(M_MMAP_THRESHOLD) refused");
  }
  if (o.trim_threshold_bytes > 0 && ::mallopt(M_TRIM_THRESHOLD, static_cast<int>(o.trim_threshold_bytes)) != 1) {
    ok = false;
    add(r.warnings, "mallopt(M_TRIM_THRESHOLD) refused");
  }
  r.malloc_bounded = ok;
  if (o.thread_stack_bytes > 0) {
    pthread_attr_t a;
    int e = ::pthread_attr_init(&a);
    if (e == 0) e = ::pthread_attr_setstacksize(&a, o.thread_stack_bytes);
    if (e == 0) e = ::pthread_setattr_default_np(&a);
    ::pthread_attr_destroy(&a);
    if (e == 0) r.stack_size_set = true;
    else add(r.warnings, "thread stack size " + std::to_string(o.thread_stack_bytes) + ": " + std::strerror(e));
  }
  return r;
}

ProcessMemory read_process_memory() {
  ProcessMemory m;
  std::ifstream f("/proc/self/status");
  std::string key;
  uint64_t v = 0;
  std::string line;
  while (std::getline(f, line)) {
    std::istringstream is(line);
    if (!(is >> key >> v)) continue;
    if (key == "VmLck:") m.locked_kb = v;
    else if (key == "VmRSS:") m.resident_kb = v;
    else if (key == "VmHWM:") m.peak_resident_kb = v;
    else if (key == "VmSize:") m.virtual_kb = v;
  }
  return m;
}

int64_t thread_cpu_ns(pthread_t thread) {
  clockid_t cid;
  if (::pthread_getcpuclockid(thread, &cid) != 0) return -1;
  timespec ts{};
  if (::clock_gettime(cid, &ts) != 0) return -1;
  return static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

int64_t ns_since_process_start() {
  // Field 22 of /proc/self/stat (after the parenthesised command name, which may hold spaces).
  std::ifstream f("/proc/self/stat");
  std::string s((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  const size_t close = s.rfind(')');
  if (close == std::string::npos) return -1;
  std::istringstream is(s.substr(close + 2));
  std::string field;
  unsigned long long start_ticks = 0;
  for (int i = 3; i <= 22; ++i) {
    if (!(is >> field)) return -1;
    if (i == 22) start_ticks = std::strtoull(field.c_str(), nullptr, 10);
  }
  const long hz = ::sysconf(_SC_CLK_TCK);
  if (hz <= 0) return -1;
  timespec ts{};
  if (::clock_gettime(CLOCK_BOOTTIME, &ts) != 0) return -1;
  const int64_t now_ns = static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
  const int64_t start_ns = static_cast<int64_t>(start_ticks) * (1'000'000'000 / hz);
  return now_ns - start_ns;
}

}  // namespace amb::hal::linux_hw
