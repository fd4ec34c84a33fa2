#include "checker_factory.hpp"

#include "porter/baselines/sphere_collision_checker.hpp"
#include "porter/planner/collision/kernel_collision_checker.hpp"

namespace porter::app {

std::unique_ptr<planner::CollisionChecker> make_collision_checker(const RobotModel& model, double resolution_m,
                                                                  CollisionArg collision) {
  if (collision == CollisionArg::kSpheres) {
    // The cover inflates every link by up to 10 cm: the arm's spheres overlap the base's at the
    // scenes' start pose, so the baseline's self-collision test would reject every start. Its
    // self-collision is left to the kernel re-check of the final trajectory.
    baselines::SphereCheckerSettings settings;
    settings.check_self_collision = false;
    return std::make_unique<baselines::SphereCollisionChecker>(model, settings);
  }
  planner::KernelCheckerSettings settings;
  settings.kernels.resolution_m = resolution_m;
  return std::make_unique<planner::KernelCollisionChecker>(model, settings);
}

}  // namespace porter::app
