#include "hal/linux/service_notify.hpp"

#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstddef>
#include <cstdlib>
#include <cstring>

namespace amb::hal::linux_hw {

namespace {
/// Parse a decimal unsigned number that is the whole string; false if it is not.
bool parse_u64(const char* s, uint64_t& v) {
  if (s == nullptr || *s == '\0') return false;
  char* end = nullptr;
  errno = 0;
  const unsigned long long x = std::strtoull(s, &end, 10);
  if (errno != 0 || end == nullptr || *end != '\0' || s[0] == '-') return false;
  v = x;
  return true;
}
}  // namespace

bool notify_service_manager(const std::string& state) {
  const char* path = std::getenv("NOTIFY_SOCKET");
  if (path == nullptr || (path[0] != '/' && path[0] != '@')) return false;
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  const size_t len = std::strlen(path);
  if (len >= sizeof addr.sun_path) return false;
  std::memcpy(addr.sun_path, path, len);
  if (path[0] == '@') addr.sun_path[0] = '\0';  // abstract namespace: no terminating NUL counted
  const socklen_t addr_len =
      static_cast<socklen_t>(offsetof(sockaddr_un, sun_path) + len + (path[0] == '@' ? 0 : 1));
  const int fd = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return false;
  const ssize_t n = ::sendto(fd, state.data(), state.size(), MSG_NOSIGNAL, reinterpret_cast<const sockaddr*>(&addr),
                             addr_len);
  ::close(fd);
  return n == static_cast<ssize_t>(state.size());
}

int64_t service_watchdog_ns() {
  uint64_t usec = 0, pid = 0;
  if (!parse_u64(std::getenv("WATCHDOG_USEC"), usec) || usec == 0) return 0;
  if (const char* p = std::getenv("WATCHDOG_PID"); p != nullptr) {
    if (!parse_u64(p, pid) || pid != static_cast<uint64_t>(::getpid())) return 0;
  }
  return static_cast<int64_t>(usec) * 1000;
}

}  // namespace amb::hal::linux_hw
