#pragma once
// KernelCollisionChecker: the chain-decomposed kernel collision check (paper §IV-B, §IV-C), the
// "kernels" implementation of CollisionChecker. It is split in two parts: the robot side
// (KernelRobot, kernel_robot.hpp: robot kernels, kinematics, self-collision proofs), built once per
// robot + payload and shared, and the map side this object owns (MapKernel, map_kernel.hpp), which
// set_map() replaces or updates incrementally. A checker for another map shares the same robot.
//
// A configuration is reported in collision when (each bound stated in the part's header):
//   - base (link 0): its geometry meets a voxel of O_m (occupied, dilated by the safety margin)
//     or a voxel outside the map horizontally / above it. The ground is not an obstacle for the
//     base. Exact at voxel level up to the inflation RobotKernels::inflation_bound_m(0);
//   - arm link j = 1..6 or gripper + payload (7): its geometry meets a voxel of O_m, a voxel
//     outside the map, or a voxel below the ground z = 0 (links other than the base must stay
//     above it). Conservative; inflation RobotKernels::inflation_bound_m(j);
//   - self: two links the model does not allow to touch have intersecting exact geometry
//     (conservative; inflation SelfCollisionChecker::inflation_bound_m(), 0 for proven pairs);
//   - the base origin is outside the map horizontally (link 0), a joint is outside its limits by
//     more than half a kernel sample step (link = that joint's link), a value is NaN (link 0), or
//     no map has been set yet (link 0).
// Query order: base (tile-skipped integer offsets), then the root spheres of links 1..7 in one
// eight-lane test against the map's distance field, then the eight-wide sphere trees of the
// links not cleared there (payload link 7 first, then 6..1), then self-collision; the first hit
// is returned.
//
// Motions: check_motion() interpolates x, y and q linearly and yaw along the shorter arc (the
// difference wrapped to [-pi, pi]); it samples both ends and n - 1 interior points, n chosen so
// that no point of the robot moves more than motion_step_m between neighbouring samples
// (bound: |dxy| + reach |dyaw| + sum_j rho_j |dq_j|, ChainRadii), interior samples in
// coarse-to-fine (bisection) order so collisions are found early. check_trajectory() samples each
// piece at a time step from the piece's coefficient bounds on d(xy)/dt and dq/dt (each part at
// most half the step) and halves an interval again while the heading change between its ends
// moves a point more than half the step (the heading is evaluated, not bounded, in between).
// Every point of the swept body is within motion_step_m / 2 of the body at some sample, so a
// collision can only be missed where the swept body reaches into flagged voxels by less than
// motion_step_m / 2 between two samples (a graze); a thin column crossed by the body is caught.
//
// Batches: check_batch() answers as check() does, eight configurations per pass: the tests
// that are the same shape for every configuration (forward kinematics, the links' root spheres,
// the self-collision bounding and root spheres) run once per pass with one configuration per
// lane, the data-dependent tree walks per configuration. check_motion() and check_trajectory()
// check their samples this way, in the order described above, and report the first hit in that
// order (at most seven samples past it are checked).
//
// Speed: a check is a few hundred nanoseconds (the payload's tree walk and the self-collision part
// dominate, then cache misses and mispredicted branches); porter-bench-collision measures it
// (tests/bench/bench_collision.cpp, figures in the README). No heap allocation in check(),
// check_batch(), check_base(), check_motion(), check_trajectory().
// Thread-safety: const members may be called concurrently once the map is set; set_map() needs
// exclusive access.

#include <array>
#include <cstddef>
#include <memory>
#include <string>

#include "porter/core/robot_model.hpp"
#include "porter/planner/collision/collision_checker.hpp"
#include "porter/planner/collision/kernel_kinematics.hpp"
#include "porter/planner/collision/kernel_robot.hpp"
#include "porter/planner/collision/map_kernel.hpp"
#include "porter/planner/collision/robot_kernels.hpp"
#include "porter/planner/collision/self_collision.hpp"

namespace porter::planner {

/// Memory used and kernels held.
struct KernelStorage {
  int kernel_count = 0;                  ///< N_0 + sum_j N_j + 1
  std::size_t robot_kernel_bytes = 0;    ///< K^0..K^7
  std::size_t self_collision_bytes = 0;  ///< self-collision samples and distance grids
  std::size_t map_kernel_bytes = 0;      ///< bit sets, projection, distance field
};

class KernelCollisionChecker final : public CollisionChecker {
 public:
  /// The map part for a robot side built before (shared; never rebuilt here), with `map`'s margin
  /// and distance cap. Throws std::invalid_argument when `robot` is null.
  KernelCollisionChecker(std::shared_ptr<const KernelRobot> robot, const MapKernelSettings& map = {});
  /// Builds its own robot side for `model` (payload attached) from `settings`. Throws
  /// std::invalid_argument for non-positive resolutions or spacings.
  explicit KernelCollisionChecker(const RobotModel& model, const KernelCheckerSettings& settings = {});

