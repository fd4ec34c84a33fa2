#include "plan_result_json.hpp"

#include "porter/core/trajectory_json.hpp"

#include <cmath>

#include <nlohmann/json.hpp>

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

json stage_json(const frontend::StageReport& s) {
  return json{{"ran", s.ran},
              {"status", s.ran ? frontend::to_string(s.status) : "not_run"},
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
      const RobotConfiguration& c = n.config;
      nodes.push_back(json{{"t_s", n.time_s},
                           {"base", {c.base.x_m, c.base.y_m, c.base.yaw_rad}},
                           {"q_rad", std::vector<double>(c.q_rad.data(), c.q_rad.data() + kNumArmJoints)}});
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

json safety_json(const backend::BackendCost& c) {
  const double min_d = c.safety_stats.min_distance_m;
  return json{{"total", c.total()},
              {"safety", c.safety},
              {"violations", c.safety_stats.violations},
              {"inside", c.safety_stats.inside},
              {"self_collision", c.self_collision},
              {"self_violations", c.self_stats.violations},
              {"min_distance_m", std::isfinite(min_d) ? json(min_d) : json(nullptr)}};
}

json backend_json(const BackendRun& run) {
  const backend::BackendResult& r = run.result;
  json check = r.check == backend::SafetyCheck::kNotChecked
                   ? json(nullptr)
                   : json{{"checker", "kernels"},
                          {"collision_free", r.check == backend::SafetyCheck::kCollisionFree},
                          {"collision_link", r.collision_link},
                          {"time_ms", r.check_s * 1e3}};
  json out{{"status", backend::to_string(r.status)},
           {"reason", r.message},
           {"success", r.success()},
           {"safety_model", run.safety_model},
           {"self_collision_term", run.self_collision_term},
           {"warm_start", run.warm_start},  // 0: the reported mid-end solve's trajectory; 1: the first solve's
           {"warm_start_safety", run.warm_start_safety},
           {"selection_ms", run.selection_s * 1e3},
           {"time_ms", r.elapsed_s * 1e3},
           {"budget_ms", run.budget_s * 1e3},
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
           {"final_check", std::move(check)},
           {"initial_cost", safety_json(r.initial_cost)},
           {"final_cost", r.ok() ? safety_json(r.final_cost) : json(nullptr)}};
  out["duration_s"] = r.trajectory ? json(r.trajectory->total_duration_s()) : json(nullptr);
  return out;
}

}  // namespace

std::string plan_result_json(const PlanRunInfo& info, const frontend::FrontendResult* fe, const std::string& status,
                             int exit_code, const std::string& error, const midend::MidendResult* mid,
                             const BackendRun* be, const FinalCheck* final_check) {
  json doc;
  doc["format"] = "porter-plan-result/3";
  doc["status"] = status;
  doc["exit_code"] = exit_code;
  doc["error"] = error;
  doc["scene"] = json{{"file", info.scene_file}, {"name", info.scene_name}, {"seed", info.seed},
                      {"parameters", info.parameters}};
  doc["robot_file"] = info.robot_file;
  doc["payload_file"] = info.payload_file;
  doc["checker"] = info.checker;
  doc["stages"] = info.stages;
  doc["collision"] = info.collision;
  doc["safety"] = info.safety;
  doc["budgets_ms"] = json{{"frontend", info.frontend_budget_ms}, {"midend", info.midend_budget_ms},
                           {"backend", info.backend_budget_ms}};
  if (fe) {
    doc["frontend"] = json{{"status", frontend::to_string(fe->status)},
                           {"message", fe->message},
                           {"time_ms", fe->elapsed_s * 1e3},
                           {"budget_ms", info.frontend_budget_ms},
                           {"iterations", fe->hybrid_astar.iterations + fe->layered_arm.iterations +
                                              fe->whole_body_rrt.iterations},
                           {"num_layers", fe->num_layers},
                           {"used_fallback", fe->used_fallback},
                           {"stages", json{{"hybrid_astar", stage_json(fe->hybrid_astar)},
                                           {"layered_arm", stage_json(fe->layered_arm)},
                                           {"whole_body_rrt", stage_json(fe->whole_body_rrt)}}}};
    doc["path"] = fe->status == frontend::PlannerStatus::kSuccess ? path_json(fe->path) : json(nullptr);
  } else {
    doc["frontend"] = nullptr;
    doc["path"] = nullptr;
  }
  doc["midend"] = nullptr;
  doc["trajectory"] = nullptr;
  if (mid) {
    doc["midend"] = json{{"status", midend::to_string(mid->status)},
                         {"message", mid->message},
                         {"time_ms", mid->elapsed_s * 1e3},
                         {"optimize_ms", mid->optimize_s * 1e3},
                         {"validate_ms", mid->validate_s * 1e3},
                         {"iterations", mid->iterations},
                         {"evaluations", mid->evaluations},
                         {"num_pieces", mid->num_pieces},
                         {"num_segments", mid->num_segments},
                         {"execution", midend::to_string(mid->execution)},
                         {"direct_execution", mid->execution == midend::Execution::kDirect},
                         {"retry", info.midend_retry.empty() ? json(nullptr) : json(info.midend_retry)},
                         {"residual_arm_bound_rad", info.midend_arm_residual_bound_rad}};
    if (mid->trajectory) {
      doc["midend"]["duration_s"] = mid->trajectory->total_duration_s();
      doc["trajectory"] = json::parse(to_json(*mid->trajectory));
    }
  }
  doc["backend"] = be ? backend_json(*be) : json(nullptr);
  if (be && be->result.trajectory) doc["trajectory"] = json::parse(to_json(*be->result.trajectory));
  doc["final_check"] = nullptr;
  if (final_check) {
    doc["final_check"] = json{{"checker", "kernels"},
                              {"stage", final_check->stage},
                              {"collision_free", final_check->collision_free},
                              {"collision_link", final_check->collision_link},
                              {"check_ms", final_check->check_ms}};
  }
  return doc.dump(2) + "\n";
}

}  // namespace porter::app
