#pragma once
// The simulated MID-360's command channel: answers parameter-configuration requests (command
// 0x0100) like the sensor, so porter-lidar's sensor set-up can be exercised without hardware.
// Supported keys: 0x0006 and 0x0007 (point and IMU destinations: applied to the sender),
// 0x0005 (status destination: accepted, no status is pushed) and 0x001A (work mode: 0x01
// sampling starts the streams, 0x02 idle stops them). Any other key is refused with ret_code
// 0x20 (parameter not supported) and that key, nothing applied. Frames that do not decode are
// counted and dropped, as the sensor does.
//
// Thread-safety: one thread.

#include <cstdint>
#include <optional>
#include <string>

#include "porter/livox/command.hpp"
#include "porter/livox/udp.hpp"
#include "porter/livox_sim/realtime_sender.hpp"

namespace porter::livox::sim {

class CommandServer {
 public:
  static std::optional<CommandServer> open(const std::string& address, std::uint16_t port, std::string& error);

  int fd() const { return socket_.fd(); }
  /// Handles every waiting request; returns how many were applied and acknowledged.
  std::size_t poll(RealtimeSender& sender);

  std::uint64_t bad_frames() const { return bad_frames_; }
  /// A line about the last applied request ("" when none yet).
  const std::string& last_applied() const { return last_applied_; }

 private:
  explicit CommandServer(UdpEndpoint socket) : socket_(std::move(socket)) {}
  UdpEndpoint socket_;
  std::uint64_t bad_frames_ = 0;
  std::string last_applied_;
};

}  // namespace porter::livox::sim
