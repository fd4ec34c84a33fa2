#pragma once
// The acceptance test the pipeline uses today: the kernel collision check along the trajectory
// (KernelCollisionChecker::check_trajectory: environment, ground and self-collision, sampled so
// that no robot point moves more than the motion step between samples).
//
// Thread-safety: check() may run concurrently once the checker's map is set; the checker must
// outlive this object and keep its map during check().

#include <string>

#include "porter/planner/collision/collision_checker.hpp"
#include "porter/planner/trajectory_acceptance.hpp"

namespace porter::pipeline {

class KernelAcceptance final : public planner::TrajectoryAcceptance {
 public:
  explicit KernelAcceptance(const planner::CollisionChecker& checker) : checker_(checker) {}
  planner::AcceptanceResult check(const Trajectory& trajectory) const override {
    const planner::CollisionResult c = checker_.check_trajectory(trajectory);
    return planner::AcceptanceResult{!c.in_collision, c.link, c.other_link};
  }
  std::string name() const override { return checker_.name(); }

 private:
  const planner::CollisionChecker& checker_;
};

}  // namespace porter::pipeline
