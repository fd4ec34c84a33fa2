#include "porter/can/socketcan_bus.hpp"

#include <cerrno>
#include <cstring>

#include <linux/can.h>
#include <linux/can/error.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include "porter/can/can_error.hpp"

namespace porter::can {
namespace {

std::string no_kernel_support(int err) {
  return std::string("this kernel has no SocketCAN support (socket(PF_CAN, SOCK_RAW, CAN_RAW) "
                     "failed: ") +
         std::strerror(err) +
         "); load the can and can_raw kernel modules (modprobe can_raw; vcan for a virtual bus) "
         "or use an slcan: or lcm: bus";
}

bool is_missing_support(int err) {
  return err == EAFNOSUPPORT || err == EPROTONOSUPPORT || err == ESOCKTNOSUPPORT;
}

}  // namespace

bool socketcan_supported(std::string& reason) {
  const int fd = ::socket(PF_CAN, SOCK_RAW | SOCK_CLOEXEC, CAN_RAW);
  if (fd < 0) {
    reason = is_missing_support(errno) ? no_kernel_support(errno)
                                       : std::string("socket(PF_CAN) failed: ") +
                                             std::strerror(errno);
    return false;
  }
  ::close(fd);
  reason.clear();
  return true;
}

std::unique_ptr<SocketCanBus> SocketCanBus::open(const std::string& interface_name) {
  std::unique_ptr<SocketCanBus> bus(new SocketCanBus(interface_name));
  const std::string self = bus->describe();
  if (interface_name.empty() || interface_name.size() >= IFNAMSIZ) {
    bus->set_error(self + ": '" + interface_name + "' is not a network interface name");
    return bus;
  }
  const int fd = ::socket(PF_CAN, SOCK_RAW | SOCK_CLOEXEC, CAN_RAW);
  if (fd < 0) {
    const int err = errno;
    bus->set_error(self + ": " +
                   (is_missing_support(err) ? no_kernel_support(err)
                                            : std::string("socket(PF_CAN) failed: ") +
                                                  std::strerror(err)));
    return bus;
  }
  const unsigned int index = ::if_nametoindex(interface_name.c_str());
  if (index == 0) {
    bus->set_error(self + ": no network interface '" + interface_name +
                   "' (ip link show; a virtual bus: ip link add dev vcan0 type vcan && "
                   "ip link set up vcan0)");
    ::close(fd);
    return bus;
  }
  const can_err_mask_t err_mask = CAN_ERR_MASK;
  const int on = 1;
  if (::setsockopt(fd, SOL_CAN_RAW, CAN_RAW_ERR_FILTER, &err_mask, sizeof err_mask) != 0 ||
      ::setsockopt(fd, SOL_SOCKET, SO_TIMESTAMP, &on, sizeof on) != 0) {
    bus->set_error(self + ": setsockopt failed: " + std::strerror(errno));
    ::close(fd);
    return bus;
  }
  sockaddr_can addr{};
  addr.can_family = AF_CAN;
  addr.can_ifindex = static_cast<int>(index);
  if (::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    bus->set_error(self + ": bind to '" + interface_name + "' failed: " + std::strerror(errno));
    ::close(fd);
    return bus;
  }
  bus->fd_ = fd;
  return bus;
}

SocketCanBus::~SocketCanBus() {
  if (fd_ >= 0) ::close(fd_);
}

CanStatus SocketCanBus::send(const CanFrame& frame) {
  if (fd_ < 0) return CanStatus::closed;
  if (!frame.valid()) return CanStatus::invalid_frame;
  can_frame raw{};
  raw.can_id = frame.id | (frame.extended ? CAN_EFF_FLAG : 0u) | (frame.rtr ? CAN_RTR_FLAG : 0u);
  raw.can_dlc = frame.dlc;
  std::memcpy(raw.data, frame.data.data(), frame.dlc);
  for (;;) {
    const ssize_t n = ::send(fd_, &raw, sizeof raw, MSG_DONTWAIT);
    if (n == static_cast<ssize_t>(sizeof raw)) return CanStatus::ok;
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == ENOBUFS || errno == EAGAIN)) return CanStatus::tx_full;
    set_error(describe() + ": send failed: " +
              (n < 0 ? std::string(std::strerror(errno)) : std::string("short write")) +
              (n < 0 && errno == ENETDOWN ? " (ip link set " + interface_ + " up)" : ""));
    return CanStatus::io_error;
  }
}

CanStatus SocketCanBus::receive(CanFrame& frame, int timeout_ms) {
  if (fd_ < 0) return CanStatus::closed;
  for (;;) {
    pollfd p{fd_, POLLIN, 0};
    const int ready = ::poll(&p, 1, timeout_ms < 0 ? -1 : timeout_ms);
    if (ready < 0 && errno == EINTR) continue;
    if (ready < 0) {
      set_error(describe() + ": poll failed: " + std::strerror(errno));
      return CanStatus::io_error;
    }
    if (ready == 0) return CanStatus::timeout;
    can_frame raw{};
    iovec iov{&raw, sizeof raw};
    alignas(cmsghdr) char control[CMSG_SPACE(sizeof(timeval))];
    msghdr msg{};
    msg.msg_iov = &iov;
    msg.msg_iovlen = 1;
    msg.msg_control = control;
    msg.msg_controllen = sizeof control;
    const ssize_t n = ::recvmsg(fd_, &msg, MSG_DONTWAIT);
    if (n < 0 && (errno == EAGAIN || errno == EINTR)) continue;
    if (n < 0) {
      set_error(describe() + ": receive failed: " + std::strerror(errno));
      return CanStatus::io_error;
    }
    if (n != static_cast<ssize_t>(sizeof raw)) {
      set_error(describe() + ": skipped a truncated frame (" + std::to_string(n) + " bytes)");
      continue;
    }
    frame = CanFrame{};
    for (cmsghdr* c = CMSG_FIRSTHDR(&msg); c != nullptr; c = CMSG_NXTHDR(&msg, c)) {
      if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SO_TIMESTAMP) {
        timeval tv{};
        std::memcpy(&tv, CMSG_DATA(c), sizeof tv);
        frame.utime = static_cast<std::int64_t>(tv.tv_sec) * 1000000 + tv.tv_usec;
      }
    }
    frame.dlc = raw.can_dlc > 8 ? 8 : raw.can_dlc;
    std::memcpy(frame.data.data(), raw.data, frame.dlc);
    if ((raw.can_id & CAN_ERR_FLAG) != 0) {
      frame.id = raw.can_id & CAN_ERR_MASK;
      frame.extended = true;
      const ControllerError e = decode_error_frame(frame);
      set_error(describe() + ": " + e.text);
      return e.bus_off ? CanStatus::bus_off : CanStatus::error_frame;
    }
    frame.extended = (raw.can_id & CAN_EFF_FLAG) != 0;
    frame.rtr = (raw.can_id & CAN_RTR_FLAG) != 0;
    frame.id = raw.can_id & (frame.extended ? CAN_EFF_MASK : CAN_SFF_MASK);
    return CanStatus::ok;
  }
}

std::string SocketCanBus::last_error() const {
  std::lock_guard<std::mutex> lock(error_mutex_);
  return error_;
}

void SocketCanBus::set_error(std::string error) {
  std::lock_guard<std::mutex> lock(error_mutex_);
  error_ = std::move(error);
}

}  // namespace porter::can
