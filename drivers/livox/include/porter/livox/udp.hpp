#pragma once
// Minimal UDP endpoints for the MID-360 streams (Linux sockets): a receiver that takes
// datagrams in batches (recvmmsg) with kernel receive timestamps, and a sender.
//
// Receive time: the kernel's SO_TIMESTAMPNS stamp (CLOCK_REALTIME when the datagram reached the
// socket) when available, else the clock when recvmmsg returned. A datagram longer than the
// receive buffer (kDatagramCapacity, above any valid packet) is flagged `truncated` and must be
// treated as oversized.
//
// Failure: open() returns an empty optional and an error message naming the address and the
// system error; receive/send return -1 on a system error (errno kept in last_error()).
// Thread-safety: one thread per endpoint.

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace porter::livox {

struct Datagram {
  static constexpr std::size_t kCapacity = 2048;
  std::array<std::uint8_t, kCapacity> bytes{};
  std::size_t size = 0;
  bool truncated = false;
  std::int64_t receive_utime_ns = 0;  ///< CLOCK_REALTIME, ns since the epoch
};

class UdpReceiver {
 public:
  /// Binds to address:port ("0.0.0.0" for every interface). receive_buffer_bytes asks the
  /// kernel for a socket buffer of that size (it may grant less: see granted_buffer_bytes()).
  static std::optional<UdpReceiver> open(const std::string& address, std::uint16_t port,
                                         int receive_buffer_bytes, std::string& error);
  UdpReceiver(UdpReceiver&& other) noexcept;
  UdpReceiver& operator=(UdpReceiver&& other) noexcept;
  UdpReceiver(const UdpReceiver&) = delete;
  UdpReceiver& operator=(const UdpReceiver&) = delete;
  ~UdpReceiver();

  int fd() const { return fd_; }
  std::uint16_t port() const { return port_; }
  int granted_buffer_bytes() const { return granted_buffer_bytes_; }

  /// Reads up to out.size() waiting datagrams without blocking; returns how many (0 when none
  /// is waiting) or -1 on a system error.
  int receive(std::vector<Datagram>& out);
  /// Datagrams the kernel dropped because the socket buffer was full (SO_RXQ_OVFL), as last
  /// reported; 0 when the kernel does not report it.
  std::uint32_t kernel_drops() const { return kernel_drops_; }
  const std::string& last_error() const { return last_error_; }

 private:
  UdpReceiver() = default;
  int fd_ = -1;
  std::uint16_t port_ = 0;
  int granted_buffer_bytes_ = 0;
  std::uint32_t kernel_drops_ = 0;
  std::string last_error_;
  std::vector<std::array<std::uint8_t, 128>> control_;
};

class UdpSender {
 public:
  /// Sends to address:port; source_port 0 lets the kernel choose.
  static std::optional<UdpSender> open(const std::string& address, std::uint16_t port,
                                       std::uint16_t source_port, std::string& error);
  UdpSender(UdpSender&& other) noexcept;
  UdpSender& operator=(UdpSender&& other) noexcept;
  UdpSender(const UdpSender&) = delete;
  UdpSender& operator=(const UdpSender&) = delete;
  ~UdpSender();

  /// Sends one datagram; returns the bytes sent or -1.
  long send(const std::uint8_t* data, std::size_t size);
  const std::string& last_error() const { return last_error_; }

 private:
  UdpSender() = default;
  int fd_ = -1;
  std::string last_error_;
};

/// A bound UDP socket that sends to any address and receives from any (the command channel:
/// porter-lidar talks to the sensor's command port, the simulated sensor answers).
class UdpEndpoint {
 public:
  /// Binds to local_address:local_port (port 0: the kernel chooses).
  static std::optional<UdpEndpoint> open(const std::string& local_address, std::uint16_t local_port,
                                         std::string& error);
  UdpEndpoint(UdpEndpoint&& other) noexcept;
  UdpEndpoint& operator=(UdpEndpoint&& other) noexcept;
  UdpEndpoint(const UdpEndpoint&) = delete;
  UdpEndpoint& operator=(const UdpEndpoint&) = delete;
  ~UdpEndpoint();

  int fd() const { return fd_; }
  std::uint16_t port() const { return port_; }
  /// Sends one datagram to address:port; bytes sent or -1 (last_error()).
  long send_to(const std::string& address, std::uint16_t port, const std::uint8_t* data, std::size_t size);
  /// Reads one waiting datagram without blocking into `out` (resized to its length; a longer
  /// datagram is cut at out's capacity of 2048 bytes and `truncated` set). Returns 1 when one
  /// was read, 0 when none waits, -1 on error. from_address/from_port: the sender.
  int receive_from(std::vector<std::uint8_t>& out, bool& truncated, std::string& from_address,
                   std::uint16_t& from_port);
  const std::string& last_error() const { return last_error_; }

 private:
  UdpEndpoint() = default;
  int fd_ = -1;
  std::uint16_t port_ = 0;
  std::string last_error_;
};

}  // namespace porter::livox
