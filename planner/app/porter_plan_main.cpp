// porter-plan: loads a scene, plans, prints one summary line per stage and writes the JSON result.
// Usage and exit codes: plan_args.cpp / README.md.

#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "backend_stage.hpp"
#include "checker_factory.hpp"
#include "plan_args.hpp"
#include "plan_result_json.hpp"
#include "plan_summary.hpp"
#include "porter/core/load_error.hpp"
#include "porter/core/payload.hpp"
#include "porter/core/payload_loader.hpp"
#include "porter/core/robot_loader.hpp"
#include "porter/core/scene_loader.hpp"
#include "porter/core/scene_voxelizer.hpp"
#include "porter/frontend/frontend.hpp"
#include "porter/midend/midend.hpp"
#include "porter/planner/collision/kernel_collision_checker.hpp"

namespace {

// 5 ("stage not available") is retired: every stage is built (README.md).
enum ExitCode { kOk = 0, kPlanFailed = 1, kBadArgs = 2, kBadFile = 3, kInvalidEndpoint = 4 };

/// The arm residual bound of the mid-end's retry, relative to the first solve's. Measured on the
/// bridge ablation's self-colliding runs (seed 17 at every h_b: links 1-4, seed 13 at h_b = 0.8:
/// links 2-4): 0.5 and 0.25 both give collision-free trajectories; 0.5 keeps more freedom for the
/// obstacle terms.
constexpr double kRetryArmResidualScale = 0.5;

bool write_file(const std::string& path, const std::string& text) {
  std::ofstream f(path);
  f << text;
  return static_cast<bool>(f.flush());
}

using namespace porter;

/// The mid-end stage: the solve, and the retry below when its trajectory collides.
struct MidendStage {
  std::optional<midend::MidendResult> mid;  ///< the reported solve (times summed over both)
  planner::CollisionResult check;           ///< its kernel trajectory check
  midend::MidendSettings settings;          ///< the settings it was solved with
  /// The first solve when the retry replaced it but both collide: a second back-end warm start.
  std::optional<midend::MidendResult> first;
  midend::MidendSettings first_settings;
  std::string retry;                        ///< why the mid-end was solved again ("" if not)
};

// Not in the paper: a mid-end trajectory in collision is solved once more with the arm residual
// bound scaled by kRetryArmResidualScale, which keeps it closer to the front-end's arm path
// (collision-free by the kernel motion check, self-collision included). The retry replaces the
// first result when the first hits itself (the back-end's safety term sees obstacles only) or when
// the retry is collision-free (then executed directly); otherwise both go to the back-end, which
// starts from the one with the lower safety penalty (a retry that hits itself where the first did
// not is dropped). Why: on the bridge ablation the first solve can cut through the deck (h_b 1.1 m
// seeds 12 and 20: J_s 6 100 and 11 700 at the first solve, 4 200 and 1 200 at the retry; the
// back-end then needs 178 and 91 ms, choice included, instead of more than its 300 ms). With
// --stages mid only a self-collision is retried.
MidendStage run_midend(const app::PlanArgs& args, const RobotModel& model, const planner::WholeBodyPath& path,
                       const planner::CollisionChecker& kernels) {
  MidendStage st;
  const midend::MidEnd solver(model);
  st.settings = solver.settings();
  const double budget_s = args.midend_budget_ms * 1e-3;
  // The direct-execution test: the kernel trajectory check, its result kept in *found.
  auto kernel_validator = [&kernels](planner::CollisionResult* found) {
    return [&kernels, found](const Trajectory& t) {
      *found = kernels.check_trajectory(t);
      return !found->in_collision;
    };
  };
  st.mid = solver.solve(path, budget_s, kernel_validator(&st.check));
  const auto* kernel_checker = dynamic_cast<const planner::KernelCollisionChecker*>(&kernels);
  if (!st.mid->trajectory || !st.check.in_collision || !kernel_checker) return st;
  const planner::CollisionResult self = kernel_checker->check_trajectory_self(*st.mid->trajectory);
  if (!self.in_collision && args.stages != app::Stages::kFull) return st;

  midend::MidendSettings tight = st.settings;
  tight.residual_arm_bound_rad *= kRetryArmResidualScale;
  planner::CollisionResult retry_check;
  midend::MidendResult retry = midend::MidEnd(model, tight).solve(path, budget_s, kernel_validator(&retry_check));
  std::ostringstream why;
  if (self.in_collision) {
    why << "self-collision (links " << self.link << "-" << self.other_link << ")";
  } else {
    why << "in collision (link " << st.check.link << ")";
  }
  why << ": arm residual bound " << st.settings.residual_arm_bound_rad << " -> " << tight.residual_arm_bound_rad << " rad";
  st.retry = why.str();
  if (!args.quiet) std::cout << "mid-end: " << st.retry << ", solved again" << std::endl;
  if (!retry.trajectory) return st;
  // A retry that hits itself where the first did not is no use to the back-end either.
  const bool retry_self = retry_check.in_collision && !self.in_collision &&
                          kernel_checker->check_trajectory_self(*retry.trajectory).in_collision;
  // The stage's cost is both solves: times, iterations and evaluations add up.
  midend::MidendResult& kept = retry_self ? *st.mid : retry;
  const midend::MidendResult& other = retry_self ? retry : *st.mid;
  kept.elapsed_s += other.elapsed_s;
  kept.optimize_s += other.optimize_s;
  kept.validate_s += other.validate_s;
  kept.iterations += other.iterations;
  kept.evaluations += other.evaluations;
  if (retry_self) {
    st.retry += " (the retry hits itself: not used)";
    return st;
  }
  if (!self.in_collision && retry_check.in_collision) {  // both collide: a second warm start
    st.first = std::move(st.mid);
    st.first_settings = st.settings;
  }
  st.mid = std::move(retry);
  st.check = retry_check;
  st.settings = tight;
  return st;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace porter;
  app::PlanArgs args;
  try {
    args = app::parse_plan_args(argc, argv, PORTER_DEFAULT_ROBOT);
  } catch (const app::ArgsError& e) {
    std::cerr << "porter-plan: " << e.what() << "\n" << app::plan_usage();
    return kBadArgs;
  }
  if (args.help) {
    std::cout << app::plan_usage();
    return kOk;
  }
  app::PlanRunInfo info;
  info.scene_file = args.scene_path;
  info.robot_file = args.robot_path;
  info.stages = app::to_string(args.stages);
  info.collision = app::to_string(args.collision);
  info.safety = args.collision == app::CollisionArg::kSpheres ? "spheres" : app::to_string(args.safety);
  info.frontend_budget_ms = args.frontend_budget_ms;
  info.midend_budget_ms = args.midend_budget_ms;
  info.backend_budget_ms = args.backend_budget_ms;
  auto fail = [&](int code, const std::string& status, const std::string& msg) {
    std::cerr << "porter-plan: " << msg << "\n";
    if (args.out_path && !write_file(*args.out_path, app::plan_result_json(info, nullptr, status, code, msg))) {
      std::cerr << "porter-plan: cannot write '" << *args.out_path << "'\n";
      return static_cast<int>(kBadFile);
    }
    return code;
  };

  Scene scene;
  RobotModel model;
  try {
    SceneLoadOptions options;
    if (args.seed_given) options.seed = args.seed;
    options.parameter_overrides = args.overrides;
    scene = load_scene(args.scene_path, options);
    info.scene_name = scene.name;
    info.seed = scene.seed;
    info.parameters = scene.parameters;
    info.payload_file = args.payload_path ? *args.payload_path : scene.payload_file;
    const RobotModel bare = load_robot_model(args.robot_path);
    model = info.payload_file.empty() ? bare : attach_payload(bare, load_payload(info.payload_file));
  } catch (const LoadError& e) {
    return fail(kBadFile, "bad_input", e.what());
  } catch (const std::exception& e) {  // loaders throw LoadError; anything else is still bad input
    return fail(kBadFile, "bad_input", e.what());
  }

  // The front-end plans with the --collision model; the direct-execution test, the decision to run
  // the back-end and the final re-check are always the kernel trajectory check (comparable runs).
  OccupancyGrid grid;
  std::unique_ptr<planner::CollisionChecker> checker;
  std::unique_ptr<planner::CollisionChecker> kernel_owner;
  try {
    grid = voxelize(scene);
    checker = app::make_collision_checker(model, scene.resolution_m, args.collision);
    checker->set_map(grid);
    if (args.collision != app::CollisionArg::kKernels) {
      kernel_owner = app::make_collision_checker(model, scene.resolution_m, app::CollisionArg::kKernels);
      kernel_owner->set_map(grid);
    }
  } catch (const std::exception& e) {  // a resolution or map the checkers cannot use
    return fail(kBadFile, "bad_input", std::string("scene ") + args.scene_path + ": " + e.what());
  }
  info.checker = checker->name();
  const planner::CollisionChecker& kernels = kernel_owner ? *kernel_owner : *checker;
  frontend::FrontEnd fe(model, *checker);
  fe.set_map(grid);
  const frontend::FrontendResult result = fe.plan(scene.start, scene.goal, args.frontend_budget_ms * 1e-3, scene.seed);

  int code = kOk;
  if (result.status == frontend::PlannerStatus::kInvalidStart || result.status == frontend::PlannerStatus::kInvalidGoal)
    code = kInvalidEndpoint;
  else if (result.status != frontend::PlannerStatus::kSuccess)
    code = kPlanFailed;
  if (code == kInvalidEndpoint) std::cerr << "porter-plan: " << result.message << "\n";
  if (!args.quiet || code != kOk) std::cout << app::frontend_summary(result) << std::endl;
  std::string status = frontend::to_string(result.status);
  std::string error;

  // Mid-end (paper §V): MINCO over the front-end path; a trajectory the kernel check finds
  // collision-free is executed directly and the back-end is skipped.
  std::optional<midend::MidendResult> mid;
  std::optional<app::BackendRun> back;
  std::optional<app::FinalCheck> final_check;
  if (code == kOk && args.stages != app::Stages::kFront) {
    MidendStage stage = run_midend(args, model, result.path, kernels);
    mid = std::move(stage.mid);
    const planner::CollisionResult& mid_check = stage.check;
    const midend::MidendSettings& mid_settings = stage.settings;
    info.midend_retry = stage.retry;
    info.midend_arm_residual_bound_rad = mid_settings.residual_arm_bound_rad;
    status = midend::to_string(mid->status);
    if (!args.quiet || !mid->trajectory) std::cout << app::midend_summary(*mid) << std::endl;
    if (!mid->trajectory) {
      code = kPlanFailed;
      error = mid->message;
    } else {
      final_check = app::FinalCheck{"midend", !mid_check.in_collision, mid_check.in_collision ? mid_check.link : -1,
                                    mid->validate_s * 1e3};
    }
    // Back-end (paper §VI): only when the mid-end's trajectory collides.
    if (mid->trajectory && mid->execution == midend::Execution::kNeedsBackend && args.stages == app::Stages::kFull) {
      std::vector<app::BackendWarmStart> warm_starts{{&*mid->trajectory, mid_settings}};
      if (stage.first && stage.first->trajectory)
        warm_starts.push_back({&*stage.first->trajectory, stage.first_settings});
      back = app::run_backend(args, model, grid, result.path, warm_starts, kernels);
      const backend::BackendResult& r = back->result;
      status = backend::to_string(r.status);
      if (r.ok()) {
        final_check = app::FinalCheck{"backend", r.check == backend::SafetyCheck::kCollisionFree,
                                      r.check == backend::SafetyCheck::kInCollision ? r.collision_link : -1, r.check_s * 1e3};
      }
      if (!r.success()) {
        code = kPlanFailed;
        error = r.ok() ? "back-end trajectory in collision (kernel check, link " + std::to_string(r.collision_link) + ")"
                       : "back-end: " + r.message;
      }
      if (!args.quiet || !r.success()) std::cout << app::backend_summary(*back) << std::endl;
    }
  }
  if (args.out_path &&
      !write_file(*args.out_path, app::plan_result_json(info, &result, status, code, error, mid ? &*mid : nullptr,
                                                        back ? &*back : nullptr, final_check ? &*final_check : nullptr))) {
    std::cerr << "porter-plan: cannot write '" << *args.out_path << "'\n";
    return kBadFile;
  }
  return code;
}
