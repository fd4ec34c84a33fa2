#pragma once
// Sends a simulated MID-360's packets over UDP as the sensor would: point packets from the
// point source port to the host's point port, IMU packets from the IMU source port to the IMU
// port, each when its time has come. The caller runs the clock: step(now) advances the
// simulation to `now` and sends every packet due by then, so a caller stepping every 1 ms sends
// each packet at most ~1 ms after its time (the sensor sends one every 0.48 ms).
//
// Failure: open() returns an empty optional with an error naming the address and port; send
// failures are counted (send_failures()) and the last one kept in last_error().
// Thread-safety: one thread.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "porter/livox/udp.hpp"
#include "porter/livox_sim/simulated_mid360.hpp"

namespace porter::livox::sim {

struct RealtimeSenderParams {
  std::string destination = "127.0.0.1";
  std::uint16_t point_port = kDefaultPointHostPort;
  std::uint16_t imu_port = kDefaultImuHostPort;
  std::uint16_t point_source_port = 0;  ///< 0: any (the device uses 56300)
  std::uint16_t imu_source_port = 0;    ///< 0: any (the device uses 56400)
};

class RealtimeSender {
 public:
  static std::optional<RealtimeSender> open(const RealtimeSenderParams& params, std::string& error);

  /// Advances `lidar` from the previous step's time (0 at first) to now_s and sends the packets
  /// (none while not sampling: the sensor is idle, its time still runs). Returns how many were
  /// sent.
  std::size_t step(SimulatedMid360& lidar, double now_s);
  /// Sends packets produced elsewhere (porter-sim's LiDAR advances on the simulation's steps),
  /// in order; nothing while not sampling. Returns how many were sent.
  std::size_t send(const std::vector<SimPacket>& packets);

  /// New destination of the point or IMU stream (a sensor told so over its command channel).
  /// False, with last_error(), when the socket cannot be opened (the old one is kept).
  bool set_destination(SimPacket::Stream stream, const std::string& address, std::uint16_t port);
  void set_sampling(bool on) { sampling_ = on; }
  bool sampling() const { return sampling_; }

  std::uint64_t sent() const { return sent_; }
  std::uint64_t send_failures() const { return failures_; }
  const std::string& last_error() const { return last_error_; }
  double time_s() const { return last_s_; }

 private:
  RealtimeSender(const RealtimeSenderParams& p, UdpSender points, UdpSender imu)
      : params_(p), points_(std::move(points)), imu_(std::move(imu)) {}
  RealtimeSenderParams params_;
  bool sampling_ = true;
  UdpSender points_;
  UdpSender imu_;
  std::vector<SimPacket> packets_;
  double last_s_ = 0.0;
  std::uint64_t sent_ = 0;
  std::uint64_t failures_ = 0;
  std::string last_error_;
};

}  // namespace porter::livox::sim
