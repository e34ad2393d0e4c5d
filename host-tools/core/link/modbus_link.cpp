#include "host-tools/core/link/modbus_link.hpp"

#include <modbus/modbus.h>

#include <cerrno>
#include <chrono>
#include <thread>

namespace amb::host::link {

uint64_t u64_at(std::span<const uint16_t> r, size_t at) {
  uint64_t v = 0;
  for (size_t i = 0; i < 4; ++i) v = v << 16 | r[at + i];
  return v;
}

std::string string_at(std::span<const uint16_t> r, size_t at, size_t regs_count) {
  std::string s;
  for (size_t i = 0; i < regs_count; ++i) {
    const char hi = static_cast<char>(r[at + i] >> 8), lo = static_cast<char>(r[at + i] & 0xFF);
    if (!hi) break;
    s += hi;
    if (!lo) break;
    s += lo;
  }
  return s;
}

ModbusLink::ModbusLink(LinkOptions options) : options_(std::move(options)) {}

ModbusLink::~ModbusLink() {
  drop();
  if (ctx_) modbus_free(static_cast<modbus_t*>(ctx_));
}

void ModbusLink::drop() {
  if (ctx_ && connected_) modbus_close(static_cast<modbus_t*>(ctx_));
  connected_ = false;
}

void ModbusLink::connect() {
  if (!ctx_) {
    modbus_t* ctx = modbus_new_tcp(options_.host.c_str(), options_.port);
    if (!ctx) throw LinkError("cannot create a Modbus TCP context for " + options_.host);
    modbus_set_slave(ctx, options_.unit_id);
    const auto us = static_cast<uint32_t>(options_.response_timeout_s * 1e6);
    modbus_set_response_timeout(ctx, us / 1'000'000, us % 1'000'000);
    ctx_ = ctx;
  }
  if (modbus_connect(static_cast<modbus_t*>(ctx_)) != 0)
    throw LinkError("cannot connect to " + options_.host + ":" + std::to_string(options_.port) + ": " +
                    modbus_strerror(errno));
  connected_ = true;
  if (connects_++ > 0) ++reconnects_;
}

template <typename F>
void ModbusLink::with_retry(const char* what, F&& op) {
  std::string last_error;
  for (int attempt = 0; attempt <= options_.max_retries; ++attempt) {
    if (attempt > 0)
      std::this_thread::sleep_for(std::chrono::duration<double>(options_.retry_delay_s));
    try {
      if (!connected_) connect();
    } catch (const LinkError& e) {
      last_error = e.what();
      continue;
    }
    ++requests_;
    if (op(static_cast<modbus_t*>(ctx_)) >= 0) return;
    const int err = errno;
    // An exception is the board's answer: report it, do not retry.
    if (err > MODBUS_ENOBASE && err < MODBUS_ENOBASE + MODBUS_EXCEPTION_MAX) {
      const int code = err - MODBUS_ENOBASE;
      throw ModbusException(code, std::string(what) + ": board answered Modbus exception " + std::to_string(code) +
                                      " (" + modbus_strerror(err) + ")");
    }
    last_error = modbus_strerror(err);
    drop();  // the stream may be out of step: start a fresh connection
  }
  throw LinkError(std::string(what) + ": gave up after " + std::to_string(options_.max_retries) +
                  " retries: " + last_error);
}

void ModbusLink::read(uint16_t address, std::span<uint16_t> out) {
  with_retry("read", [&](modbus_t* c) {
    return modbus_read_registers(c, address, static_cast<int>(out.size()), out.data()) == static_cast<int>(out.size()) ? 0 : -1;
  });
}

void ModbusLink::write(uint16_t address, std::span<const uint16_t> values) {
  with_retry("write", [&](modbus_t* c) {
    return modbus_write_registers(c, address, static_cast<int>(values.size()), values.data()) ==
                   static_cast<int>(values.size())
               ? 0
               : -1;
  });
}

void ModbusLink::write_read(uint16_t write_address, std::span<const uint16_t> values, uint16_t read_address,
                            std::span<uint16_t> out) {
  with_retry("write-read", [&](modbus_t* c) {
    return modbus_write_and_read_registers(c, write_address, static_cast<int>(values.size()), values.data(),
                                           read_address, static_cast<int>(out.size()), out.data()) ==
                   static_cast<int>(out.size())
               ? 0
               : -1;
  });
}

}  // namespace amb::host::link
