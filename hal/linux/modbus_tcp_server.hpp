#pragma once
// The supervisory link: a Modbus TCP server (libmodbus) in its own thread serving a
// hal::RegisterHandler. Several clients at once (select loop). Function codes served:
// 3 and 4 (read registers), 6 (write one), 16 (write many), 23 (write then read, one round
// trip). Anything else is answered with exception 1 (illegal function); bad frames (wrong
// protocol id, a length field outside the protocol's range, a request not complete within
// request_timeout_ms of its first byte) are counted and the connection closed. The server never
// waits on one client: it reads what each connection has sent and answers complete requests,
// so a slow or hostile client cannot hold up the others.
// The loop thread is never touched: the handler exchanges data with it lock-free.
#include <atomic>
#include <cstdint>
#include <string>
#include <thread>

#include "hal/interfaces.hpp"

namespace amb::hal::linux_hw {

struct ModbusTcpOptions {
  std::string bind_address = "127.0.0.1";  ///< IPv4 address to listen on (default: loopback only)
  uint16_t port = 502;                   ///< TCP port (0: ephemeral, see bound_port())
  uint8_t unit_id = 1;                   ///< unit answered; 0 and 255 are accepted too
  int max_clients = 4;                   ///< simultaneous connections, further ones are refused
  int request_timeout_ms = 1000;         ///< a started request must complete within this, ms
};

/// Counters of the server (any thread).
struct ModbusServerStats {
  uint64_t connections = 0;       ///< accepted since start
  uint64_t refused_connections = 0;
  uint64_t requests = 0;          ///< well-formed requests answered
  uint64_t exceptions = 0;        ///< of which answered with a Modbus exception
  uint64_t bad_frames = 0;        ///< malformed frames (connection closed)
  uint64_t wrong_unit = 0;        ///< requests to another unit id (exception 0x0B)
};

class ModbusTcpServer final : public SupervisoryServer {
 public:
  explicit ModbusTcpServer(ModbusTcpOptions options) : options_(std::move(options)) {}
  ~ModbusTcpServer() override { stop(); }

  bool start(RegisterHandler& handler, std::string& error) override;
  void stop() override;
  /// The port actually listened on (useful with port 0).
  uint16_t bound_port() const { return bound_port_; }
  ModbusServerStats stats() const;

 private:
  void serve(RegisterHandler& handler);
  ModbusTcpOptions options_;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  int listen_fd_ = -1;
  uint16_t bound_port_ = 0;
  void* ctx_ = nullptr;  // modbus_t*
  std::atomic<uint64_t> connections_{0}, refused_{0}, requests_{0}, exceptions_{0}, bad_frames_{0}, wrong_unit_{0};
};

}  // namespace amb::hal::linux_hw