  /// Throws std::invalid_argument when the grid's resolution differs from the kernels' (by more
  /// than 1e-9 relative), the grid is empty, or the ground is not a voxel boundary.
  void set_map(const OccupancyGrid& occupancy_W) override;
  CollisionResult check(const RobotConfiguration& config) const override;
  CollisionResult check_base(const BasePose& base) const override;
  CollisionResult check_motion(const RobotConfiguration& from, const RobotConfiguration& to) const override;
  CollisionResult check_trajectory(const Trajectory& trajectory) const override;
  /// results[i] = check(configs[i]) for i < count (the same tests, so the same answers up to
  /// float rounding in the forward kinematics), eight configurations at a time: forward
  /// kinematics, the links' root spheres and the self-collision sphere tests run in eight-lane
  /// operations with one configuration per lane; the tree walks run per configuration. Faster
  /// than count check() calls when the configurations are free (see the header comment).
  void check_batch(const RobotConfiguration* configs, std::size_t count, CollisionResult* results) const override;
  std::string name() const override { return "kernels"; }

  /// Environment part of check() (no self-collision).
  CollisionResult check_environment(const RobotConfiguration& config) const;
  /// Self-collision part of check(); joint-limit violations are reported as in check().
  CollisionResult check_self(const JointVector& q_rad) const;
  /// Self-collision (and joint limits) along a trajectory: the arm at samples where no point moves
  /// more than motion_step_m / 2 relative to the base between neighbours (joint rates only; the
  /// base motion does not change self-collision). Unlike check_trajectory(), which reports the
  /// first hit of any kind, this finds a self-collision even where the environment is hit first.
  CollisionResult check_trajectory_self(const Trajectory& trajectory) const override;
  /// RobotKernels::inflation_bound_m(link); the self-collision check's own bound is
  /// self_collision().inflation_bound_m().
  double inflation_bound_m(int link) const override { return kernels_.inflation_bound_m(link); }

  /// Number of intervals check_motion() splits the segment into.
  int motion_intervals(const RobotConfiguration& from, const RobotConfiguration& to) const;
  double motion_step_m() const { return motion_step_m_; }

  const MapUpdateStats& last_map_update() const { return last_update_; }
  KernelStorage storage() const;
  /// The shared robot side.
  const std::shared_ptr<const KernelRobot>& robot() const { return robot_; }
  const RobotKernels& kernels() const { return kernels_; }
  const MapKernel& map_kernel() const { return map_; }
  const SelfCollisionChecker& self_collision() const { return self_; }
  const KernelKinematics& kinematics() const { return kinematics_; }

 private:
  bool base_hit(int bx, int by, int yaw_sample) const;
  /// Base origin in padded voxel coordinates; false when it is outside the grid horizontally or
  /// a value is NaN.
  bool base_voxel(const BasePose& base, double* ux, double* uy) const;
  /// Bit j (1..7) set when link j's kernel sample may hit: its root sphere is not proven clear.
  std::uint32_t links_near(const std::array<int, kNumLinks>& sample, const Pose4f& T_V_B, const ArmPoses& poses) const;
  /// Walks link j's kernel sample below its root sphere; true on a hit.
  bool link_hit(int link, int sample, const Pose4f& T_V_B, const Pose4f& T_B_J) const;
  /// Base frame -> padded voxel coordinates of the map kernel (metres to voxels), for the base
  /// origin at padded voxel coordinates (ux, uy).
  Pose4f base_to_voxels(double yaw_rad, double ux, double uy) const {
    const double inv_h = 1.0 / kernels_.resolution_m();
    // The large world offset was subtracted in double (base_voxel) before rounding to float.
    float sy = 0.f, cy = 1.f;
    fast_sincos(yaw_rad, &sy, &cy);
    Pose4f T_V_B;
    const float c = cy * static_cast<float>(inv_h), s = sy * static_cast<float>(inv_h);
    T_V_B.c0 = v4f{c, s, 0.f, 0.f};
    T_V_B.c1 = v4f{-s, c, 0.f, 0.f};
    T_V_B.c2 = v4f{0.f, 0.f, static_cast<float>(inv_h), 0.f};
    T_V_B.t = v4f{static_cast<float>(ux), static_cast<float>(uy),
                  static_cast<float>(-map_.padded_origin_W().z() * inv_h), 0.f};
    return T_V_B;
  }
  /// check_batch() of count <= 8 configurations.
  void check_lanes(const RobotConfiguration* configs, int count, CollisionResult* results) const;
  /// The tests before any kinematics (map set, joint samples, base origin and base kernel), in
  /// check()'s order: the link to report, or -1 with sample and the base origin (padded voxel
  /// coordinates) filled in.
  int first_tests(const RobotConfiguration& config, std::array<int, kNumLinks>& sample, double* ux, double* uy) const;
  /// check() (self = true) or check_environment() (self = false).
  CollisionResult check_prepared(const RobotConfiguration& config, bool self) const;

  std::shared_ptr<const KernelRobot> robot_;
  KernelCheckerSettings settings_;  ///< the robot's, with this checker's map settings
  // The robot side's parts (owned by robot_).
  const RobotKernels& kernels_;
  const KernelKinematics& kinematics_;
  const SelfCollisionChecker& self_;
  MapKernel map_;
  MapUpdateStats last_update_;
  double motion_step_m_ = 0.0;
  std::array<float, kNumLinks> kernel_reach2_vox_{};   ///< (d_j / h)^2 per link, for MapKernel::arm_near
  std::array<float, kNumLinks> kernel_reach_units_{};  ///< d_j in clearance units (h / 4) per link
  float clearance_units_per_m_ = 0.f;                   ///< 4 / h
};

}  // namespace porter::planner
