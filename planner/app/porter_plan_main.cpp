// porter-plan: loads a scene, plans, prints one summary line per stage and writes the JSON result.
// Usage and exit codes: plan_args.cpp / README.md.

#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include "checker_factory.hpp"
#include "plan_args.hpp"
#include "plan_result_json.hpp"
#include "porter/core/load_error.hpp"
#include "porter/core/payload.hpp"
#include "porter/core/payload_loader.hpp"
#include "porter/core/robot_loader.hpp"
#include "porter/core/scene_loader.hpp"
#include "porter/core/scene_voxelizer.hpp"
#include "porter/frontend/frontend.hpp"
#include "porter/midend/midend.hpp"

namespace {

enum ExitCode { kOk = 0, kPlanFailed = 1, kBadArgs = 2, kBadFile = 3, kInvalidEndpoint = 4, kUnavailable = 5 };

bool write_file(const std::string& path, const std::string& text) {
  std::ofstream f(path);
  f << text;
  return static_cast<bool>(f.flush());
}

std::string summary_line(const porter::frontend::FrontendResult& r) {
  using porter::frontend::to_string;
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "front-end: %s %.1f ms, iterations %lld (hybrid_astar %lld, layered_arm %lld, whole_body_rrt %lld)",
                to_string(r.status), r.elapsed_s * 1e3,
                static_cast<long long>(r.hybrid_astar.iterations + r.layered_arm.iterations + r.whole_body_rrt.iterations),
                static_cast<long long>(r.hybrid_astar.iterations), static_cast<long long>(r.layered_arm.iterations),
                static_cast<long long>(r.whole_body_rrt.iterations));
  std::string line = buf;
  if (r.status == porter::frontend::PlannerStatus::kSuccess) {
    std::snprintf(buf, sizeof buf, ", nodes %zu, segments %zu, length %.2f m%s", r.path.node_count(),
                  r.path.segments.size(), porter::app::path_length_m(r.path), r.used_fallback ? ", fallback used" : "");
    line += buf;
  } else {
    line += " -- " + r.message;
  }
  return line;
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
  info.frontend_budget_ms = args.frontend_budget_ms;
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

  const OccupancyGrid grid = voxelize(scene);
  std::unique_ptr<planner::CollisionChecker> checker = app::make_collision_checker(model);
  info.checker = checker->name();
  checker->set_map(grid);
  frontend::FrontEnd fe(model, *checker);
  fe.set_map(grid);
  const frontend::FrontendResult result = fe.plan(scene.start, scene.goal, args.frontend_budget_ms * 1e-3, scene.seed);

  int code = kOk;
  if (result.status == frontend::PlannerStatus::kInvalidStart || result.status == frontend::PlannerStatus::kInvalidGoal)
    code = kInvalidEndpoint;
  else if (result.status != frontend::PlannerStatus::kSuccess)
    code = kPlanFailed;
  if (code == kInvalidEndpoint) std::cerr << "porter-plan: " << result.message << "\n";
  if (!args.quiet || code != kOk) std::cout << summary_line(result) << std::endl;
  std::string status = frontend::to_string(result.status);
  std::string error;

  // Mid-end (paper §V): MINCO over the front-end path; a trajectory the kernel check finds
  // collision-free is executed directly and the back-end is skipped.
  std::optional<midend::MidendResult> mid;
  if (code == kOk && args.stages != app::Stages::kFront) {
    const midend::MidEnd midend_solver(model);
    mid = midend_solver.solve(result.path, /*time_budget_s=*/0.0,
                              [&](const Trajectory& t) { return !checker->check_trajectory(t).in_collision; });
    status = midend::to_string(mid->status);
    if (!args.quiet || !mid->trajectory) {
      std::printf("mid-end: %s %.1f ms (optimize %.1f ms, check %.1f ms), iterations %d, evaluations %d, pieces %d",
                  midend::to_string(mid->status), mid->elapsed_s * 1e3, mid->optimize_s * 1e3, mid->validate_s * 1e3,
                  mid->iterations, mid->evaluations, mid->num_pieces);
      if (mid->trajectory) std::printf(", duration %.2f s, %s", mid->trajectory->total_duration_s(), midend::to_string(mid->execution));
      std::printf("\n");
    }
    if (!mid->trajectory) {
      code = kPlanFailed;
      error = mid->message;
    } else if (mid->execution == midend::Execution::kNeedsBackend && args.stages == app::Stages::kFull) {
      // The back-end (KC-SVSDF, paper §VI) has not landed: say so rather than return a colliding plan.
      code = kUnavailable;
      status = "needs_backend";
      error = "the mid-end trajectory is in collision and the back-end is not available yet";
      std::cerr << "porter-plan: " << error << "\n";
    }
  }
  if (args.out_path &&
      !write_file(*args.out_path, app::plan_result_json(info, &result, status, code, error, mid ? &*mid : nullptr))) {
    std::cerr << "porter-plan: cannot write '" << *args.out_path << "'\n";
    return kBadFile;
  }
  return code;
}
