// porter-plan: loads a scene and the planner settings, plans once through porter::pipeline::Planner,
// prints one summary line per stage and writes the JSON result. Usage and exit codes: README.md.

#include <fstream>
#include <iostream>
#include <memory>
#include <string>

#include "plan_args.hpp"
#include "plan_result_json.hpp"
#include "plan_summary.hpp"
#include "porter/core/load_error.hpp"
#include "porter/core/payload.hpp"
#include "porter/core/payload_loader.hpp"
#include "porter/core/robot_loader.hpp"
#include "porter/core/scene_loader.hpp"
#include "porter/core/scene_voxelizer.hpp"
#include "porter/pipeline/config_dir.hpp"
#include "porter/pipeline/exact_acceptance.hpp"
#include "porter/pipeline/planner.hpp"
#include "porter/pipeline/settings_yaml.hpp"

namespace {

using namespace porter;

enum ExitCode { kOk = 0, kPlanFailed = 1, kBadArgs = 2, kBadFile = 3, kInvalidEndpoint = 4 };

bool write_file(const std::string& path, const std::string& text) {
  std::ofstream f(path);
  f << text;
  return static_cast<bool>(f.flush());
}

/// The flags that override the settings files.
void apply_overrides(const app::PlanArgs& a, pipeline::PlannerSettings& s) {
  pipeline::PipelineSettings& p = s.pipeline;
  if (a.frontend_budget_ms) p.frontend_budget_s = *a.frontend_budget_ms * 1e-3;
  if (a.midend_budget_ms) p.midend_budget_s = *a.midend_budget_ms * 1e-3;
  if (a.backend_budget_ms) p.backend_budget_s = *a.backend_budget_ms * 1e-3;
  if (a.backend_max_iterations) s.backend.max_iterations = *a.backend_max_iterations;
  if (a.collision)
    p.collision = *a.collision == app::CollisionArg::kSpheres ? baselines::CollisionModel::kSpheres
                                                              : baselines::CollisionModel::kKernels;
  if (a.safety)
    p.safety = *a.safety == app::SafetyArg::kSvsdfPerLink ? baselines::SafetyModel::kSvsdfPerLink
                                                          : baselines::SafetyModel::kKcSvsdf;
  if (a.self_collision_term) p.self_collision_term = *a.self_collision_term;
  if (a.choose_warm_start_by_safety) p.choose_warm_start_by_safety = *a.choose_warm_start_by_safety;
}

int exit_code(const pipeline::PlanResult& r, pipeline::Stages stages) {
  if (r.status == planner::Status::kInvalidStart || r.status == planner::Status::kInvalidGoal) return kInvalidEndpoint;
  if (stages == pipeline::Stages::kMid) return r.midend && r.midend->result.trajectory ? kOk : kPlanFailed;
  return r.success() ? kOk : kPlanFailed;
}

/// The last stage's status token (the JSON's "status").
std::string last_status(const pipeline::PlanResult& r) {
  if (r.backend) return planner::to_string(r.backend->result.status);
  if (r.midend) return planner::to_string(r.midend->result.status);
  if (r.frontend) return planner::to_string(r.frontend->status);
  return planner::to_string(r.status);
}

}  // namespace

