// The Linux pieces of the board budget (hal/linux): the service-manager notification without
// libsystemd, the process memory set-up (thread stack size, malloc bounds), /proc memory
// figures and per-thread CPU clocks.
#include <gtest/gtest.h>
#include <pthread.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <time.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>

#include "hal/linux/process_memory.hpp"
#include "hal/linux/service_notify.hpp"
#include "tests/support/sanitizer_build.hpp"

using namespace amb::hal::linux_hw;

namespace {
int64_t own_cpu_ns() {
  timespec ts{};
  ::clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}
// A sanitizer build (ASan, TSan) brings its own allocator, which need not honour mallopt.
constexpr bool k_sanitizer_owns_malloc = AMB_SANITIZER_BUILD;

/// A datagram socket bound to `path` ('@': abstract); returns the fd.
int bind_dgram(const std::string& path) {
  const int fd = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  sockaddr_un a{};
  a.sun_family = AF_UNIX;
  std::memcpy(a.sun_path, path.data(), path.size());
  socklen_t len = static_cast<socklen_t>(offsetof(sockaddr_un, sun_path) + path.size());
  if (path[0] == '@') a.sun_path[0] = '\0';
  else {
    ::unlink(path.c_str());
    len += 1;
  }
  EXPECT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&a), len), 0) << path;
  return fd;
}
std::string receive(int fd) {
  char buf[256];
  const ssize_t n = ::recv(fd, buf, sizeof buf, MSG_DONTWAIT);
  return n > 0 ? std::string(buf, static_cast<size_t>(n)) : std::string();
}
}  // namespace

TEST(ServiceNotify, SendsTheStateToNotifySocketPathAndAbstract) {
  ::unsetenv("NOTIFY_SOCKET");
  EXPECT_FALSE(notify_service_manager("READY=1"));  // no service manager: nothing sent, no error
  const std::string path = "/tmp/amb-notify-test-" + std::to_string(::getpid());
  const int fd = bind_dgram(path);
  ::setenv("NOTIFY_SOCKET", path.c_str(), 1);
  EXPECT_TRUE(notify_service_manager("READY=1\nSTATUS=loop running"));
  EXPECT_EQ(receive(fd), "READY=1\nSTATUS=loop running");
  ::close(fd);
  ::unlink(path.c_str());
  const std::string abstract = "@amb-notify-test-" + std::to_string(::getpid());
  const int fa = bind_dgram(abstract);
  ::setenv("NOTIFY_SOCKET", abstract.c_str(), 1);
  EXPECT_TRUE(notify_service_manager("WATCHDOG=1"));
  EXPECT_EQ(receive(fa), "WATCHDOG=1");
  ::close(fa);
  ::setenv("NOTIFY_SOCKET", "relative/path", 1);  // neither absolute nor abstract: refused
  EXPECT_FALSE(notify_service_manager("READY=1"));
  ::unsetenv("NOTIFY_SOCKET");
}

TEST(ServiceNotify, WatchdogIntervalOnlyForThisProcess) {
  ::unsetenv("WATCHDOG_PID");
  ::setenv("WATCHDOG_USEC", "5000000", 1);
  EXPECT_EQ(service_watchdog_ns(), 5'000'000'000);
  ::setenv("WATCHDOG_PID", std::to_string(::getpid()).c_str(), 1);
  EXPECT_EQ(service_watchdog_ns(), 5'000'000'000);
  ::setenv("WATCHDOG_PID", std::to_string(::getpid() + 1).c_str(), 1);  // meant for another process
  EXPECT_EQ(service_watchdog_ns(), 0);
  ::unsetenv("WATCHDOG_PID");
  for (const char* bad : {"", "5s", "-1", "0"}) {
    ::setenv("WATCHDOG_USEC", bad, 1);
    EXPECT_EQ(service_watchdog_ns(), 0) << bad;
  }
  ::unsetenv("WATCHDOG_USEC");
}

TEST(ProcessMemory, ThreadsGetTheConfiguredStackSize) {
  pthread_attr_t old;
  ASSERT_EQ(::pthread_getattr_default_np(&old), 0);
  ProcessMemoryOptions o;
  o.thread_stack_bytes = 384 * 1024;
  const ProcessMemoryReport r = configure_process_memory(o);
  EXPECT_TRUE(r.stack_size_set) << r.warnings;
  if (k_sanitizer_owns_malloc) {
    // ASan's allocator replaces glibc's and refuses mallopt: that must be said, not claimed done.
    if (!r.malloc_bounded) {
      EXPECT_NE(r.warnings.find("mallopt"), std::string::npos) << r.warnings;
    }
  } else {
    EXPECT_TRUE(r.malloc_bounded) << r.warnings;
  }
  size_t stack = 0;
  std::thread t([&] {
    pthread_attr_t a;
    ::pthread_getattr_np(::pthread_self(), &a);
    ::pthread_attr_getstacksize(&a, &stack);
    ::pthread_attr_destroy(&a);
  });
  t.join();
  EXPECT_EQ(stack, 384u * 1024u);
  ::pthread_setattr_default_np(&old);  // leave the test process as it was
  ::pthread_attr_destroy(&old);
}

TEST(ProcessMemory, ProcFiguresAndThreadCpuClock) {
  const ProcessMemory m = read_process_memory();
  EXPECT_GT(m.resident_kb, 0u);
  EXPECT_GE(m.peak_resident_kb, m.resident_kb);
  EXPECT_GE(m.virtual_kb, m.resident_kb);
  // A thread that burns 100 ms of its own CPU time: read from outside, its clock shows at
  // least that, and no more than the wall time it existed.
  std::atomic<bool> burnt{false}, release{false};
  const auto w0 = std::chrono::steady_clock::now();
  std::thread t([&] {
    const int64_t c0 = own_cpu_ns();
    while (own_cpu_ns() - c0 < 100'000'000) {
    }
    burnt = true;
    while (!release) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  });
  while (!burnt) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  const int64_t cpu = thread_cpu_ns(t.native_handle());
  const int64_t wall = std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - w0).count();
  release = true;
  t.join();
  EXPECT_GE(cpu, 100'000'000);
  EXPECT_LE(cpu, wall);
  const int64_t up = ns_since_process_start();
  EXPECT_GT(up, 0);
  EXPECT_LT(up, int64_t{3600} * 1'000'000'000);  // this test process started less than an hour ago
}
