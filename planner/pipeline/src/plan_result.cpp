#include "porter/pipeline/plan_result.hpp"

namespace porter::pipeline {

std::vector<std::pair<std::string, double>> PlanResult::time_breakdown() const {
  std::vector<std::pair<std::string, double>> out;
  out.emplace_back("goal", goal.time_s);
  if (frontend) {
    out.emplace_back("frontend", frontend->elapsed_s);
    if (frontend->hybrid_astar.ran) out.emplace_back("frontend.hybrid_astar", frontend->hybrid_astar.elapsed_s);
    if (frontend->layered_arm.ran) out.emplace_back("frontend.layered_arm", frontend->layered_arm.elapsed_s);
    if (frontend->whole_body_rrt.ran) out.emplace_back("frontend.whole_body_rrt", frontend->whole_body_rrt.elapsed_s);
  }
  if (midend) {
    const midend::MidendResult& m = midend->result;
    out.emplace_back("midend", midend->time_s);
    out.emplace_back("midend.prepare", m.prepare_s);
    out.emplace_back("midend.optimize", m.optimize_s);
    out.emplace_back("midend.result_check", m.elapsed_s - m.prepare_s - m.optimize_s);
    out.emplace_back("midend.acceptance", midend->acceptance_s);
    if (!midend->retry.empty()) out.emplace_back("midend.self_check", midend->self_check_s);
  }
  if (backend) {
    const backend::BackendResult& b = backend->result;
    out.emplace_back("backend.setup", backend->setup_s);
    out.emplace_back("backend", b.elapsed_s);
    out.emplace_back("backend.selection", backend->selection_s);
    out.emplace_back("backend.prepare", b.prepare_s);
    out.emplace_back("backend.optimize", b.optimize_s);
    out.emplace_back("backend.safety_term", b.safety_s);
    out.emplace_back("backend.safety_prefilter", b.safety_prefilter_s);
    out.emplace_back("backend.self_collision_term", b.self_collision_s);
    out.emplace_back("backend.rechecks", b.recheck_s);
    out.emplace_back("backend.acceptance", b.check_s);
  }
  out.emplace_back("total", total_s);
  return out;
}

}  // namespace porter::pipeline
