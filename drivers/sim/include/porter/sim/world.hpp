#pragma once
// The simulated world: the scene's exact obstacles (plus boxes added and obstacles removed at
// run time), the robot model (with its payload attached), and the robot's ground truth over the
// recent past. Sensors read it (sensor.hpp); the Simulator writes it after every step.
//
// Ground truth: the Simulator records one RobotSample per step. robot_at(t) interpolates
// linearly between the recorded samples (x, y, joint angles and velocities; yaw along the
// shorter arc) and clamps t to the recorded span, which covers the last `history_s` seconds.
// With 1 ms steps, the interpolation error is below the motion in 1 ms.
//
// Obstacles: obstacles() lists the scene's, then the ones added at run time, in W.
// obstacles_version() increases on every change, so a sensor that built an acceleration
// structure (a ray tracer's BVH) knows when to rebuild it.
//
// Time: simulated seconds from the start of the run; utime_at(t) maps them to the wall-clock
// µs stamped on messages and frames (utime_origin + t * 1e6).
//
// Frames and units: W (z up, ground z = 0), B, SI units (README "Frames and units").
// Thread-safety: none; the simulation thread owns the world, sensors read it from that thread.

#include <cstdint>
#include <deque>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "porter/core/geometry.hpp"
#include "porter/core/robot_model.hpp"
#include "porter/core/scene.hpp"
#include "porter/core/types.hpp"

namespace porter::sim {

/// The robot's ground truth at one instant.
struct RobotSample {
  double t_s = 0.0;
  RobotConfiguration config;                      ///< base pose B in W, joint angles
  double v_mps = 0.0;                             ///< forward speed of B along x_B
  double omega_radps = 0.0;                       ///< yaw rate about z
  JointVector qd_radps = JointVector::Zero();     ///< joint velocities
};

enum class ObstacleStatus { ok, duplicate_name, not_found, invalid };
const char* to_string(ObstacleStatus status);

class World {
 public:
  /// `robot` should carry the payload already (attach_payload). history_s > 0.
  World(Scene scene, RobotModel robot, double history_s = 2.0);

  const Scene& scene() const { return scene_; }
  const RobotModel& robot() const { return robot_; }

  // ---- obstacles ---------------------------------------------------------------------------------
  const std::vector<CollisionShape>& obstacles() const { return obstacles_; }
  std::uint64_t obstacles_version() const { return version_; }
  /// A box centred at center_W (m), full edge lengths size_m (> 0, finite), rotated yaw_rad about
  /// z. Its name must not be in use.
  ObstacleStatus add_box(const std::string& name, const Eigen::Vector3d& center_W,
                         const Eigen::Vector3d& size_m, double yaw_rad);
  /// Removes the obstacle (scene or added) with this name.
  ObstacleStatus remove_obstacle(const std::string& name);

  // ---- ground truth ------------------------------------------------------------------------------
  /// Appends a sample; its time must be later than the latest one (an earlier or equal time
  /// replaces the latest sample). Samples older than history_s before it are forgotten.
  void record(const RobotSample& sample);
  bool has_truth() const { return !history_.empty(); }
  /// The latest sample (a default sample before the first record()).
  const RobotSample& latest() const;
  /// Ground truth at t_s, interpolated; clamped to the recorded span.
  RobotSample robot_at(double t_s) const;
  /// Earliest time robot_at() interpolates rather than clamps.
  double history_start_s() const;

  void set_utime_origin(std::int64_t utime_at_zero) { utime_origin_ = utime_at_zero; }
  std::int64_t utime_origin() const { return utime_origin_; }
  std::int64_t utime_at(double t_s) const;

 private:
  Scene scene_;
  RobotModel robot_;
  double history_s_;
  std::vector<CollisionShape> obstacles_;
  std::uint64_t version_ = 0;
  std::deque<RobotSample> history_;
  RobotSample empty_;
  std::int64_t utime_origin_ = 0;
};

}  // namespace porter::sim
