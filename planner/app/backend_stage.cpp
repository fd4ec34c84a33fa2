#include "backend_stage.hpp"

#include <array>
#include <chrono>
#include <memory>
#include <optional>

#include "porter/backend/backend.hpp"
#include "porter/backend/recheck_margins.hpp"
#include "porter/backend/robot_sdf.hpp"
#include "porter/baselines/safety_models.hpp"
#include "porter/planner/collision/kernel_collision_checker.hpp"

namespace porter::app {

BackendRun run_backend(const PlanArgs& args, const RobotModel& model, const OccupancyGrid& grid_W,
                       const planner::WholeBodyPath& path, const Trajectory& warm_start,
                       const midend::MidendSettings& midend_settings, const planner::CollisionChecker& recheck) {
  using Clock = std::chrono::steady_clock;
  BackendRun run;
  run.budget_s = args.backend_budget_ms * 1e-3;
  baselines::SafetyModel model_kind = baselines::SafetyModel::kKcSvsdf;
  if (args.collision == CollisionArg::kSpheres) {
    model_kind = baselines::SafetyModel::kSpheres;
  } else if (args.safety == SafetyArg::kSvsdfPerLink) {
    model_kind = baselines::SafetyModel::kSvsdfPerLink;
  }
  run.safety_model = baselines::to_string(model_kind);

  const auto t0 = Clock::now();
  std::optional<backend::RobotSdf> sdf;
  if (model_kind != baselines::SafetyModel::kSpheres) sdf = backend::RobotSdf::build(model);
  run.setup_s = std::chrono::duration<double>(Clock::now() - t0).count();
  // s_thr per link from the re-check's inflation (recheck_margins.hpp): a trajectory with a zero
  // penalty then passes the kernel check.
  baselines::SafetyTermSettings term_settings;
  if (const auto* kernels = dynamic_cast<const planner::KernelCollisionChecker*>(&recheck); kernels && sdf) {
    std::array<double, kNumLinks> inflation{};
    for (int j = 0; j < kNumLinks; ++j) inflation[static_cast<std::size_t>(j)] = kernels->kernels().inflation_bound_m(j);
    backend::apply_recheck_margins(backend::recheck_margins(inflation, grid_W.resolution_m(), *sdf), term_settings.svsdf);
  }
  std::unique_ptr<backend::SafetyTerm> term =
      baselines::make_safety_term(model_kind, model, sdf ? &*sdf : nullptr, term_settings);

  backend::BackendSettings settings;
  settings.problem = midend_settings;
  settings.max_iterations = args.backend_max_iterations;
  const backend::BackEnd solver(model, settings);
  run.result = solver.solve(path, warm_start, grid_W, *term, run.budget_s, &recheck);
  return run;
}

}  // namespace porter::app
