#include "hal/linux/modbus_tcp_server.hpp"

#include <arpa/inet.h>
#include <modbus/modbus.h>
#include <netinet/in.h>
#include <sys/select.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <ctime>
#include <vector>

namespace amb::hal::linux_hw {

namespace {

constexpr int k_fc_read_holding = 3, k_fc_read_input = 4, k_fc_write_single = 6, k_fc_write_multiple = 16,
              k_fc_write_read = 23;
constexpr int k_max_read = 125, k_max_write = 123, k_max_write_read_write = 121;
constexpr int k_exception_gateway_target = 0x0B;

uint16_t be16(const uint8_t* p) { return static_cast<uint16_t>((p[0] << 8) | p[1]); }

}  // namespace

bool ModbusTcpServer::start(RegisterHandler& handler, std::string& error) {
  stop();
  modbus_t* ctx = modbus_new_tcp(options_.bind_address.c_str(), options_.port);
  if (!ctx) {
    error = std::string("modbus_new_tcp: ") + modbus_strerror(errno);
    return false;
  }
  listen_fd_ = modbus_tcp_listen(ctx, options_.max_clients);
  if (listen_fd_ < 0) {
    error = "cannot listen on " + options_.bind_address + ":" + std::to_string(options_.port) + ": " +
            modbus_strerror(errno);
    modbus_free(ctx);
    return false;
  }
  sockaddr_in a{};
  socklen_t len = sizeof a;
  getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&a), &len);
  bound_port_ = ntohs(a.sin_port);
  ctx_ = ctx;
  stop_.store(false);
  thread_ = std::thread([this, &handler] { serve(handler); });
  return true;
}

void ModbusTcpServer::stop() {
  stop_.store(true);
  if (thread_.joinable()) thread_.join();
  if (listen_fd_ >= 0) ::close(listen_fd_);
  listen_fd_ = -1;
  if (ctx_) modbus_free(static_cast<modbus_t*>(ctx_));
  ctx_ = nullptr;
}

ModbusServerStats ModbusTcpServer::stats() const {
  ModbusServerStats s;
  s.connections = connections_.load(std::memory_order_relaxed);
  s.refused_connections = refused_.load(std::memory_order_relaxed);
  s.requests = requests_.load(std::memory_order_relaxed);
  s.exceptions = exceptions_.load(std::memory_order_relaxed);
  s.bad_frames = bad_frames_.load(std::memory_order_relaxed);
  s.wrong_unit = wrong_unit_.load(std::memory_order_relaxed);
  return s;
}

