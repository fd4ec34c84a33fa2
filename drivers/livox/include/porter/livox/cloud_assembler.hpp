#pragma once
// Cuts a stream of decoded point packets into clouds (scans) at a fixed rate.
//
// Cloud k holds the points whose time t satisfies k * period <= t < (k + 1) * period on the
// output clock (the host clock for an unsynchronised sensor, the sensor's PTP/GPS clock
// otherwise; see host_time.hpp); points are cut one by one, so a packet may straddle two clouds.
// A cloud is complete when a point of a later period arrives, or when flush() is called (the
// driver calls it when the stream pauses). Each point carries its time after the cloud's first
// point (time_offset_ns, >= 0), its line (sample index modulo 4: the vendor driver's convention
// for the MID-360's four lines; the packet does not carry it) and its tag. The configured
// extrinsic T_out_sensor maps points from the sensor frame into the output frame. "No return"
// points (x = y = z = 0) are dropped unless keep_no_return is set, and counted.
//
// Failure: none at run time; a point whose time precedes its cloud's first point (a clock step
// backwards) completes the cloud and starts a new one (time_steps() counts it); points beyond
// max_points in one cloud are dropped and counted (bounded memory).
// Thread-safety: one thread per assembler.

#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Geometry>

#include "porter/livox/decoder.hpp"

namespace porter::livox {

struct CloudAssemblerParams {
  double period_s = 0.1;                 ///< 0.1 = 10 Hz clouds; values below 0.01 act as 0.01
  Eigen::Isometry3d T_out_sensor = Eigen::Isometry3d::Identity();  ///< extrinsic
  bool keep_no_return = false;
  std::size_t max_points = 400000;       ///< per cloud, > 0
};

/// One assembled scan (structure of arrays, the layout of point_cloud_t).
struct Cloud {
  std::int64_t start_ns = 0;     ///< time of the first point, ns on the output clock
  std::int64_t period_index = 0; ///< k of the period [k, k+1) * period the cloud belongs to
  std::int64_t scan_id = 0;      ///< 0, 1, 2, ... per completed cloud
  std::uint8_t time_type = 0;    ///< time_type of the packets (0 = host clock)
  std::vector<float> x_m, y_m, z_m, intensity;
  std::vector<std::int32_t> time_offset_ns;
  std::vector<std::uint8_t> line, tag;

  std::size_t size() const { return x_m.size(); }
  void clear();
};

class CloudAssembler {
 public:
  explicit CloudAssembler(const CloudAssemblerParams& params);

  /// Adds the points of a decoded point packet whose first sample is at first_sample_ns (output
  /// clock). Clouds the packet completes are appended to `completed` (usually none, at most two
  /// when the clock steps backwards inside a period); returns how many.
  std::size_t add(const DecodedPacket& packet, std::int64_t first_sample_ns,
                  std::vector<Cloud>& completed);

  /// Completes the cloud in progress (if it has points), appending it to `completed`.
  bool flush(std::vector<Cloud>& completed);

  /// Time the cloud in progress ends (its period's end), ns; meaningless when empty().
  std::int64_t current_end_ns() const;
  bool empty() const { return current_.size() == 0; }

  std::uint64_t no_return_points() const { return no_return_; }
  std::uint64_t points_over_capacity() const { return over_capacity_; }
  std::uint64_t time_steps() const { return time_steps_; }
  std::uint64_t clouds_completed() const { return completed_count_; }

 private:
  bool complete(std::vector<Cloud>& completed);

  CloudAssemblerParams params_;
  std::int64_t period_ns_;
  Eigen::Matrix3f R_;
  Eigen::Vector3f t_;
  Cloud current_;
  std::uint64_t no_return_ = 0;
  std::uint64_t over_capacity_ = 0;
  std::uint64_t time_steps_ = 0;
  std::uint64_t completed_count_ = 0;
};

/// floor(t / period) for signed t.
std::int64_t period_index(std::int64_t t_ns, std::int64_t period_ns);

}  // namespace porter::livox
