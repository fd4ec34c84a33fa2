#pragma once
// Everything porter-lidar does with a datagram, without sockets or LCM: decode it, put its
// time on the output clock, count what was malformed or lost, and turn point packets into
// clouds and IMU packets into IMU samples.
//
// Output clock: for an unsynchronised sensor (time_type 0) the host's wall clock through
// HostTimeMapper (host_time.hpp; the vendor driver also uses the host clock here, per packet at
// receipt); for PTP/gPTP and GPS time (time_type 1, 2) the sensor's timestamp as it is (ns since
// the epoch of the time source: PTP is normally TAI/UTC on a PTP-synced host clock, GPS time is
// ahead of UTC by the leap seconds and is not corrected here).
//
// Lost point packets are counted from gaps in the packet timestamps (a packet's first sample
// follows the previous packet's by time_interval * dot_num / (dot_num - 1)); lost IMU packets
// from gaps in udp_cnt. Datagrams are dispatched by their data_type, not by the port they came
// in on (as Livox-SDK2 does).
//
// Failure: counted, never thrown. Thread-safety: one thread.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "porter/livox/cloud_assembler.hpp"
#include "porter/livox/decoder.hpp"
#include "porter/livox/host_time.hpp"

namespace porter::livox {

struct LidarStreamParams {
  DecodeOptions decode;
  HostTimeParams host_time;
  CloudAssemblerParams cloud;
};

/// One IMU sample on the output clock.
struct ImuMeasurement {
  std::int64_t time_ns = 0;
  std::uint8_t time_type = 0;
  ImuSample sample;
};

struct LidarStreamCounters {
  DecodeCounters decode;              ///< every datagram, by decode status (truncated included)
  std::uint64_t point_packets = 0;    ///< decoded point packets
  std::uint64_t imu_packets = 0;      ///< decoded IMU packets
  std::uint64_t lost_point_packets = 0;
  std::uint64_t lost_imu_packets = 0;
  std::uint64_t reordered_packets = 0;  ///< a point packet older than its predecessor
  std::uint64_t points = 0;           ///< points put into clouds
  std::uint64_t clouds = 0;
};

class LidarStream {
 public:
  explicit LidarStream(const LidarStreamParams& params);

  /// Handles one datagram received at receive_ns (host wall clock). `truncated`: the datagram
  /// was longer than the receive buffer (counted as length_mismatch). Completed clouds and IMU
  /// samples are appended to the outputs.
  void handle(const std::uint8_t* data, std::size_t size, bool truncated, std::int64_t receive_ns,
              std::vector<Cloud>& clouds, std::vector<ImuMeasurement>& imu);

  /// Completes the cloud in progress when no point packet arrived for idle_s (host clock), so
  /// a paused stream still delivers its last cloud. Returns true when a cloud was completed.
  bool flush_if_idle(std::int64_t now_ns, double idle_s, std::vector<Cloud>& clouds);

  const LidarStreamCounters& counters() const { return counters_; }
  const HostTimeMapper& host_time() const { return host_time_; }
  const CloudAssembler& assembler() const { return assembler_; }
  /// Host time the last decoded packet of each kind arrived (0 before the first).
  std::int64_t last_point_receive_ns() const { return last_point_receive_ns_; }
  std::int64_t last_imu_receive_ns() const { return last_imu_receive_ns_; }
  /// Counts for a status line: "malformed 3 (crc_mismatch=3), lost 0+0, no-return 1520".
  std::string summary() const;

 private:
  LidarStreamParams params_;
  HostTimeMapper host_time_;
  CloudAssembler assembler_;
  DecodedPacket packet_;
  LidarStreamCounters counters_;
  bool have_point_ = false;
  std::int64_t last_point_sensor_ns_ = 0;
  bool have_imu_ = false;
  std::uint16_t last_imu_cnt_ = 0;
  std::int64_t last_point_receive_ns_ = 0;
  std::int64_t last_imu_receive_ns_ = 0;
};

}  // namespace porter::livox
