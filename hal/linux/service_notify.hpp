#pragma once
// The service manager's notification protocol (systemd's sd_notify, Type=notify and
// WatchdogSec=), implemented here so that the firmware does not load libsystemd and the
// libraries it pulls in (compression, crypto) only to send a datagram. Protocol: a datagram
// "KEY=value\n..." to the AF_UNIX socket named by $NOTIFY_SOCKET ('@' prefix: abstract
// namespace); the watchdog interval is $WATCHDOG_USEC, for the process $WATCHDOG_PID if set.
// Not for the loop thread: these are system calls.
#include <cstdint>
#include <string>

namespace amb::hal::linux_hw {

/// Send `state` (e.g. "READY=1", "WATCHDOG=1") to $NOTIFY_SOCKET. Returns true when sent,
/// false when there is no service manager to tell (no $NOTIFY_SOCKET) or the send failed.
bool notify_service_manager(const std::string& state);

/// The watchdog interval the service manager asks this process for, ns; 0 when none
/// ($WATCHDOG_USEC unset, invalid, or $WATCHDOG_PID names another process).
int64_t service_watchdog_ns();

}  // namespace amb::hal::linux_hw
