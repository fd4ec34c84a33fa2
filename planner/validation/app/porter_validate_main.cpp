// porter-validate: checks a porter-plan result at mesh level with FCL (see
// planner/validation/README.md). Prints one line; --json writes the full report.
#include <filesystem>
#include <fstream>
#include <iostream>

#include "porter/core/load_error.hpp"
#include "porter/core/payload_loader.hpp"
#include "porter/core/robot_loader.hpp"
#include "porter/core/scene_loader.hpp"
#include "porter/validation/plan_file.hpp"
#include "porter/validation/report_json.hpp"
#include "porter/validation/swept_trace.hpp"
#include "validate_args.hpp"

namespace {

bool write_text(const std::string& path, const std::string& text) {
  if (path == "-") {
    std::cout << text << "\n";
    return true;
  }
  std::ofstream out(path);
  out << text << "\n";
  return static_cast<bool>(out);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace porter;
  using namespace porter::validation;
  std::string error;
  const auto args = parse_validate_args(argc, argv, &error);
  if (!args) {
    std::cerr << "porter-validate: " << error << "\n" << kValidateUsage;
    return 2;
  }
  PlanFile plan;
  Scene scene;
  RobotModel model;
  Payload payload;
  try {
    plan = load_plan_file(args->result_file);
    SceneLoadOptions options;
    options.seed = args->seed;
    options.parameter_overrides = args->overrides;
    scene = load_scene(args->scene_file, options);
    std::string robot = args->robot_file;
    if (robot.empty())
      robot = (std::filesystem::path(args->scene_file).parent_path() / ".." / "robots" / "scout_mini_piper" /
               "robot.yaml").lexically_normal().string();
    model = load_robot_model(robot);
    payload = load_payload(args->payload_file.empty() ? scene.payload_file : args->payload_file);
  } catch (const LoadError& e) {
    std::cerr << "porter-validate: " << e.what() << "\n";
    return 3;
  }
  if (plan.scene_seed && static_cast<std::uint64_t>(*plan.scene_seed) != scene.seed)
    std::cerr << "porter-validate: warning: the plan used seed " << *plan.scene_seed << ", validating against seed "
              << scene.seed << "\n";

  if (!plan.has_trajectory) {
    std::cout << report_line(plan, nullptr) << "\n";
    if (!args->json_out.empty() && !write_text(args->json_out, report_to_json(plan, nullptr))) {
      std::cerr << "porter-validate: cannot write " << args->json_out << "\n";
      return 3;
    }
    return 4;
  }
  const FlatTrajectory trajectory(plan.pieces, plan.start_yaw_rad);
  const ValidationReport report = validate_trajectory(model, payload, scene, trajectory, args->settings);
  if (!args->quiet || !report.valid) std::cout << report_line(plan, &report) << "\n";
  if (!args->json_out.empty() && !write_text(args->json_out, report_to_json(plan, &report))) {
    std::cerr << "porter-validate: cannot write " << args->json_out << "\n";
    return 3;
  }
  if (!args->trace_out.empty() &&
      !write_text(args->trace_out, swept_trace_json(model, payload, scene, trajectory))) {
    std::cerr << "porter-validate: cannot write " << args->trace_out << "\n";
    return 3;
  }
  return report.valid ? 0 : 1;
}
