#pragma once
// The robot side of the kernel collision check: everything that depends only on the robot, its
// payload and the settings, built once and shared by every KernelCollisionChecker (one per map)
// made from it — the robot kernels K^0..K^7 (robot_kernels.hpp), the kinematics the checks run
// (kernel_kinematics.hpp) and the self-collision check with its proofs (self_collision.hpp),
// a few hundred ms for the Scout Mini + Piper with a payload. A new map never rebuilds it.
//
//   auto robot = std::make_shared<const KernelRobot>(model, settings);   // once per robot + payload
//   KernelCollisionChecker checker(robot, settings.map);                 // the map part
//   checker.set_map(grid);
//
// Thread-safety: immutable after construction; share freely (std::shared_ptr<const KernelRobot>).
// build_count() is safe from any thread.

#include <array>
#include <cstdint>

#include "porter/core/robot_model.hpp"
#include "porter/core/types.hpp"
#include "porter/planner/collision/kernel_kinematics.hpp"
#include "porter/planner/collision/map_kernel.hpp"
#include "porter/planner/collision/robot_kernels.hpp"
#include "porter/planner/collision/self_collision.hpp"

namespace porter::planner {

struct KernelCheckerSettings {
  RobotKernelSettings kernels;  ///< resolution (= map resolution), joint sampling
  MapKernelSettings map;        ///< safety margin, distance-field cap (the map part's)
  SelfCollisionSettings self;   ///< sample spacing, proofs
  bool check_self_collision = true;
  /// Largest displacement of any robot point between neighbouring samples of a motion or a
  /// trajectory (m); <= 0 selects one voxel.
  double motion_step_m = 0.0;
};

class KernelRobot {
 public:
  /// Builds the kernels and self-collision proofs for `model` (payload attached) with every field
  /// of `settings` but `map`. Throws std::invalid_argument for non-positive resolutions or
  /// spacings. Does not keep a reference to `model`.
  KernelRobot(const RobotModel& model, const KernelCheckerSettings& settings);

  const KernelCheckerSettings& settings() const { return settings_; }
  const RobotKernels& kernels() const { return kernels_; }
  const KernelKinematics& kinematics() const { return kinematics_; }
  const SelfCollisionChecker& self_collision() const { return self_; }
  double resolution_m() const { return kernels_.resolution_m(); }
  /// Largest displacement of a robot point between neighbouring motion / trajectory samples, m.
  double motion_step_m() const { return motion_step_m_; }
  /// The inflation bound of link j's environment check (RobotKernels::inflation_bound_m), m.
  double inflation_bound_m(int link) const { return kernels_.inflation_bound_m(link); }

  /// KernelRobot objects constructed in this process so far (a diagnostic: tests count builds).
  static std::int64_t build_count();

 private:
  KernelCheckerSettings settings_;
  RobotKernels kernels_;
  KernelKinematics kinematics_;
  SelfCollisionChecker self_;
  double motion_step_m_ = 0.0;
};

}  // namespace porter::planner
