#include "hal/linux/socketcan_bus.hpp"

#include <linux/can.h>
#include <linux/can/error.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "hal/linux/linux_clock.hpp"

namespace amb::hal::linux_hw {

SocketCanBus::~SocketCanBus() { close(); }

void SocketCanBus::close() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

bool SocketCanBus::open(const SocketCanOptions& o, std::string& error) {
  close();
  auto fail = [&](const std::string& what) {
    error = what + " (" + o.interface + "): " + std::strerror(errno);
    close();
    return false;
  };
  fd_ = ::socket(PF_CAN, SOCK_RAW | SOCK_CLOEXEC, CAN_RAW);
  if (fd_ < 0) return fail("cannot create a CAN_RAW socket");
  ifreq ifr{};
  if (o.interface.size() >= IFNAMSIZ) {
    errno = ENAMETOOLONG;
    return fail("interface name too long");
  }
  std::strncpy(ifr.ifr_name, o.interface.c_str(), IFNAMSIZ - 1);
  if (::ioctl(fd_, SIOCGIFINDEX, &ifr) < 0) return fail("no such CAN interface");
  fd_mode_ = o.fd;
  if (o.fd) {
    const int on = 1;
    if (::setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_FD_FRAMES, &on, sizeof on) < 0)
      return fail("interface does not support CAN FD");
  }
  if (!o.filters.empty()) {
    std::vector<can_filter> f;
    for (const CanFilter& c : o.filters) {
      can_filter k{};
      k.can_id = c.extended ? (c.id & CAN_EFF_MASK) | CAN_EFF_FLAG : (c.id & CAN_SFF_MASK);
      k.can_mask = (c.extended ? (c.mask & CAN_EFF_MASK) : (c.mask & CAN_SFF_MASK)) | CAN_EFF_FLAG | CAN_RTR_FLAG;
      f.push_back(k);
    }
    if (::setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_FILTER, f.data(), static_cast<socklen_t>(f.size() * sizeof(can_filter))) < 0)
      return fail("cannot install receive filters");
  }
  // Error frames: bus-off, controller state (passive/warning/overflow), protocol violations,
  // transceiver, missing ACK, restart after bus-off.
  const can_err_mask_t err_mask = CAN_ERR_TX_TIMEOUT | CAN_ERR_LOSTARB | CAN_ERR_CRTL | CAN_ERR_PROT |
                                  CAN_ERR_TRX | CAN_ERR_ACK | CAN_ERR_BUSOFF | CAN_ERR_BUSERROR |
                                  CAN_ERR_RESTARTED;
  if (::setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_ERR_FILTER, &err_mask, sizeof err_mask) < 0)
    return fail("cannot set the error-frame mask");
  const int own = o.receive_own ? 1 : 0;
  ::setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_RECV_OWN_MSGS, &own, sizeof own);
  // The kernel reports its receive-queue drops with every message (SO_RXQ_OVFL).
  const int on = 1;
  ::setsockopt(fd_, SOL_SOCKET, SO_RXQ_OVFL, &on, sizeof on);
  if (o.rx_buffer_bytes > 0)
    ::setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &o.rx_buffer_bytes, sizeof o.rx_buffer_bytes);
  sockaddr_can addr{};
  addr.can_family = AF_CAN;
  addr.can_ifindex = ifr.ifr_ifindex;
  if (::bind(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) < 0) return fail("cannot bind");
  bus_off_restart_ns_ = o.bus_off_restart_ns;
  bus_off_.store(false);
  return true;
}

