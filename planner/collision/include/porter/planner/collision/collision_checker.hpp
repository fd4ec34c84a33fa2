#pragma once
// The collision-checking interface every planner stage talks to. Implementations:
//   - KernelCollisionChecker (chain-decomposed voxel kernels, paper §IV-C) — "kernels"
//   - the sphere-ESDF baseline (REMANI/TOPAY style) — "spheres"
// so the paper's ablations are one flag each.
//
// Contract: a configuration is "in collision" when any planning link (base, arm links,
// gripper + payload) overlaps an obstacle of the current map, the robot collides with itself
// (pairs not allowed by the model's AllowedCollisionMatrix), or any link leaves the map's
// vertical extent below the ground (z < 0). Implementations are conservative: they may report
// a collision that the exact geometry does not have (bounded by their documented inflation),
// never the reverse. A point outside the map's horizontal bounds is treated as occupied.
//
// Thread-safety: const member functions may be called concurrently from several threads once
// the map is set; set_map() needs exclusive access.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

#include "porter/core/occupancy_grid.hpp"
#include "porter/core/trajectory.hpp"
#include "porter/core/types.hpp"

namespace porter::planner {

/// What a check found. `link` is the first planning link found in collision (0..7), -1 when
/// free; `other_link` is the second link of a self-collision, -1 for an environment hit.
struct CollisionResult {
  bool in_collision = false;
  int link = -1;
  int other_link = -1;
  explicit operator bool() const { return in_collision; }
};

class CollisionChecker {
 public:
  virtual ~CollisionChecker() = default;

  /// Replaces the obstacle map (occupancy in the world frame). Cheap relative to planning; an
  /// implementation may keep derived data (dilation, distance fields) up to date incrementally.
  virtual void set_map(const OccupancyGrid& occupancy_W) = 0;

  /// Whole-body check of one configuration (environment + self + ground).
  virtual CollisionResult check(const RobotConfiguration& config) const = 0;

  /// results[i] = check(configs[i]) for i < count. Implementations may check several
  /// configurations per pass (the kernel checker does eight); this default checks one at a time.
  virtual void check_batch(const RobotConfiguration* configs, std::size_t count, CollisionResult* results) const {
    for (std::size_t i = 0; i < count; ++i) results[i] = check(configs[i]);
  }

  /// Base-only environment check (front-end's Hybrid A* expansion).
  virtual CollisionResult check_base(const BasePose& base) const = 0;

  /// Straight-line motion in [x, y, yaw, q] between two configurations, sampled so that no point
  /// of any link moves more than the implementation's step bound between samples.
  virtual CollisionResult check_motion(const RobotConfiguration& from, const RobotConfiguration& to) const = 0;

  /// The trajectory over time, sampled with the same step bound (base yaw from the trajectory's
  /// heading rule).
  virtual CollisionResult check_trajectory(const Trajectory& trajectory) const = 0;

  /// Self-collision (and joint limits) only, along the trajectory: finds a self-collision even
  /// where check_trajectory() stops at an environment hit first (the pipeline re-solves a
  /// self-colliding mid-end trajectory closer to the front-end's path). An implementation that
  /// does not check self-collision returns "free" and says so in its header.
  virtual CollisionResult check_trajectory_self(const Trajectory& trajectory) const = 0;

  /// How much larger than the exact geometry link j (0..7) may be when checked against the map:
  /// a reported collision is at most this far from a real one (m, >= 0). The back-end keeps its
  /// safety margins above it so that its answer passes this checker.
  virtual double inflation_bound_m(int link) const = 0;

  /// A short name for logs and result files ("kernels", "spheres").
  virtual std::string name() const = 0;
};

}  // namespace porter::planner
