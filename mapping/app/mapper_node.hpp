#pragma once
// porter-mapper's logic between the bus and the library, without the bus itself (so the
// process, the replay test and the process test run the same code):
//
//   receiver thread:  on_state(ROBOT_STATE), on_cloud(LIDAR_POINTS)  — never block for long
//   worker thread:    step(now) — processes the oldest queued cloud once ROBOT_STATE covers it
//                     (base and arm samples at or before its first point and at or after its
//                     last), and says when a map is due.
//
// A cloud is integrated when the states that came before the base track passed its last point
// by state_wait_s cover it (StateBuffer::covers_by: the arm sample that covers its last point
// must come with a ROBOT_STATE whose utime is at most state_wait_s after that point). One they
// do not cover, or can no longer cover (its first point is older than the history kept, or
// than the first sample), is dropped and counted (dropped_no_state), never integrated with a
// held state: the self-filter needs the arm where it was at each point's time, and a cloud
// filtered with a stale arm leaves the robot's own points in the map as obstacles in front of
// it. The rule is on the messages' own stamps, not on when they arrive or when the worker gets
// to them: the same clouds and states give the same map whatever their interleaving and the
// worker's delays (as long as no queue overflows and the history holds the samples).
//
// No cloud is dropped silently: a cloud that arrives while another is being processed or
// waits is counted (arrived_while_busy); when the queue (max_queued_clouds) is full the oldest
// waiting cloud is dropped and counted (dropped_queue_full when the state covered it, else
// dropped_no_state: with no state coming, the queue is what bounds the wait); gaps in scan_id
// are counted (lost_upstream); malformed messages are counted (rejected) with the last reason.
//
// Thread-safety: on_state/on_cloud/counters from any thread; step()/make_map() from one
// worker thread.

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <string>

#include "mapper_params.hpp"
#include "porter/mapping/mapper.hpp"
#include "porter/mapping/octomap_binary.hpp"
#include "porter/octomap_t.hpp"
#include "porter/point_cloud_t.hpp"
#include "porter/robot_state_t.hpp"

namespace porter::mapping::app {

struct MapperCounters {
  std::uint64_t clouds_received = 0;
  std::uint64_t clouds_processed = 0;
  std::uint64_t arrived_while_busy = 0;
  std::uint64_t dropped_queue_full = 0;
  std::uint64_t lost_upstream = 0;
  std::uint64_t rejected = 0;
  std::uint64_t states_received = 0;
  std::uint64_t states_without_arm = 0;   ///< ROBOT_STATEs with no joints (base pose only used)
  std::uint64_t dropped_no_state = 0;     ///< dropped: no state covering the scan in time
  std::uint64_t points_state_outside = 0; ///< points posed with a held (not interpolated) state
  std::uint64_t maps = 0;
  std::string last_reject;
};

struct StepResult {
  CloudReport report;
  std::int64_t scan_id = 0;
  std::int64_t received_ns = 0;   ///< monotonic time the cloud was received
  bool map_due = false;           ///< publish_rate_hz says a map should go out now
};

class MapperNode {
 public:
  MapperNode(const MapperConfig& config, const RobotModel& robot);

  void on_state(const porter::robot_state_t& msg);
  void on_cloud(const porter::point_cloud_t& msg, std::int64_t now_ns);

  /// Processes at most one cloud; false when none was ready. Waits up to wait_ns for one.
  bool step(std::int64_t now_ns, std::int64_t wait_ns, StepResult& out);
  /// Builds the map message of the current map (map_id increments); re-encodes only the parts
  /// of the stream that changed since the last map (octomap_binary.hpp).
  void make_map(porter::octomap_t& out);

  MapperCounters counters() const;
  const Mapper& mapper() const { return mapper_; }

 private:
  struct Queued {
    SensorCloud cloud;
    std::int64_t scan_id = 0;
    std::int64_t received_ns = 0;
    std::int64_t start_us = 0;  ///< first point's time
    std::int64_t end_us = 0;    ///< last point's time
  };
  std::int64_t wait_us() const { return static_cast<std::int64_t>(config_.state_wait_s * 1e6); }

  MapperConfig config_;
  Mapper mapper_;
  OctomapBinaryWriter writer_;  ///< keeps the map's stream between maps (worker thread only)
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<Queued> queue_;
  StateBuffer states_;
  bool processing_ = false;
  bool have_scan_id_ = false;
  std::int64_t last_scan_id_ = 0;
  MapperCounters counters_;
  std::int64_t last_map_ns_ = 0;
  std::int64_t map_id_ = 0;
};

}  // namespace porter::mapping::app
