#pragma once
// porter-lidar's optional sensor set-up over the MID-360's command channel
// (porter/livox/command.hpp): tells the sensor to send its point, IMU and status streams to
// this host and to sample. Sent at start and again whenever the stream is silent (a sensor
// that rebooted), every retry_period_s until the sensor acknowledges; the outcome is logged.
//
// Failure: open() fails with a message when the command socket cannot be bound; replies that
// do not decode are counted and logged, never thrown.
// Thread-safety: one thread.

#include <cstdint>
#include <optional>
#include <string>

#include "porter/livox/command.hpp"
#include "porter/livox/udp.hpp"

namespace porter::livox::app {

struct DeviceParams {
  bool configure = false;
  std::string lidar_address = "192.168.1.100";
  std::uint16_t lidar_command_port = kDefaultLidarCommandPort;
  std::string host_address = "192.168.1.5";
  std::uint16_t host_command_port = kDefaultHostCommandPort;
  std::uint16_t host_push_port = 56201;
  double retry_period_s = 2.0;
};

class DeviceConfigurator {
 public:
  /// point_port / imu_port: where porter-lidar listens (sent to the sensor as destinations).
  static std::optional<DeviceConfigurator> open(const DeviceParams& params, std::uint16_t point_port,
                                                std::uint16_t imu_port, std::string& error);

  int fd() const { return socket_.fd(); }
  /// Reads replies, and sends a request when one is due: not acknowledged yet, or
  /// `stream_alive` false (then a new acknowledgement is needed).
  void step(std::int64_t now_ns, bool stream_alive);

  bool acknowledged() const { return acknowledged_; }
  std::uint64_t requests() const { return requests_; }
  std::uint64_t bad_replies() const { return bad_replies_; }

 private:
  DeviceConfigurator(const DeviceParams& p, std::array<std::uint8_t, 4> host_ip, std::uint16_t point_port,
                     std::uint16_t imu_port, UdpEndpoint socket)
      : params_(p), host_ip_(host_ip), point_port_(point_port), imu_port_(imu_port), socket_(std::move(socket)) {}

  DeviceParams params_;
  std::array<std::uint8_t, 4> host_ip_{};
  std::uint16_t point_port_;
  std::uint16_t imu_port_;
  UdpEndpoint socket_;
  bool acknowledged_ = false;
  bool was_alive_ = false;
  std::uint32_t seq_ = 0;
  std::int64_t next_request_ns_ = 0;
  std::uint64_t requests_ = 0;
  std::uint64_t bad_replies_ = 0;
};

}  // namespace porter::livox::app
