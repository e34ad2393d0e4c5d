#pragma once
// Host side of the supervisory link: a Modbus TCP client (libmodbus) that survives dropped
// connections. Every register operation is retried after reconnecting, up to a bound; Modbus
// exceptions from the board are not retried (they are answers). Register addresses:
// firmware/supervisory/register_addresses.hpp.
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace amb::host::link {

struct LinkOptions {
  std::string host = "127.0.0.1";  ///< board address
  int port = 502;                  ///< Modbus TCP port
  int unit_id = 1;                 ///< Modbus unit id of the board
  double response_timeout_s = 2.0; ///< per request, s
  int max_retries = 30;            ///< consecutive failed attempts before giving up
  double retry_delay_s = 0.2;      ///< wait before reconnecting, s
};

/// The link failed for good (retries exhausted).
class LinkError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The board answered with a Modbus exception.
class ModbusException : public std::runtime_error {
 public:
  ModbusException(int code, const std::string& what) : std::runtime_error(what), code_(code) {}
  int code() const { return code_; }  ///< 1 illegal function, 2 address, 3 value, 4 failure, 6 busy

 private:
  int code_;
};

class ModbusLink {
 public:
  explicit ModbusLink(LinkOptions options);
  ~ModbusLink();
  ModbusLink(const ModbusLink&) = delete;
  ModbusLink& operator=(const ModbusLink&) = delete;

  /// Read `out.size()` (<= 125) holding registers at `address`.
  void read(uint16_t address, std::span<uint16_t> out);
  /// Write `values` (<= 123) at `address`.
  void write(uint16_t address, std::span<const uint16_t> values);
  /// Write then read in one transaction (function 23).
  void write_read(uint16_t write_address, std::span<const uint16_t> values, uint16_t read_address,
                  std::span<uint16_t> out);

  int reconnects() const { return reconnects_; }
  uint64_t requests() const { return requests_; }
  const LinkOptions& options() const { return options_; }

 private:
  template <typename F>
  void with_retry(const char* what, F&& op);
  void connect();
  void drop();
  LinkOptions options_;
  void* ctx_ = nullptr;  // modbus_t*
  bool connected_ = false;
  int reconnects_ = 0;
  int connects_ = 0;
  uint64_t requests_ = 0;
};

/// Helpers for the register encoding (most significant word first).
inline uint32_t u32_at(std::span<const uint16_t> r, size_t at) { return static_cast<uint32_t>(r[at]) << 16 | r[at + 1]; }
uint64_t u64_at(std::span<const uint16_t> r, size_t at);
std::string string_at(std::span<const uint16_t> r, size_t at, size_t regs_count);

}  // namespace amb::host::link
