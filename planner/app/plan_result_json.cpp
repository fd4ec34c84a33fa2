#include "plan_result_json.hpp"

#include <cmath>

#include <nlohmann/json.hpp>

#include "porter/core/trajectory_json.hpp"

namespace porter::app {

using nlohmann::json;

double path_length_m(const planner::WholeBodyPath& path) {
  double len = 0.0;
  for (const auto& seg : path.segments) {
    for (std::size_t i = 1; i < seg.nodes.size(); ++i) {
      const BasePose& a = seg.nodes[i - 1].config.base;
      const BasePose& b = seg.nodes[i].config.base;
      len += std::hypot(b.x_m - a.x_m, b.y_m - a.y_m);
    }
  }
  return len;
}

namespace {

json config_json(const RobotConfiguration& c) {
  return json{{"base", {c.base.x_m, c.base.y_m, c.base.yaw_rad}},
              {"q_rad", std::vector<double>(c.q_rad.data(), c.q_rad.data() + kNumArmJoints)}};
}

json stage_json(const frontend::StageReport& s) {
  return json{{"ran", s.ran},
              {"status", s.ran ? planner::to_string(s.status) : "not_run"},
              {"time_ms", s.elapsed_s * 1e3},
              {"iterations", s.iterations},
              {"collision_checks", s.collision_checks},
              {"message", s.message}};
}

json path_json(const planner::WholeBodyPath& path) {
  json segs = json::array();
  for (const auto& seg : path.segments) {
    json nodes = json::array();
    for (const auto& n : seg.nodes) {
      json node = config_json(n.config);
      node["t_s"] = n.time_s;
      nodes.push_back(std::move(node));
    }
    segs.push_back(json{{"eta", seg.eta}, {"nodes", std::move(nodes)}});
  }
  const double duration = path.empty() || path.segments.back().nodes.empty() ? 0.0 : path.segments.back().nodes.back().time_s;
  return json{{"num_nodes", path.node_count()},
              {"num_segments", path.segments.size()},
              {"length_m", path_length_m(path)},
              {"duration_s", duration},
              {"segments", std::move(segs)}};
}

json frontend_json(const frontend::FrontendResult& fe, double budget_ms) {
  return json{{"status", planner::to_string(fe.status)},
              {"message", fe.message},
              {"time_ms", fe.elapsed_s * 1e3},
              {"budget_ms", budget_ms},
              {"iterations", fe.hybrid_astar.iterations + fe.layered_arm.iterations + fe.whole_body_rrt.iterations},
              {"num_layers", fe.num_layers},
              {"used_fallback", fe.used_fallback},
              {"stages", json{{"hybrid_astar", stage_json(fe.hybrid_astar)},
                              {"layered_arm", stage_json(fe.layered_arm)},
                              {"whole_body_rrt", stage_json(fe.whole_body_rrt)}}}};
}

json midend_json(const pipeline::MidendReport& m) {
  const midend::MidendResult& r = m.result;
  const bool direct = r.trajectory && m.acceptance.accepted;
  json out{{"status", planner::to_string(r.status)},
           {"message", r.message},
           {"time_ms", m.time_s * 1e3},
           {"prepare_ms", r.prepare_s * 1e3},
           {"optimize_ms", r.optimize_s * 1e3},
           {"validate_ms", m.acceptance_s * 1e3},
           {"iterations", r.iterations},
           {"evaluations", r.evaluations},
           {"num_pieces", r.num_pieces},
           {"num_segments", r.num_segments},
           {"execution", !r.trajectory ? "not checked"
                         : direct      ? "collision-free: direct execution, back-end skipped"
                                       : "in collision: back-end required"},
           {"direct_execution", direct},
           {"retry", m.retry.empty() ? json(nullptr) : json(m.retry)},
           {"residual_arm_bound_rad", m.residual_arm_bound_rad}};
  if (r.trajectory) out["duration_s"] = r.trajectory->total_duration_s();
  return out;
}

json cost_json(const backend::BackendCost& c) {
  const double min_d = c.safety_stats.min_distance_m;
  return json{{"total", c.total()},
              {"safety", c.safety},
              {"violations", c.safety_stats.violations},
              {"inside", c.safety_stats.inside},
              {"self_collision", c.self_collision},
              {"self_violations", c.self_stats.violations},
              {"min_distance_m", std::isfinite(min_d) ? json(min_d) : json(nullptr)}};
}

json backend_json(const pipeline::BackendReport& run, const std::string& checker) {
  const backend::BackendResult& r = run.result;
  json check = r.check == backend::SafetyCheck::kNotChecked
                   ? json(nullptr)
                   : json{{"checker", checker},
                          {"collision_free", r.check == backend::SafetyCheck::kCollisionFree},
                          {"collision_link", r.collision_link},
                          {"time_ms", r.check_s * 1e3}};
  json out{{"status", planner::to_string(r.status)},
           {"reason", r.message},
           {"success", r.success()},
           {"safety_model", run.safety_model},
           {"self_collision_term", run.self_collision_term},
           {"warm_start", run.warm_start},
           {"warm_start_safety", run.warm_start_safety},
           {"selection_ms", run.selection_s * 1e3},
           {"time_ms", r.elapsed_s * 1e3},
           {"budget_ms", run.budget_s * 1e3},
           {"prepare_ms", r.prepare_s * 1e3},
           {"optimize_ms", r.optimize_s * 1e3},
           {"safety_ms", r.safety_s * 1e3},
           {"self_collision_ms", r.self_collision_s * 1e3},
           {"setup_ms", run.setup_s * 1e3},
           {"iterations", r.iterations},
           {"evaluations", r.evaluations},
           {"rounds", r.rounds},
           {"rechecks", r.rechecks},
           {"recheck_ms", r.recheck_s * 1e3},
           {"probe_evaluations", r.probe_evaluations},
           {"safety_skips", r.safety_skips},
           {"num_pieces", r.num_pieces},
           {"num_variables", r.num_variables},
           {"window_flagged", r.window_flagged},
           {"window_solves", r.window_solves},
           {"window_pieces", r.window_pieces},
           {"window_fallback", r.window_fallback},
           {"window_localise_ms", r.window_localise_s * 1e3},
           {"final_check", std::move(check)},
           {"initial_cost", cost_json(r.initial_cost)},
           {"final_cost", r.ok() ? cost_json(r.final_cost) : json(nullptr)}};
  out["duration_s"] = r.trajectory ? json(r.trajectory->total_duration_s()) : json(nullptr);
  return out;
}

}  // namespace

std::string plan_result_json(const PlanRunInfo& info, const pipeline::PlanResult* result, const std::string& status,
                             int exit_code, const std::string& error) {
  json doc;
  doc["format"] = "porter-plan-result/4";
  doc["status"] = status;
  doc["exit_code"] = exit_code;
  doc["error"] = error;
  doc["scene"] = json{{"file", info.scene_file}, {"name", info.scene_name}, {"seed", info.seed},
                      {"parameters", info.parameters}};
  doc["robot_file"] = info.robot_file;
  doc["payload_file"] = info.payload_file;
  doc["planner_config"] = info.planner_config;
  doc["checker"] = info.checker;
  doc["acceptance"] = info.acceptance;
  doc["clearance_margin_m"] = info.clearance_margin_m >= 0.0 ? json(info.clearance_margin_m) : json(nullptr);
  doc["stages"] = info.stages;
  doc["collision"] = info.collision;
  doc["safety"] = info.safety;
  doc["budgets_ms"] = json{{"frontend", info.frontend_budget_ms}, {"midend", info.midend_budget_ms},
                           {"backend", info.backend_budget_ms}};
  doc["goal"] = nullptr;
  doc["frontend"] = nullptr;
  doc["path"] = nullptr;
  doc["midend"] = nullptr;
  doc["backend"] = nullptr;
  doc["final_check"] = nullptr;
  doc["trajectory"] = nullptr;
  doc["time_breakdown_ms"] = nullptr;
  doc["setup_ms"] = nullptr;
  if (!result) return doc.dump(2) + "\n";
  const pipeline::PlanResult& r = *result;
  if (r.goal.status != planner::Status::kNotRun) {
    json goal = config_json(r.goal.config);
    goal["status"] = planner::to_string(r.goal.status);
    goal["base_moved"] = r.goal.base_moved;
    goal["arm_chosen"] = r.goal.arm_chosen;
    goal["candidates"] = r.goal.candidates;
    goal["time_ms"] = r.goal.time_s * 1e3;
    doc["goal"] = std::move(goal);
  }
  if (r.frontend) {
    doc["frontend"] = frontend_json(*r.frontend, info.frontend_budget_ms);
    if (r.frontend->status == planner::Status::kSuccess) doc["path"] = path_json(r.frontend->path);
  }
  if (r.midend) doc["midend"] = midend_json(*r.midend);
  if (r.backend) doc["backend"] = backend_json(*r.backend, r.final_check ? r.final_check->checker : "kernels");
  if (r.final_check) {
    doc["final_check"] = json{{"checker", r.final_check->checker},
                              {"stage", r.final_check->stage},
                              {"collision_free", r.final_check->result.accepted},
                              {"collision_link", r.final_check->result.accepted ? -1 : r.final_check->result.link},
                              {"check_ms", r.final_check->time_s * 1e3}};
  }
  if (r.trajectory) doc["trajectory"] = json::parse(to_json(*r.trajectory));
  json times = json::object();
  for (const auto& [name, s] : r.time_breakdown()) times[name] = s * 1e3;
  doc["time_breakdown_ms"] = std::move(times);
  doc["setup_ms"] = r.setup_s * 1e3;
  return doc.dump(2) + "\n";
}

}  // namespace porter::app