namespace {

/// One client connection and the bytes of its next request received so far.
struct Client {
  int fd = -1;
  std::array<uint8_t, MODBUS_TCP_MAX_ADU_LENGTH> buf{};
  size_t n = 0;              ///< bytes buffered
  int64_t started_ns = 0;    ///< when the first byte of the buffered request arrived
};

int64_t mono_ns() {
  timespec ts{};
  ::clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

}  // namespace

void ModbusTcpServer::serve(RegisterHandler& handler) {
  auto* ctx = static_cast<modbus_t*>(ctx_);
  // One mapping covering the whole address space, allocated once: modbus_reply() formats
  // the answer from it after the handler has filled the requested range.
  modbus_mapping_t* map = modbus_mapping_new(0, 0, 0x10000, 0x10000);
  std::vector<Client> clients;
  std::array<uint16_t, k_max_read> scratch{};
  const int header = modbus_get_header_length(ctx);  // 7 (MBAP) for TCP
  const int64_t request_timeout_ns = static_cast<int64_t>(options_.request_timeout_ms) * 1'000'000;
  const uint8_t* req = nullptr;  // the request being answered (inside a client's buffer)

  auto reply_exception = [&](int code) {
    modbus_reply_exception(ctx, req, static_cast<unsigned>(code));
    exceptions_.fetch_add(1, std::memory_order_relaxed);
  };
  auto do_read = [&](int fc, uint16_t addr, int count) -> int {
    if (count < 1 || count > k_max_read) return RegisterHandler::illegal_value;
    if (addr + count > 0x10000) return RegisterHandler::illegal_address;
    const auto st = handler.read_registers(addr, std::span<uint16_t>(scratch.data(), static_cast<size_t>(count)));
    if (st != RegisterHandler::ok) return st;
    uint16_t* dst = (fc == k_fc_read_input ? map->tab_input_registers : map->tab_registers) + addr;
    std::copy_n(scratch.begin(), count, dst);
    return RegisterHandler::ok;
  };
  auto do_write = [&](uint16_t addr, int count, const uint8_t* bytes, int max) -> int {
    if (count < 1 || count > max) return RegisterHandler::illegal_value;
    if (addr + count > 0x10000) return RegisterHandler::illegal_address;
    for (int i = 0; i < count; ++i) scratch[static_cast<size_t>(i)] = be16(bytes + 2 * i);
    return handler.write_registers(addr, std::span<const uint16_t>(scratch.data(), static_cast<size_t>(count)));
  };
  // Answer one complete request of `rc` bytes at `req` on the current socket.
  auto answer = [&](int rc) {
    const uint8_t unit = req[static_cast<size_t>(header - 1)];
    const int fc = req[static_cast<size_t>(header)];
    const uint8_t* body = &req[static_cast<size_t>(header + 1)];
    const int body_len = rc - header - 1;
    requests_.fetch_add(1, std::memory_order_relaxed);
    if (unit != options_.unit_id && unit != 0 && unit != 0xFF) {
      wrong_unit_.fetch_add(1, std::memory_order_relaxed);
      reply_exception(k_exception_gateway_target);
      return;
    }
    int st = RegisterHandler::ok;
    switch (fc) {
      case k_fc_read_holding:
      case k_fc_read_input:
        st = body_len < 4 ? RegisterHandler::illegal_value : do_read(fc, be16(body), be16(body + 2));
        break;
      case k_fc_write_single:
        st = body_len < 4 ? RegisterHandler::illegal_value : do_write(be16(body), 1, body + 2, 1);
        break;
      case k_fc_write_multiple: {
        const int count = body_len >= 5 ? be16(body + 2) : 0;
        if (body_len < 5 || body[4] != 2 * count || body_len != 5 + 2 * count) st = RegisterHandler::illegal_value;
        else st = do_write(be16(body), count, body + 5, k_max_write);
        break;
      }
      case k_fc_write_read: {
        const int wcount = body_len >= 9 ? be16(body + 6) : 0;
        if (body_len < 9 || body[8] != 2 * wcount || body_len != 9 + 2 * wcount) {
          st = RegisterHandler::illegal_value;
          break;
        }
        // The specification performs the write before the read.
        st = do_write(be16(body + 4), wcount, body + 9, k_max_write_read_write);
        if (st == RegisterHandler::ok) st = do_read(k_fc_read_holding, be16(body), be16(body + 2));
        break;
      }
      default:
        st = RegisterHandler::illegal_function;
    }
    if (st != RegisterHandler::ok) reply_exception(st);
    else modbus_reply(ctx, req, rc, map);
  };
  // Take what a client sent (never blocks: one recv of what is there) and answer every
  // complete request in it. False: close the connection (closed by the peer, or a frame that
  // cannot be resynchronised: protocol id != 0, a length outside 2..254).
  auto service = [&](Client& cl) -> bool {
    const ssize_t r = ::recv(cl.fd, cl.buf.data() + cl.n, cl.buf.size() - cl.n, MSG_DONTWAIT);
    if (r == 0) return false;
    if (r < 0) {
      if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) return true;
      if (errno != ECONNRESET && errno != EPIPE) bad_frames_.fetch_add(1, std::memory_order_relaxed);
      return false;
    }
    if (cl.n == 0) cl.started_ns = mono_ns();
    cl.n += static_cast<size_t>(r);
    while (cl.n >= static_cast<size_t>(header)) {
      const int len = be16(&cl.buf[4]);
      if (be16(&cl.buf[2]) != 0 || len < 2 || len > MODBUS_TCP_MAX_ADU_LENGTH - 6) {
        bad_frames_.fetch_add(1, std::memory_order_relaxed);
        return false;
      }
      const size_t total = 6 + static_cast<size_t>(len);
      if (cl.n < total) break;
      modbus_set_socket(ctx, cl.fd);
      req = cl.buf.data();
      answer(static_cast<int>(total));
      std::memmove(cl.buf.data(), cl.buf.data() + total, cl.n - total);
      cl.n -= total;
      cl.started_ns = mono_ns();
    }
    return true;
  };

  while (!stop_.load()) {
    fd_set rd;
    FD_ZERO(&rd);
    FD_SET(listen_fd_, &rd);
    int maxfd = listen_fd_;
    for (const Client& c : clients) {
      FD_SET(c.fd, &rd);
      maxfd = std::max(maxfd, c.fd);
    }
    timeval tv{0, 100'000};  // wake up to see stop_ and request timeouts
    const int n = ::select(maxfd + 1, &rd, nullptr, nullptr, &tv);
    if (n > 0 && FD_ISSET(listen_fd_, &rd)) {
      const int c = ::accept4(listen_fd_, nullptr, nullptr, SOCK_CLOEXEC);
      if (c >= 0) {
        if (static_cast<int>(clients.size()) >= options_.max_clients) {
          ::close(c);
          refused_.fetch_add(1, std::memory_order_relaxed);
        } else {
          clients.push_back(Client{});
          clients.back().fd = c;
          connections_.fetch_add(1, std::memory_order_relaxed);
        }
      }
    }
    // A request must arrive whole within request_timeout_ms of its first byte: a client that
    // sends part of a frame and waits (slow or hostile) is closed, and never holds up the
    // others (the server reads only what is there, it never waits on one client).
    const int64_t now = mono_ns();
    for (size_t i = 0; i < clients.size();) {
      Client& c = clients[i];
      bool keep = true;
      if (n > 0 && FD_ISSET(c.fd, &rd)) keep = service(c);
      if (keep && c.n > 0 && now - c.started_ns > request_timeout_ns) {
        bad_frames_.fetch_add(1, std::memory_order_relaxed);
        keep = false;
      }
      if (!keep) {
        ::close(c.fd);
        clients.erase(clients.begin() + static_cast<long>(i));
        continue;
      }
      ++i;
    }
  }
  for (const Client& c : clients) ::close(c.fd);
  modbus_set_socket(ctx, -1);
  modbus_mapping_free(map);
}

}  // namespace amb::hal::linux_hw
