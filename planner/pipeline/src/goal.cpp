#include "goal.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>
#include <vector>

#include "porter/planner/angle.hpp"

namespace porter::pipeline::detail {

namespace {

constexpr double kPi = 3.14159265358979323846;

struct BaseOffset {
  double dx = 0.0, dy = 0.0, dyaw = 0.0, cost = 0.0;
};

/// Base offsets within the tolerances, cheapest first (the exact pose first).
std::vector<BaseOffset> base_offsets(double tol_p, double tol_yaw, double voxel_m) {
  std::vector<BaseOffset> out;
  std::vector<double> radii{0.0};
  if (tol_p > 0.0) {
    const double step = std::max(voxel_m, tol_p / 8.0);
    for (double r = step; r <= tol_p + 1e-12; r += step) radii.push_back(r);
  }
  std::vector<double> yaws{0.0};
  if (tol_yaw > 0.0) {
    for (int k = 1; k <= 4; ++k) {
      yaws.push_back(k * tol_yaw / 4.0);
      yaws.push_back(-k * tol_yaw / 4.0);
    }
  }
  for (double r : radii) {
    const int n = r > 0.0 ? std::max(6, static_cast<int>(std::ceil(2.0 * kPi * r / std::max(voxel_m, 1e-3)))) : 1;
    for (int a = 0; a < n; ++a) {
      const double phi = 2.0 * kPi * a / n;
      for (double dyaw : yaws) {
        BaseOffset o;
        o.dx = r * std::cos(phi);
        o.dy = r * std::sin(phi);
        o.dyaw = dyaw;
        const double cp = tol_p > 0.0 ? r / tol_p : 0.0;
        const double cy = tol_yaw > 0.0 ? dyaw / tol_yaw : 0.0;
        o.cost = cp * cp + cy * cy;
        out.push_back(o);
      }
    }
  }
  std::stable_sort(out.begin(), out.end(), [](const BaseOffset& a, const BaseOffset& b) { return a.cost < b.cost; });
  return out;
}

/// The start's arm (clamped to the limits) then seeded random arms, nearest to the start's first.
std::vector<JointVector> free_arms(const RobotModel& model, const JointVector& start_q, int count, std::uint64_t seed) {
  const JointVector lo = model.lower_limits(), hi = model.upper_limits();
  std::vector<JointVector> out{start_q.cwiseMax(lo).cwiseMin(hi)};
  std::mt19937_64 rng(seed ^ 0x6a09e667f3bcc909ull);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<JointVector> random;
  for (int k = 0; k < count; ++k) {
    JointVector q;
    for (int j = 0; j < kNumArmJoints; ++j) q[j] = lo[j] + u(rng) * (hi[j] - lo[j]);
    random.push_back(q);
  }
  std::stable_sort(random.begin(), random.end(), [&](const JointVector& a, const JointVector& b) {
    return (a - start_q).squaredNorm() < (b - start_q).squaredNorm();
  });
  out.insert(out.end(), random.begin(), random.end());
  return out;
}

}  // namespace

std::string endpoint_problem(const RobotModel& model, const planner::CollisionChecker& checker,
                             const Eigen::AlignedBox2d& map_xy_W, const RobotConfiguration& c) {
  if (!std::isfinite(c.base.x_m) || !std::isfinite(c.base.y_m) || !std::isfinite(c.base.yaw_rad) ||
      !c.q_rad.allFinite())
    return "non-finite value";
  if (!map_xy_W.contains(Eigen::Vector2d(c.base.x_m, c.base.y_m))) return "base position outside the map bounds";
  const JointVector lo = model.lower_limits(), hi = model.upper_limits();
  for (int j = 0; j < kNumArmJoints; ++j) {
    if (c.q_rad[j] < lo[j] - 1e-9 || c.q_rad[j] > hi[j] + 1e-9)
      return "joint " + std::to_string(j + 1) + " = " + std::to_string(c.q_rad[j]) + " rad outside [" +
             std::to_string(lo[j]) + ", " + std::to_string(hi[j]) + "]";
  }
  const planner::CollisionResult r = checker.check(c);
  if (r.in_collision) {
    std::string why = "in collision: link " + std::to_string(r.link);
    if (r.other_link >= 0) why += " with link " + std::to_string(r.other_link) + " (self-collision)";
    else why += " with the environment or the ground";
    return why;
  }
  return "";
}

GoalReport resolve_goal(const RobotModel& model, const planner::CollisionChecker& checker,
                        const Eigen::AlignedBox2d& map_xy_W, double voxel_m, const GoalSpec& goal,
                        const JointVector& start_q_rad, const PipelineSettings& settings, std::uint64_t seed) {
  const auto t0 = std::chrono::steady_clock::now();
  GoalReport rep;
  const double tol_p = goal.position_tolerance_m >= 0.0 ? goal.position_tolerance_m : settings.goal_position_tolerance_m;
  const double tol_yaw = goal.yaw_tolerance_rad >= 0.0 ? goal.yaw_tolerance_rad : settings.goal_yaw_tolerance_rad;
  const std::vector<JointVector> arms =
      goal.arm_q_rad ? std::vector<JointVector>{*goal.arm_q_rad}
                     : free_arms(model, start_q_rad, std::max(0, settings.free_arm_candidates), seed);
  const std::vector<BaseOffset> offsets = base_offsets(tol_p, tol_yaw, voxel_m);
  std::string first_problem;
  for (const BaseOffset& o : offsets) {
    RobotConfiguration c;
    c.base = {goal.base.x_m + o.dx, goal.base.y_m + o.dy, planner::wrap_angle_rad(goal.base.yaw_rad + o.dyaw)};
    if (o.cost == 0.0) c.base.yaw_rad = goal.base.yaw_rad;  // the exact pose as given
    for (std::size_t k = 0; k < arms.size(); ++k) {
      c.q_rad = arms[k];
      ++rep.candidates;
      const std::string problem = endpoint_problem(model, checker, map_xy_W, c);
      if (problem.empty()) {
        rep.status = planner::Status::kSuccess;
        rep.config = c;
        rep.base_moved = o.cost > 0.0;
        rep.arm_chosen = !goal.arm_q_rad.has_value();
        rep.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        return rep;
      }
      if (first_problem.empty()) first_problem = problem;
      if (rep.candidates >= kMaxGoalChecks) break;
    }
    if (rep.candidates >= kMaxGoalChecks) break;
  }
  rep.status = planner::Status::kInvalidGoal;
  rep.config.base = goal.base;
  rep.config.q_rad = goal.arm_q_rad ? *goal.arm_q_rad : start_q_rad;
  rep.message = "goal " + first_problem;
  if (rep.candidates > 1)
    rep.message += " (and no valid goal among " + std::to_string(rep.candidates) + " configurations within the tolerance" +
                   (goal.arm_q_rad ? "" : " and the free arm") + ")";
  rep.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return rep;
}

}  // namespace porter::pipeline::detail
