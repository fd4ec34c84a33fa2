#include "plan_summary.hpp"

#include <cmath>
#include <cstdio>

#include "plan_result_json.hpp"

namespace porter::app {

std::string frontend_summary(const frontend::FrontendResult& r) {
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "front-end: %s %.1f ms, iterations %lld (hybrid_astar %lld, layered_arm %lld, whole_body_rrt %lld)",
                planner::to_string(r.status), r.elapsed_s * 1e3,
                static_cast<long long>(r.hybrid_astar.iterations + r.layered_arm.iterations + r.whole_body_rrt.iterations),
                static_cast<long long>(r.hybrid_astar.iterations), static_cast<long long>(r.layered_arm.iterations),
                static_cast<long long>(r.whole_body_rrt.iterations));
  std::string line = buf;
  if (r.status == planner::Status::kSuccess) {
    std::snprintf(buf, sizeof buf, ", nodes %zu, segments %zu, length %.2f m%s", r.path.node_count(),
                  r.path.segments.size(), path_length_m(r.path), r.used_fallback ? ", fallback used" : "");
    line += buf;
  } else {
    line += " -- " + r.message;
  }
  return line;
}

std::string midend_summary(const pipeline::MidendReport& m) {
  const midend::MidendResult& r = m.result;
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "mid-end: %s %.1f ms (prepare %.1f ms, optimize %.1f ms, check %.1f ms), iterations %d, evaluations %d, "
                "pieces %d",
                planner::to_string(r.status), m.time_s * 1e3, r.prepare_s * 1e3, r.optimize_s * 1e3, m.acceptance_s * 1e3,
                r.iterations, r.evaluations, r.num_pieces);
  std::string line = buf;
  if (r.trajectory) {
    std::snprintf(buf, sizeof buf, ", duration %.2f s, %s", r.trajectory->total_duration_s(),
                  m.acceptance.accepted ? "collision-free: direct execution, back-end skipped"
                                        : "in collision: back-end required");
    line += buf;
  } else {
    line += " -- " + r.message;
  }
  return line;
}

std::string backend_summary(const pipeline::BackendReport& run) {
  const backend::BackendResult& r = run.result;
  char buf[768];
  std::snprintf(buf, sizeof buf,
                "back-end: %s %.1f ms (prepare %.1f ms, optimize %.1f ms, safety term %.1f ms, self-collision term %.1f "
                "ms, check %.1f ms; sdf setup %.1f ms), iterations %d, evaluations %d, safety %s, J_s %.3g -> %.3g",
                planner::to_string(r.status), r.elapsed_s * 1e3, r.prepare_s * 1e3, r.optimize_s * 1e3,
                r.safety_s * 1e3, r.self_collision_s * 1e3, r.check_s * 1e3, run.setup_s * 1e3, r.iterations,
                r.evaluations, run.safety_model.c_str(), r.initial_cost.safety,
                r.ok() ? r.final_cost.safety : std::nan(""));
  std::string line = buf;
  if (r.ok()) {
    std::snprintf(buf, sizeof buf, ", kernel re-check: %s", backend::to_string(r.check));
    line += buf;
    if (r.check == backend::SafetyCheck::kInCollision) line += " (link " + std::to_string(r.collision_link) + ")";
  } else {
    line += " -- " + r.message;
  }
  return line;
}

}  // namespace porter::app
