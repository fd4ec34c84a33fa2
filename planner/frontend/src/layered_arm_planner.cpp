#include "porter/frontend/layered_arm_planner.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <utility>

#include "layered_arm_search.hpp"
#include "porter/planner/deadline.hpp"

namespace porter::frontend {

bool validate_settings(const LayeredArmSettings& s, std::string* why) {
  auto bad = [&](const char* field) {
    if (why) *why = std::string("LayeredArmSettings.") + field + " out of range";
    return false;
  };
  if (!(s.arm_speed_fraction > 0.0 && s.arm_speed_fraction <= 1.0)) return bad("arm_speed_fraction");
  if (!(s.goal_bias >= 0.0 && s.goal_bias <= 1.0)) return bad("goal_bias");
  if (!(s.frontier_bias >= 0.0 && s.frontier_bias <= 1.0)) return bad("frontier_bias");
  if (!(s.local_bias >= 0.0 && s.goal_bias + s.local_bias <= 1.0)) return bad("local_bias");
  if (!(s.hold_bias >= 0.0 && s.hold_bias <= 1.0)) return bad("hold_bias");
  if (!(s.corridor_bias >= 0.0 && s.goal_bias + s.local_bias + s.corridor_bias <= 1.0)) return bad("corridor_bias");
  if (!(s.corridor_target_bias >= 0.0 && s.corridor_target_bias <= 1.0)) return bad("corridor_target_bias");
  if (s.corridor_draws < 1) return bad("corridor_draws");
  if (s.max_corridor_targets < 0) return bad("max_corridor_targets");
  if (!(s.corridor_margin_m >= 0.0)) return bad("corridor_margin_m");
  if (s.chain_retries < 0) return bad("chain_retries");
  if (s.frontier_window < 1) return bad("frontier_window");
  if (s.max_parent_candidates < 1) return bad("max_parent_candidates");
  if (s.max_connect_candidates < 1) return bad("max_connect_candidates");
  if (s.refine_iterations < 0) return bad("refine_iterations");
  if (s.shortcut_attempts < 0) return bad("shortcut_attempts");
  if (s.shortcut_max_layers < 2) return bad("shortcut_max_layers");
  if (s.max_iterations < 1) return bad("max_iterations");
  return true;
}

LayeredArmPlanner::LayeredArmPlanner(const RobotModel& model, const planner::CollisionChecker& checker,
                                     LayeredArmSettings settings)
    : model_(model), checker_(checker), settings_(settings) {}

LayeredArmResult LayeredArmPlanner::plan(const ArmLayerProblem& problem, const planner::Deadline& budget,
                                         std::uint64_t seed) const {
  const planner::Deadline deadline = budget.from_now();
  LayeredArmResult out;
  out.report.ran = true;
  const int n = static_cast<int>(problem.bases.size());
  if (n < 2 || problem.dt_s.size() + 1 != problem.bases.size()) {
    out.report.status = planner::Status::kNoPath;
    out.report.message = "malformed problem: need N >= 2 layers and N-1 layer times";
    return out;
  }
  for (double dt : problem.dt_s) {
    if (!(dt > 0.0) || !std::isfinite(dt)) {
      out.report.status = planner::Status::kNoPath;
      out.report.message = "malformed problem: layer times must be positive";
      return out;
    }
  }
  detail::LayeredArmSearch search(model_, checker_, settings_, problem, seed, out.report);
  out.report.status = search.run(deadline, out);
  if (out.report.status == planner::Status::kInvalidStart) out.report.message = "arm start configuration in collision";
  if (out.report.status == planner::Status::kInvalidGoal) out.report.message = "arm goal configuration in collision";
  if (out.report.status == planner::Status::kTimeout) out.report.message = "no connection within the budget";
  if (out.report.status == planner::Status::kNoPath && out.report.message.empty())
    out.report.message = "layers cannot be connected";
  out.report.elapsed_s = deadline.elapsed_s();
  return out;
}

}  // namespace porter::frontend
