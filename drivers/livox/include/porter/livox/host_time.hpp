#pragma once
// Host-clock time for packets of a sensor that is not time-synchronised (time_type 0: the
// timestamp counts ns since the sensor powered on).
//
// The vendor driver (livox_ros_driver2) replaces such a timestamp with the host clock at the
// moment the packet is handled, so every packet carries its own network and scheduling delay.
// HostTimeMapper also puts these packets on the host clock, but through an offset: for every
// packet, offset = receive time - sensor time of its last sample (the packet cannot leave the
// sensor before that sample), and the offset used is the smallest seen over a sliding window
// (between window_s and 2 * window_s long). Host time of a sample = sensor time + offset. The
// smallest offset is the least-delayed packet's, so mapped times keep the sensor's own spacing
// and lag the true time by the minimum transport delay only; the window lets the offset follow
// the drift between the two clocks. window_s = 0 gives the vendor driver's behaviour (each
// packet's own receive time, shifted so that its last sample, not its first, is at receipt).
//
// An offset that moves by more than reset_threshold_s (sensor reboot, clock change) restarts
// the window; resets() counts such restarts. Within each stream (points, IMU: their packets
// interleave out of order when read from two sockets) a packet whose mapped time would precede
// the stream's previous last sample by at most max_clamp_s is moved forward to it (clamped()
// counts them), so jitter-sized offset changes keep times monotonic; each clamp shortens the
// next packets' spacing (95/96 of it for point packets) until the offset's step is absorbed, so
// a larger step back (the first window finding a smaller delay than its first packets had) is
// taken at once instead (steps_back() counts them) rather than squeezing seconds of points.
//
// Thread-safety: one thread per mapper.

#include <cstdint>

namespace porter::livox {

struct HostTimeParams {
  /// Length of the minimum filter's window, s (>= 0; 0 = each packet's own receive time).
  double window_s = 1.0;
  /// An offset change larger than this, s (> 0), restarts the filter.
  double reset_threshold_s = 0.5;
  /// Largest backward step absorbed by clamping, s (>= 0).
  double max_clamp_s = 100e-6;
};

class HostTimeMapper {
 public:
  explicit HostTimeMapper(HostTimeParams params = {});

  /// sensor_first_ns: the packet's timestamp (first sample); span_ns: first to last sample;
  /// receive_ns: host clock when the datagram was received. Returns the host-clock time of the
  /// packet's first sample, ns.
  /// `stream` (0 or 1) selects the monotonic clamp: 0 for points, 1 for IMU.
  std::int64_t map(std::uint64_t sensor_first_ns, std::int64_t span_ns, std::int64_t receive_ns,
                   int stream = 0);

  /// Offset currently applied (host - sensor), ns; 0 before the first packet.
  std::int64_t offset_ns() const { return offset_ns_; }
  std::uint64_t resets() const { return resets_; }
  std::uint64_t clamped() const { return clamped_; }
  std::uint64_t steps_back() const { return steps_back_; }

 private:
  HostTimeParams params_;
  std::int64_t window_ns_;
  std::int64_t reset_ns_;
  std::int64_t max_clamp_ns_;
  bool started_ = false;
  std::int64_t bucket_start_ns_ = 0;  // receive time the current bucket began
  std::int64_t current_min_ = 0;
  std::int64_t previous_min_ = 0;
  bool have_previous_ = false;
  std::int64_t offset_ns_ = 0;
  std::int64_t last_end_ns_[2] = {0, 0};
  bool have_end_[2] = {false, false};
  std::uint64_t resets_ = 0;
  std::uint64_t clamped_ = 0;
  std::uint64_t steps_back_ = 0;
};

}  // namespace porter::livox
