#include "porter/pipeline/planner_settings.hpp"

#include <cmath>

#include "porter/backend/backend.hpp"
#include "porter/midend/midend.hpp"

namespace porter::pipeline {

namespace {
constexpr double kMaxStageBudgetS = 3600.0;
}  // namespace

bool validate_settings(const PlannerSettings& s, std::string* why) {
  auto fail = [why](const std::string& m) {
    if (why) *why = m;
    return false;
  };
  auto pos = [](double v) { return std::isfinite(v) && v > 0.0; };
  auto nonneg = [](double v) { return std::isfinite(v) && v >= 0.0; };
  const PipelineSettings& p = s.pipeline;
  // A stage budget above an hour is a unit mistake (ms given as s), not a plan anyone waits for.
  auto budget = [&](double v) { return pos(v) && v <= kMaxStageBudgetS; };
  if (!budget(p.frontend_budget_s)) return fail("pipeline.frontend_budget_s must be in (0, 3600] s");
  if (!budget(p.midend_budget_s)) return fail("pipeline.midend_budget_s must be in (0, 3600] s");
  if (!budget(p.backend_budget_s)) return fail("pipeline.backend_budget_s must be in (0, 3600] s");
  if (p.safety == baselines::SafetyModel::kSpheres)
    return fail("pipeline.safety must be kc_svsdf or svsdf_per_link (spheres follows from collision: spheres)");
  if (!(p.retry_arm_residual_scale > 0.0 && p.retry_arm_residual_scale <= 1.0))
    return fail("pipeline.retry_arm_residual_scale must be in (0, 1]");
  if (!nonneg(p.goal_position_tolerance_m)) return fail("pipeline.goal_position_tolerance_m must be >= 0");
  if (!nonneg(p.goal_yaw_tolerance_rad)) return fail("pipeline.goal_yaw_tolerance_rad must be >= 0");
  if (p.free_arm_candidates < 0) return fail("pipeline.free_arm_candidates must be >= 0");
  if (!pos(s.kernels.kernels.resolution_m)) return fail("kernels.resolution_m must be > 0");
  if (!nonneg(s.kernels.map.safety_margin_m)) return fail("kernels.safety_margin_m must be >= 0");
  if (!pos(s.kernels.map.distance_cap_m)) return fail("kernels.distance_cap_m must be > 0");
  if (!std::isfinite(s.kernels.motion_step_m)) return fail("kernels.motion_step_m must be finite");
  const backend::SelfCollisionTermSettings& sc = s.self_collision;
  if (!pos(sc.weight) || !pos(sc.sample_interval_s) || !pos(sc.point_spacing_m) || !nonneg(sc.slack_m) ||
      !nonneg(sc.warm_start_slack_m))
    return fail("self_collision: weight, sample_interval_s and point_spacing_m must be > 0, the slacks >= 0");
  if (!pos(s.safety_terms.svsdf.weight) || s.safety_terms.svsdf.threads < 1)
    return fail("safety_terms.svsdf: weight must be > 0 and threads >= 1");
  std::string inner;
  if (!frontend::validate_settings(s.frontend, &inner)) return fail("frontend: " + inner);
  if (!midend::validate_settings(s.midend, &inner)) return fail("midend: " + inner);
  if (!backend::validate_settings(s.backend, &inner)) return fail("backend: " + inner);
  return true;
}

}  // namespace porter::pipeline
