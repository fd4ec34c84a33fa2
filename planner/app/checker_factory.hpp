#pragma once
// The collision checker porter-plan plans with (the paper's chain-decomposed kernels).

#include <memory>

#include "porter/core/robot_model.hpp"
#include "porter/planner/collision/collision_checker.hpp"

namespace porter::app {

/// A KernelCollisionChecker for `model` (payload attached) with default settings.
std::unique_ptr<planner::CollisionChecker> make_collision_checker(const RobotModel& model);

}  // namespace porter::app
