#pragma once
// The collision checkers porter-plan plans with: the paper's chain-decomposed kernels, or the
// sphere-ESDF baseline (--collision spheres).

#include <memory>

#include "plan_args.hpp"
#include "porter/core/robot_model.hpp"
#include "porter/planner/collision/collision_checker.hpp"

namespace porter::app {

/// A KernelCollisionChecker (kKernels) or a baselines::SphereCollisionChecker (kSpheres, without
/// self-collision: see the source) for `model` (payload attached), otherwise default settings.
/// The kernels are built at `resolution_m`, which must be the resolution of the maps given to
/// set_map() (the scene's). `model` must outlive the checker. Throws std::invalid_argument for a
/// resolution the kernels cannot use.
std::unique_ptr<planner::CollisionChecker> make_collision_checker(const RobotModel& model, double resolution_m,
                                                                  CollisionArg collision = CollisionArg::kKernels);

}  // namespace porter::app