bool SocketCanBus::send(const CanFrame& f) {
  if (fd_ < 0 || f.len > (f.fd ? CANFD_MAX_DLEN : CAN_MAX_DLEN) || (f.fd && !fd_mode_)) {
    tx_dropped_.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  if (bus_off_.load(std::memory_order_relaxed)) {
    // While bus-off the controller cannot send; the kernel (restart-ms) or the CAN_ERR_RESTARTED
    // frame ends it. Retry after the hold in case no restart frame comes (e.g. virtual buses).
    if (monotonic_ns() - bus_off_since_ns_ < bus_off_restart_ns_) {
      tx_dropped_.fetch_add(1, std::memory_order_relaxed);
      return false;
    }
    bus_off_.store(false, std::memory_order_relaxed);
  }
  canfd_frame k{};
  k.can_id = f.extended ? (f.id & CAN_EFF_MASK) | CAN_EFF_FLAG : (f.id & CAN_SFF_MASK);
  k.len = f.len;
  std::memcpy(k.data, f.data.data(), f.len);
  const size_t size = f.fd ? CANFD_MTU : CAN_MTU;
  const ssize_t n = ::send(fd_, &k, size, MSG_DONTWAIT);
  if (n != static_cast<ssize_t>(size)) {
    tx_dropped_.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  tx_frames_.fetch_add(1, std::memory_order_relaxed);
  return true;
}

bool SocketCanBus::receive(CanFrame& f) {
  if (fd_ < 0) return false;
  canfd_frame k{};
  iovec iov{&k, sizeof k};
  alignas(cmsghdr) char control[CMSG_SPACE(sizeof(uint32_t)) + 64];
  msghdr msg{};
  msg.msg_iov = &iov;
  msg.msg_iovlen = 1;
  msg.msg_control = control;
  msg.msg_controllen = sizeof control;
  const ssize_t n = ::recvmsg(fd_, &msg, MSG_DONTWAIT);
  if (n < 0) return false;  // EAGAIN: nothing waiting
  for (cmsghdr* c = CMSG_FIRSTHDR(&msg); c; c = CMSG_NXTHDR(&msg, c)) {
    if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SO_RXQ_OVFL) {
      uint32_t dropped = 0;
      std::memcpy(&dropped, CMSG_DATA(c), sizeof dropped);
      if (dropped != last_overflow_count_) {
        rx_dropped_.fetch_add(dropped - last_overflow_count_, std::memory_order_relaxed);
        last_overflow_count_ = dropped;
      }
    }
  }
  if (n != CAN_MTU && n != CANFD_MTU) {
    malformed_.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  f.fd = (n == CANFD_MTU);
  f.error = (k.can_id & CAN_ERR_FLAG) != 0;
  f.extended = (k.can_id & CAN_EFF_FLAG) != 0;
  f.id = k.can_id & (f.error ? CAN_ERR_MASK : (f.extended ? CAN_EFF_MASK : CAN_SFF_MASK));
  f.len = k.len > (f.fd ? CANFD_MAX_DLEN : CAN_MAX_DLEN) ? 0 : k.len;
  std::memcpy(f.data.data(), k.data, f.len);
  if (f.error) {
    error_frames_.fetch_add(1, std::memory_order_relaxed);
    if (f.id & CAN_ERR_BUSOFF) {
      bus_off_events_.fetch_add(1, std::memory_order_relaxed);
      bus_off_since_ns_ = monotonic_ns();
      bus_off_.store(true, std::memory_order_relaxed);
    }
    if (f.id & CAN_ERR_RESTARTED) bus_off_.store(false, std::memory_order_relaxed);
  } else {
    rx_frames_.fetch_add(1, std::memory_order_relaxed);
  }
  return true;
}

CanStats SocketCanBus::stats() const {
  CanStats s;
  s.tx_frames = tx_frames_.load(std::memory_order_relaxed);
  s.rx_frames = rx_frames_.load(std::memory_order_relaxed);
  s.tx_dropped = tx_dropped_.load(std::memory_order_relaxed);
  s.rx_dropped = rx_dropped_.load(std::memory_order_relaxed);
  s.error_frames = error_frames_.load(std::memory_order_relaxed);
  s.bus_off_events = bus_off_events_.load(std::memory_order_relaxed);
  s.malformed = malformed_.load(std::memory_order_relaxed);
  return s;
}

}  // namespace amb::hal::linux_hw
