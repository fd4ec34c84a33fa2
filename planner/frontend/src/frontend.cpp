#include "porter/frontend/frontend.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "porter/planner/deadline.hpp"

namespace porter::frontend {

bool validate_settings(const FrontendSettings& s, std::string* why) {
  if (!validate_settings(s.hybrid_astar, why) || !validate_settings(s.layered_arm, why) ||
      !validate_settings(s.whole_body_rrt, why) || !validate_settings(s.time_allocation, why))
    return false;
  auto bad = [&](const char* field) {
    if (why) *why = std::string("FrontendSettings.") + field + " out of range";
    return false;
  };
  if (!(s.hybrid_astar_budget_fraction > 0.0 && s.hybrid_astar_budget_fraction <= 1.0)) return bad("hybrid_astar_budget_fraction");
  if (!(s.layered_arm_budget_fraction > 0.0 && s.layered_arm_budget_fraction <= 1.0)) return bad("layered_arm_budget_fraction");
  if (!(s.arm_time_scale > 0.0)) return bad("arm_time_scale");
  if (!(s.min_layer_time_s > 0.0)) return bad("min_layer_time_s");
  if (s.bridge_margin_layers < 0) return bad("bridge_margin_layers");
  return true;
}

FrontEnd::FrontEnd(const RobotModel& model, const planner::CollisionChecker& checker, FrontendSettings settings)
    : model_(model), checker_(checker), settings_(settings), hybrid_astar_(model, checker, settings.hybrid_astar),
      layered_arm_(model, checker, settings.layered_arm) {}

void FrontEnd::set_map(const OccupancyGrid& occupancy_W) {
  hybrid_astar_.set_map(occupancy_W);
  const Eigen::AlignedBox3d b = occupancy_W.bounds_W();
  map_xy_W_ = Eigen::AlignedBox2d(b.min().head<2>(), b.max().head<2>());
  have_map_ = true;
}

std::string FrontEnd::validate_endpoint(const RobotConfiguration& c) const {
  if (!std::isfinite(c.base.x_m) || !std::isfinite(c.base.y_m) || !std::isfinite(c.base.yaw_rad) ||
      !c.q_rad.allFinite())
    return "non-finite value";
  if (!map_xy_W_.contains(Eigen::Vector2d(c.base.x_m, c.base.y_m))) return "base position outside the map bounds";
  if (!model_.within_joint_limits(c.q_rad, 1e-9)) {
    const JointVector lo = model_.lower_limits(), hi = model_.upper_limits();
    for (int j = 0; j < kNumArmJoints; ++j) {
      if (c.q_rad[j] < lo[j] - 1e-9 || c.q_rad[j] > hi[j] + 1e-9)
        return "joint " + std::to_string(j + 1) + " = " + std::to_string(c.q_rad[j]) + " rad outside [" +
               std::to_string(lo[j]) + ", " + std::to_string(hi[j]) + "]";
    }
  }
  const planner::CollisionResult r = checker_.check(c);
  if (r.in_collision) {
    std::string why = "in collision: link " + std::to_string(r.link);
    if (r.other_link >= 0) why += " with link " + std::to_string(r.other_link) + " (self-collision)";
    else why += " with the environment or the ground";
    return why;
  }
  return "";
}

planner::WholeBodyPath make_path(const std::vector<WholeBodySample>& samples, const std::vector<double>& dt) {
  planner::WholeBodyPath path;
  if (samples.empty()) return path;
  double t = 0.0;
  planner::PathSegment seg;
  seg.eta = samples.size() > 1 ? samples[1].eta : samples[0].eta;
  seg.nodes.push_back({samples[0].config, 0.0});
  for (std::size_t i = 1; i < samples.size(); ++i) {
    t += dt[i - 1];
    const planner::PathNode node{samples[i].config, t};
    if (samples[i].eta != seg.eta) {
      const planner::PathNode shared = seg.nodes.back();
      path.segments.push_back(std::move(seg));
      seg = planner::PathSegment{};
      seg.eta = samples[i].eta;
      seg.nodes.push_back(shared);
    }
    seg.nodes.push_back(node);
  }
  path.segments.push_back(std::move(seg));
  return path;
}

FrontendResult FrontEnd::plan(const RobotConfiguration& start, const RobotConfiguration& goal,
                              const planner::Deadline& budget, std::uint64_t seed) {
  const planner::Deadline deadline = budget.from_now();
  const double budget_s = deadline.budget_s();
  FrontendResult out;
  auto finish = [&](planner::Status st, std::string msg) {
    if (deadline.canceled() && st != planner::Status::kSuccess) {
      // The sub-stages saw an expired deadline; say why it expired.
      st = planner::Status::kCanceled;
      for (StageReport* r : {&out.hybrid_astar, &out.layered_arm, &out.whole_body_rrt})
        if (r->ran && r->status == planner::Status::kTimeout) r->status = planner::Status::kCanceled;
    }
    out.status = st;
    out.message = std::move(msg);
    out.elapsed_s = deadline.elapsed_s();
    return out;
  };
  if (!have_map_) return finish(planner::Status::kNoMap, "FrontEnd::set_map() was not called");
  if (std::string why = validate_endpoint(start); !why.empty()) return finish(planner::Status::kInvalidStart, "start " + why);
  if (std::string why = validate_endpoint(goal); !why.empty()) return finish(planner::Status::kInvalidGoal, "goal " + why);

  const FrontendSettings& s = settings_;
  WholeBodyRrt rrt(model_, checker_, hybrid_astar_.turning_radius_m(), map_xy_W_, s.whole_body_rrt);
  auto finish_with = [&](const std::vector<WholeBodySample>& samples) {
    out.path = make_path(samples, whole_body_step_times(model_, samples, s.time_allocation));
    return finish(planner::Status::kSuccess, "");
  };

  // 1. Hybrid A* for the base.
  const HybridAStarResult base = hybrid_astar_.plan(start, goal, deadline.within(s.hybrid_astar_budget_fraction * budget_s));
  out.hybrid_astar = base.report;
  if (base.report.status == planner::Status::kTimeout) {
    const WholeBodyRrtResult wb = rrt.plan(start, goal, deadline, seed ^ 0x9e3779b97f4a7c15ull);
    out.whole_body_rrt = wb.report;
    if (wb.report.status != planner::Status::kSuccess)
      return finish(wb.report.status, "Hybrid A*: " + base.report.message + "; whole-body RRT*: " + wb.report.message);
    out.used_fallback = true;
    return finish_with(wb.path);
  }
  if (base.report.status != planner::Status::kSuccess) return finish(base.report.status, "Hybrid A*: " + base.report.message);

  // 2. Layers and their times.
  const std::size_t n = base.path.size();
  out.num_layers = static_cast<int>(n);
  ArmLayerProblem problem;
  problem.q_start = start.q_rad;
  problem.q_goal = goal.q_rad;
  for (const BaseSample& b : base.path) problem.bases.push_back(b.pose);
  problem.dt_s = base_step_times(model_, base.path, s.time_allocation);
  for (double& dt : problem.dt_s) dt = std::max(s.min_layer_time_s, s.arm_time_scale * dt);

  // 3. Layered arm search.
  const LayeredArmResult arm = layered_arm_.plan(problem, deadline.within(s.layered_arm_budget_fraction * deadline.remaining_s()), seed);
  out.layered_arm = arm.report;
  std::vector<WholeBodySample> samples;
  if (arm.report.status == planner::Status::kSuccess) {
    for (std::size_t i = 0; i < n; ++i) samples.push_back({{base.path[i].pose, arm.q[i]}, base.path[i].eta});
    return finish_with(samples);
  }
  if (arm.report.status == planner::Status::kInvalidStart || arm.report.status == planner::Status::kInvalidGoal)
    return finish(arm.report.status, "layered arm search: " + arm.report.message);

  // 4. Bridge the gap between the two trees with the whole-body RRT*.
  const int a_deep = static_cast<int>(arm.forward_q.size()) - 1;
  const int b_deep = static_cast<int>(n) - static_cast<int>(arm.backward_q.size());
  // The trees may overlap without connecting: then bridge around the middle of the overlap.
  const int a_end = b_deep > a_deep ? a_deep : (a_deep + b_deep) / 2;
  const int b_end = b_deep > a_deep ? b_deep : a_end + 1;
  const int a = std::max(0, a_end - s.bridge_margin_layers);
  const int b = std::min(static_cast<int>(n) - 1, b_end + s.bridge_margin_layers);
  const RobotConfiguration from{base.path[static_cast<std::size_t>(a)].pose, arm.forward_q[static_cast<std::size_t>(a)]};
  const RobotConfiguration to{base.path[static_cast<std::size_t>(b)].pose, arm.backward_q[static_cast<std::size_t>(b - b_deep)]};
  const WholeBodyRrtResult wb = rrt.plan(from, to, deadline, seed ^ 0x9e3779b97f4a7c15ull);
  out.whole_body_rrt = wb.report;
  if (wb.report.status != planner::Status::kSuccess) {
    const planner::Status st = wb.report.status == planner::Status::kTimeout || arm.report.status == planner::Status::kTimeout
                                 ? planner::Status::kTimeout
                                 : planner::Status::kNoPath;
    return finish(st, "layered arm search: " + arm.report.message + "; whole-body RRT* bridge (layers " +
                          std::to_string(a) + ".." + std::to_string(b) + "): " + wb.report.message);
  }
  out.used_fallback = true;
  for (int i = 0; i <= a; ++i)
    samples.push_back({{base.path[static_cast<std::size_t>(i)].pose, arm.forward_q[static_cast<std::size_t>(i)]},
                       base.path[static_cast<std::size_t>(i)].eta});
  for (std::size_t k = 1; k + 1 < wb.path.size(); ++k) samples.push_back(wb.path[k]);
  for (int i = b; i < static_cast<int>(n); ++i) {
    WholeBodySample smp{{base.path[static_cast<std::size_t>(i)].pose, arm.backward_q[static_cast<std::size_t>(i - b_deep)]},
                        base.path[static_cast<std::size_t>(i)].eta};
    if (i == b && wb.path.size() > 1) smp.eta = wb.path.back().eta;  // reached by the bridge's last motion
    samples.push_back(smp);
  }
  if (samples.size() > 1) samples.front().eta = samples[1].eta;
  return finish_with(samples);
}

}  // namespace porter::frontend