int main(int argc, char** argv) {
  app::PlanArgs args;
  try {
    args = app::parse_plan_args(argc, argv);
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
  info.stages = app::to_string(args.stages);
  auto fail = [&](int code, const std::string& msg) {
    std::cerr << "porter-plan: " << msg << "\n";
    if (args.out_path && !write_file(*args.out_path, app::plan_result_json(info, nullptr, "bad_input", code, msg))) {
      std::cerr << "porter-plan: cannot write '" << *args.out_path << "'\n";
      return static_cast<int>(kBadFile);
    }
    return code;
  };

  // Files: the robot and the planner settings default to the config directory's.
  if (!args.robot_path || !args.planner_config_dir) {
    const std::string config = pipeline::find_config_dir();
    if (config.empty())
      return fail(kBadFile, "cannot find the config directory (./config, or config/ above the executable): give "
                            "--robot and --planner-config");
    if (!args.robot_path) args.robot_path = config + "/robots/scout_mini_piper/robot.yaml";
    if (!args.planner_config_dir) args.planner_config_dir = config + "/planner";
  }
  info.robot_file = *args.robot_path;
  info.planner_config = *args.planner_config_dir;

  Scene scene;
  RobotModel bare;
  Payload payload;
  RobotModel model;
  pipeline::PlannerSettings settings;
  try {
    SceneLoadOptions options;
    if (args.seed_given) options.seed = args.seed;
    options.parameter_overrides = args.overrides;
    scene = load_scene(args.scene_path, options);
    info.scene_name = scene.name;
    info.seed = scene.seed;
    info.parameters = scene.parameters;
    info.payload_file = args.payload_path ? *args.payload_path : scene.payload_file;
    bare = load_robot_model(*args.robot_path);
    if (!info.payload_file.empty()) payload = load_payload(info.payload_file);
    model = info.payload_file.empty() ? bare : attach_payload(bare, payload);
    settings = pipeline::load_planner_settings(*args.planner_config_dir);
  } catch (const std::exception& e) {  // loaders throw LoadError; anything else is still bad input
    return fail(kBadFile, e.what());
  }
  apply_overrides(args, settings);
  settings.kernels.kernels.resolution_m = scene.resolution_m;  // the kernels follow the scene's voxels
  const pipeline::PipelineSettings& p = settings.pipeline;
  info.collision = baselines::to_string(p.collision);
  info.safety = p.collision == baselines::CollisionModel::kSpheres ? "spheres" : baselines::to_string(p.safety);
  info.frontend_budget_ms = p.frontend_budget_s * 1e3;
  info.midend_budget_ms = p.midend_budget_s * 1e3;
  info.backend_budget_ms = p.backend_budget_s * 1e3;

  std::unique_ptr<pipeline::Planner> planner;
  try {
    planner = std::make_unique<pipeline::Planner>(model, settings);
  } catch (const std::exception& e) {  // a resolution or setting the kernels cannot use
    // The robot side (kernels, self-collision proofs) is built here, at the scene's resolution.
    return fail(kBadFile, "robot " + *args.robot_path + (info.payload_file.empty() ? "" : " with payload " + info.payload_file) +
                              " at the scene's resolution (" + args.scene_path + "): " + e.what());
  }
  info.checker = planner->frontend_checker().name();
  const OccupancyGrid grid_W = voxelize(scene);
  const pipeline::MapUpdate map = planner->set_map(grid_W);
  if (!map.ok) return fail(kBadFile, std::string("scene ") + args.scene_path + ": " + map.message);
  if (args.acceptance == app::AcceptanceArg::kExact) {
    pipeline::ExactAcceptanceSettings exact;
    exact.margin_m = args.clearance_margin_m;
    planner->set_acceptance(std::make_shared<pipeline::ExactClearanceAcceptance>(
        bare, payload, scene, exact, planner->kernel_checker().robot(), grid_W));
  }
  info.acceptance = planner->acceptance().name();
  info.clearance_margin_m = planner->acceptance().clearance_margin_m();

  pipeline::PlanRequest request;
  request.start = pipeline::StartState::at_rest(scene.start);
  request.goal = pipeline::GoalSpec::exact(scene.goal);
  request.seed = scene.seed;
  request.stages = args.stages == app::Stages::kFront ? pipeline::Stages::kFront
                   : args.stages == app::Stages::kMid ? pipeline::Stages::kMid
                                                      : pipeline::Stages::kFull;
  const pipeline::PlanResult r = planner->plan(request);

  const int code = exit_code(r, request.stages);
  if (code == kInvalidEndpoint) std::cerr << "porter-plan: " << r.message << "\n";
  const bool print = !args.quiet || code != kOk;
  if (r.frontend && print) std::cout << app::frontend_summary(*r.frontend) << "\n";
  if (r.midend) {
    if (!r.midend->retry.empty() && print) std::cout << "mid-end: " << r.midend->retry << ", solved again\n";
    if (print || !r.midend->result.trajectory) std::cout << app::midend_summary(*r.midend) << "\n";
  }
  if (r.backend && (print || !r.backend->result.success())) std::cout << app::backend_summary(*r.backend) << "\n";
  std::cout.flush();
  const std::string error = code != kOk && (r.midend || r.backend) ? r.message : "";
  if (args.out_path && !write_file(*args.out_path, app::plan_result_json(info, &r, last_status(r), code, error))) {
    std::cerr << "porter-plan: cannot write '" << *args.out_path << "'\n";
    return kBadFile;
  }
  return code;
}
