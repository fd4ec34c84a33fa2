#include "porter/planner/collision/kernel_robot.hpp"

#include <atomic>

namespace porter::planner {

namespace {
std::atomic<std::int64_t> g_builds{0};
}  // namespace

KernelRobot::KernelRobot(const RobotModel& model, const KernelCheckerSettings& settings)
    : settings_(settings),
      kernels_(model, settings.kernels),
      kinematics_(model),
      self_(model, settings.self),
      motion_step_m_(settings.motion_step_m > 0.0 ? settings.motion_step_m : settings.kernels.resolution_m) {
  g_builds.fetch_add(1, std::memory_order_relaxed);
}

std::int64_t KernelRobot::build_count() { return g_builds.load(std::memory_order_relaxed); }

}  // namespace porter::planner
