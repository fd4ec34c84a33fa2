#include "porter/planner_daemon/replan.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace porter::planner_daemon {

RobotConfiguration configuration_at(const Trajectory& trajectory, double t_s) {
  const TrajVector z = trajectory.position(t_s);
  RobotConfiguration c;
  c.base.x_m = z[0];
  c.base.y_m = z[1];
  c.base.yaw_rad = trajectory.yaw_rad(t_s);
  c.q_rad = z.tail<kNumArmJoints>();
  return c;
}

std::optional<double> first_collision_s(const planner::KernelCollisionChecker& checker, const Trajectory& trajectory,
                                        double t_from_s, double step_s) {
  const double total = trajectory.total_duration_s();
  const double t0 = std::clamp(t_from_s, 0.0, total);
  const Trajectory tail = trajectory_tail(trajectory, t0);
  if (!checker.check_trajectory(tail).in_collision) return std::nullopt;
  // Find the first colliding piece of the tail, then its first colliding sample.
  for (int i = 0; i < tail.num_pieces(); ++i) {
    const double start = tail.piece_start_time_s(i);
    const double end = start + tail.piece(i).duration_s;
    std::vector<TrajectoryPiece> one{tail.piece(i)};
    const Trajectory piece = *Trajectory::create(std::move(one), tail.yaw_rad(start)).trajectory;
    if (!checker.check_trajectory(piece).in_collision) continue;
    for (double t = start;; t += step_s) {
      const double tc = std::min(t, end);
      if (checker.check(configuration_at(tail, tc)).in_collision) return t0 + tc;
      if (tc >= end) break;
    }
    return t0 + start;
  }
  return t0;  // the whole tail collides but no single piece does: only at a junction
}

const char* to_string(HandoffAction a) {
  switch (a) {
    case HandoffAction::kNone: return "none";
    case HandoffAction::kReplan: return "replan";
    case HandoffAction::kBrake: return "brake";
  }
  return "?";
}

HandoffChoice choose_handoff(const Trajectory& trajectory, double now_s, std::optional<double> collision_s,
                             const HandoffParams& params) {
  HandoffChoice c;
  if (!collision_s) return c;
  const double total = trajectory.total_duration_s();
  char b[200];
  const double t_replan = std::min(now_s + params.lead_s, total);
  const double stop_replan = t_replan + 0.5 * braking_trajectory(trajectory, t_replan, params.braking).total_duration_s();
  if (std::min(stop_replan, total) < *collision_s) {
    c.action = HandoffAction::kReplan;
    c.handoff_s = t_replan;
    c.stop_s = stop_replan;
    std::snprintf(b, sizeof b, "collision ahead at t = %.2f s (in %.2f s): re-plan from t = %.2f s", *collision_s,
                  *collision_s - now_s, t_replan);
  } else {
    const double t_brake = std::min(now_s + params.latency_s, total);
    c.action = HandoffAction::kBrake;
    c.handoff_s = t_brake;
    c.stop_s = t_brake + 0.5 * braking_trajectory(trajectory, t_brake, params.braking).total_duration_s();
    std::snprintf(b, sizeof b, "collision ahead at t = %.2f s (in %.2f s): too close to re-plan, braking from t = %.2f s",
                  *collision_s, *collision_s - now_s, t_brake);
  }
  c.reason = b;
  return c;
}

std::string map_age_problem(std::int64_t map_utime, std::int64_t now_utime, double max_age_s) {
  const double age_s = static_cast<double>(now_utime - map_utime) * 1e-6;
  if (std::abs(age_s) <= max_age_s) return "";
  char b[160];
  if (age_s > 0) {
    std::snprintf(b, sizeof b, "map is %.2f s old, limit %.2f s", age_s, max_age_s);
  } else {
    std::snprintf(b, sizeof b, "map is stamped %.2f s in the future (clocks disagree), limit %.2f s", -age_s, max_age_s);
  }
  return b;
}

}  // namespace porter::planner_daemon
