#include "checker_factory.hpp"

#include "porter/planner/collision/kernel_collision_checker.hpp"

namespace porter::app {

std::unique_ptr<planner::CollisionChecker> make_collision_checker(const RobotModel& model) {
  return std::make_unique<planner::KernelCollisionChecker>(model);
}

}  // namespace porter::app
