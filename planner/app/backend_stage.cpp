#include "backend_stage.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include "porter/backend/backend.hpp"
#include "porter/backend/recheck_margins.hpp"
#include "porter/backend/robot_sdf.hpp"
#include "porter/baselines/safety_models.hpp"
#include "porter/planner/collision/kernel_collision_checker.hpp"

namespace porter::app {

BackendRun run_backend(const PlanArgs& args, const RobotModel& model, const OccupancyGrid& grid_W,
                       const planner::WholeBodyPath& path, const std::vector<BackendWarmStart>& warm_starts,
                       const planner::CollisionChecker& recheck) {
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
  // The self-collision penalty (self_collision_term.hpp) on the pairs the re-check examines, with
  // every safety model that has link SDFs.
  std::optional<backend::SelfCollisionTerm> self_term;
  if (const auto* kernels = dynamic_cast<const planner::KernelCollisionChecker*>(&recheck);
      kernels && sdf && args.self_collision_term) {
    const planner::SelfCollisionChecker& self = kernels->self_collision();
    self_term.emplace(model, *sdf, self.checked_pairs(), self.inflation_bound_m());
    run.self_collision_term = true;
  }

  // The warm start: with several, the one with the lowest J_s (the term's own measure of how deep
  // the trajectory is in collision), at one evaluation each, taken from the budget.
  const auto t_select = Clock::now();
  if (warm_starts.size() > 1) {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < warm_starts.size(); ++i) {
      const Trajectory& t = *warm_starts[i].trajectory;
      term->prepare(grid_W, t);
      backend::TrajectoryGradient unused;
      unused.reset(t.num_pieces());
      const double js = term->evaluate(t, unused, nullptr);
      run.warm_start_safety.push_back(js);
      if (js < best) {
        best = js;
        run.warm_start = static_cast<int>(i);
      }
    }
  }
  run.selection_s = std::chrono::duration<double>(Clock::now() - t_select).count();
  const BackendWarmStart& chosen = warm_starts[static_cast<std::size_t>(run.warm_start)];

  backend::BackendSettings settings;
  settings.problem = chosen.settings;
  settings.max_iterations = args.backend_max_iterations;
  const backend::BackEnd solver(model, settings);
  const double budget = std::max(1e-3, run.budget_s - run.selection_s);
  run.result = solver.solve(path, *chosen.trajectory, grid_W, *term, budget, &recheck, self_term ? &*self_term : nullptr);
  run.result.elapsed_s += run.selection_s;
  return run;
}

}  // namespace porter::app
