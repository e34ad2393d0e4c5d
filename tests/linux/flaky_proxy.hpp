#pragma once
// A TCP proxy on 127.0.0.1 (ephemeral port) that forwards to a target port and cuts every
// connection after `cut_after_bytes` bytes from the client, to test resumable transfers.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cstdint>
#include <thread>

namespace amb::test {

class FlakyProxy {
 public:
  FlakyProxy(uint16_t target_port, size_t cut_after_bytes) : target_(target_port), cut_(cut_after_bytes) {
    listen_ = ::socket(AF_INET, SOCK_STREAM, 0);
    const int on = 1;
    setsockopt(listen_, SOL_SOCKET, SO_REUSEADDR, &on, sizeof on);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ::bind(listen_, reinterpret_cast<sockaddr*>(&a), sizeof a);
    ::listen(listen_, 4);
    socklen_t len = sizeof a;
    getsockname(listen_, reinterpret_cast<sockaddr*>(&a), &len);
    port_ = ntohs(a.sin_port);
    thread_ = std::thread([this] { run(); });
  }
  ~FlakyProxy() {
    stop_ = true;
    thread_.join();
    ::close(listen_);
  }
  uint16_t port() const { return port_; }
  int cuts() const { return cuts_.load(); }

 private:
  void run() {
    while (!stop_) {
      pollfd p{listen_, POLLIN, 0};
      if (::poll(&p, 1, 50) <= 0) continue;
      const int c = ::accept(listen_, nullptr, nullptr);
      if (c < 0) continue;
      const int s = ::socket(AF_INET, SOCK_STREAM, 0);
      sockaddr_in a{};
      a.sin_family = AF_INET;
      a.sin_port = htons(target_);
      a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
      if (::connect(s, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
        ::close(c);
        ::close(s);
        continue;
      }
      size_t forwarded = 0;
      char buf[4096];
      bool open = true;
      while (open && !stop_) {
        pollfd f[2] = {{c, POLLIN, 0}, {s, POLLIN, 0}};
        if (::poll(f, 2, 50) <= 0) continue;
        for (int i = 0; i < 2 && open; ++i) {
          if (!(f[i].revents & (POLLIN | POLLHUP | POLLERR))) continue;
          const ssize_t n = ::recv(f[i].fd, buf, sizeof buf, 0);
          if (n <= 0) { open = false; break; }
          ::send(f[1 - i].fd, buf, static_cast<size_t>(n), MSG_NOSIGNAL);
          if (i == 0 && (forwarded += static_cast<size_t>(n)) >= cut_) {
            open = false;
            cuts_.fetch_add(1);
          }
        }
      }
      ::close(c);
      ::close(s);
    }
  }
  uint16_t target_;
  size_t cut_;
  int listen_ = -1;
  uint16_t port_ = 0;
  std::atomic<bool> stop_{false};
  std::atomic<int> cuts_{0};
  std::thread thread_;
};

}  // namespace amb::test
