#include "porter/livox/udp.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <algorithm>
#include <cstring>
#include <ctime>
#include <utility>

namespace porter::livox {
namespace {

std::string errno_text(const std::string& what) { return what + ": " + std::strerror(errno); }

bool parse_address(const std::string& address, std::uint16_t port, sockaddr_in& out) {
  std::memset(&out, 0, sizeof out);
  out.sin_family = AF_INET;
  out.sin_port = htons(port);
  return ::inet_pton(AF_INET, address.c_str(), &out.sin_addr) == 1;
}

std::int64_t realtime_ns() {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1000000000 + ts.tv_nsec;
}

constexpr int kMaxBatch = 64;

}  // namespace

std::optional<UdpReceiver> UdpReceiver::open(const std::string& address, std::uint16_t port,
                                             int receive_buffer_bytes, std::string& error) {
  const std::string where = "UDP " + address + ":" + std::to_string(port);
  sockaddr_in addr{};
  if (!parse_address(address, port, addr)) {
    error = where + ": not an IPv4 address";
    return std::nullopt;
  }
  UdpReceiver r;
  r.fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (r.fd_ < 0) {
    error = errno_text(where + ": socket");
    return std::nullopt;
  }
  const int one = 1;
  ::setsockopt(r.fd_, SOL_SOCKET, SO_TIMESTAMPNS, &one, sizeof one);
  ::setsockopt(r.fd_, SOL_SOCKET, SO_RXQ_OVFL, &one, sizeof one);
  if (receive_buffer_bytes > 0) {
    ::setsockopt(r.fd_, SOL_SOCKET, SO_RCVBUF, &receive_buffer_bytes, sizeof receive_buffer_bytes);
  }
  int granted = 0;
  socklen_t len = sizeof granted;
  if (::getsockopt(r.fd_, SOL_SOCKET, SO_RCVBUF, &granted, &len) == 0) {
    r.granted_buffer_bytes_ = granted;
  }
  if (::bind(r.fd_, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0) {
    error = errno_text(where + ": bind");
    return std::nullopt;
  }
  sockaddr_in bound{};
  len = sizeof bound;
  if (::getsockname(r.fd_, reinterpret_cast<sockaddr*>(&bound), &len) == 0) {
    r.port_ = ntohs(bound.sin_port);
  }
  r.control_.resize(kMaxBatch);
  return r;
}

UdpReceiver::UdpReceiver(UdpReceiver&& o) noexcept { *this = std::move(o); }

UdpReceiver& UdpReceiver::operator=(UdpReceiver&& o) noexcept {
  if (this != &o) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = std::exchange(o.fd_, -1);
    port_ = o.port_;
    granted_buffer_bytes_ = o.granted_buffer_bytes_;
    kernel_drops_ = o.kernel_drops_;
    last_error_ = std::move(o.last_error_);
    control_ = std::move(o.control_);
  }
  return *this;
}

UdpReceiver::~UdpReceiver() {
  if (fd_ >= 0) ::close(fd_);
}

int UdpReceiver::receive(std::vector<Datagram>& out) {
  if (fd_ < 0) return -1;
  const int batch = static_cast<int>(std::min<std::size_t>(out.size(), kMaxBatch));
  if (batch == 0) return 0;
  mmsghdr msgs[kMaxBatch];
  iovec iov[kMaxBatch];
  for (int i = 0; i < batch; ++i) {
    iov[i].iov_base = out[i].bytes.data();
    iov[i].iov_len = out[i].bytes.size();
    std::memset(&msgs[i], 0, sizeof msgs[i]);
    msgs[i].msg_hdr.msg_iov = &iov[i];
    msgs[i].msg_hdr.msg_iovlen = 1;
    msgs[i].msg_hdr.msg_control = control_[i].data();
    msgs[i].msg_hdr.msg_controllen = control_[i].size();
  }
  const int n = ::recvmmsg(fd_, msgs, static_cast<unsigned>(batch), MSG_DONTWAIT, nullptr);
  if (n < 0) {
    if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) return 0;
    last_error_ = errno_text("recvmmsg");
    return -1;
  }
  const std::int64_t now = realtime_ns();
  for (int i = 0; i < n; ++i) {
    Datagram& d = out[i];
    d.size = msgs[i].msg_len;
    d.truncated = (msgs[i].msg_hdr.msg_flags & MSG_TRUNC) != 0;
    d.receive_utime_ns = now;
    for (cmsghdr* c = CMSG_FIRSTHDR(&msgs[i].msg_hdr); c != nullptr;
         c = CMSG_NXTHDR(&msgs[i].msg_hdr, c)) {
      if (c->cmsg_level != SOL_SOCKET) continue;
      if (c->cmsg_type == SCM_TIMESTAMPNS) {
        timespec ts{};
        std::memcpy(&ts, CMSG_DATA(c), sizeof ts);
        d.receive_utime_ns = static_cast<std::int64_t>(ts.tv_sec) * 1000000000 + ts.tv_nsec;
      } else if (c->cmsg_type == SO_RXQ_OVFL) {
        std::memcpy(&kernel_drops_, CMSG_DATA(c), sizeof kernel_drops_);
      }
    }
  }
  return n;
}

