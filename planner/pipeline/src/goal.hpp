#pragma once
// Private to porter::pipeline: turning a GoalSpec into the goal configuration the front-end plans
// to, and the endpoint test shared with the start.
//
// An endpoint is valid when its values are finite, its base origin lies inside the map
// horizontally, its joints are within their limits and the front-end's checker finds it
// collision-free (the front-end's own test, so that it never refuses what was chosen here).
//
// Goal: the exact base pose with the fixed arm when valid. A free arm tries the start's arm first,
// then free_arm_candidates seeded random configurations within the limits, nearest to the start's
// first. When no arm fits at the exact pose and the tolerances allow, base poses within them are
// tried in order of (|dp| / tol_p)^2 + (|dyaw| / tol_yaw)^2: positions on rings one voxel apart
// (at most 8 rings), headings in quarters of the yaw tolerance. At most kMaxGoalChecks
// configurations are checked in all.

#include <cstdint>
#include <string>

#include <Eigen/Geometry>

#include "porter/core/robot_model.hpp"
#include "porter/pipeline/plan_request.hpp"
#include "porter/pipeline/plan_result.hpp"
#include "porter/pipeline/planner_settings.hpp"
#include "porter/planner/collision/collision_checker.hpp"

namespace porter::pipeline::detail {

inline constexpr int kMaxGoalChecks = 20000;

/// Why `c` cannot be a start or goal ("" when it can).
std::string endpoint_problem(const RobotModel& model, const planner::CollisionChecker& checker,
                             const Eigen::AlignedBox2d& map_xy_W, const RobotConfiguration& c);

/// The goal configuration for `goal` (GoalReport::status kSuccess or kInvalidGoal). Tolerances
/// below zero are replaced by the settings' defaults.
GoalReport resolve_goal(const RobotModel& model, const planner::CollisionChecker& checker,
                        const Eigen::AlignedBox2d& map_xy_W, double voxel_m, const GoalSpec& goal,
                        const JointVector& start_q_rad, const PipelineSettings& settings, std::uint64_t seed);

}  // namespace porter::pipeline::detail