std::optional<UdpSender> UdpSender::open(const std::string& address, std::uint16_t port,
                                         std::uint16_t source_port, std::string& error) {
  const std::string where = "UDP " + address + ":" + std::to_string(port);
  sockaddr_in addr{};
  if (!parse_address(address, port, addr)) {
    error = where + ": not an IPv4 address";
    return std::nullopt;
  }
  UdpSender s;
  s.fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (s.fd_ < 0) {
    error = errno_text(where + ": socket");
    return std::nullopt;
  }
  if (source_port != 0) {
    sockaddr_in src{};
    src.sin_family = AF_INET;
    src.sin_port = htons(source_port);
    src.sin_addr.s_addr = htonl(INADDR_ANY);
    const int one = 1;
    ::setsockopt(s.fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    if (::bind(s.fd_, reinterpret_cast<const sockaddr*>(&src), sizeof src) != 0) {
      error = errno_text(where + ": bind source port " + std::to_string(source_port));
      return std::nullopt;
    }
  }
  // connect() fixes the destination, so send() needs no address and the kernel can drop
  // ICMP errors on this socket instead of failing later sends.
  if (::connect(s.fd_, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0) {
    error = errno_text(where + ": connect");
    return std::nullopt;
  }
  return s;
}

UdpSender::UdpSender(UdpSender&& o) noexcept { *this = std::move(o); }

UdpSender& UdpSender::operator=(UdpSender&& o) noexcept {
  if (this != &o) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = std::exchange(o.fd_, -1);
    last_error_ = std::move(o.last_error_);
  }
  return *this;
}

UdpSender::~UdpSender() {
  if (fd_ >= 0) ::close(fd_);
}

long UdpSender::send(const std::uint8_t* data, std::size_t size) {
  if (fd_ < 0) return -1;
  const ssize_t n = ::send(fd_, data, size, 0);
  if (n < 0) {
    // A connected UDP socket reports an earlier ICMP port-unreachable on the next send: the
    // receiver is not up yet, which is not an error of this datagram.
    if (errno == ECONNREFUSED) return 0;
    last_error_ = errno_text("send");
    return -1;
  }
  return static_cast<long>(n);
}

std::optional<UdpEndpoint> UdpEndpoint::open(const std::string& local_address, std::uint16_t local_port,
                                             std::string& error) {
  const std::string where = "UDP " + local_address + ":" + std::to_string(local_port);
  sockaddr_in addr{};
  if (!parse_address(local_address, local_port, addr)) {
    error = where + ": not an IPv4 address";
    return std::nullopt;
  }
  UdpEndpoint e;
  e.fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (e.fd_ < 0) {
    error = errno_text(where + ": socket");
    return std::nullopt;
  }
  if (::bind(e.fd_, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0) {
    error = errno_text(where + ": bind");
    return std::nullopt;
  }
  sockaddr_in bound{};
  socklen_t len = sizeof bound;
  if (::getsockname(e.fd_, reinterpret_cast<sockaddr*>(&bound), &len) == 0) e.port_ = ntohs(bound.sin_port);
  return e;
}

UdpEndpoint::UdpEndpoint(UdpEndpoint&& o) noexcept { *this = std::move(o); }

UdpEndpoint& UdpEndpoint::operator=(UdpEndpoint&& o) noexcept {
  if (this != &o) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = std::exchange(o.fd_, -1);
    port_ = o.port_;
    last_error_ = std::move(o.last_error_);
  }
  return *this;
}

UdpEndpoint::~UdpEndpoint() {
  if (fd_ >= 0) ::close(fd_);
}

long UdpEndpoint::send_to(const std::string& address, std::uint16_t port, const std::uint8_t* data,
                          std::size_t size) {
  sockaddr_in addr{};
  if (fd_ < 0 || !parse_address(address, port, addr)) {
    last_error_ = "send to " + address + ":" + std::to_string(port) + ": bad address or closed socket";
    return -1;
  }
  const ssize_t n = ::sendto(fd_, data, size, 0, reinterpret_cast<const sockaddr*>(&addr), sizeof addr);
  if (n < 0) {
    last_error_ = errno_text("sendto " + address + ":" + std::to_string(port));
    return -1;
  }
  return static_cast<long>(n);
}

int UdpEndpoint::receive_from(std::vector<std::uint8_t>& out, bool& truncated, std::string& from_address,
                              std::uint16_t& from_port) {
  if (fd_ < 0) return -1;
  out.resize(2048);
  sockaddr_in from{};
  socklen_t len = sizeof from;
  const ssize_t n = ::recvfrom(fd_, out.data(), out.size(), MSG_DONTWAIT | MSG_TRUNC,
                               reinterpret_cast<sockaddr*>(&from), &len);
  if (n < 0) {
    out.clear();
    if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR || errno == ECONNREFUSED) return 0;
    last_error_ = errno_text("recvfrom");
    return -1;
  }
  truncated = static_cast<std::size_t>(n) > out.size();
  out.resize(std::min(out.size(), static_cast<std::size_t>(n)));
  char text[INET_ADDRSTRLEN] = {0};
  ::inet_ntop(AF_INET, &from.sin_addr, text, sizeof text);
  from_address = text;
  from_port = ntohs(from.sin_port);
  return 1;
}

}  // namespace porter::livox
