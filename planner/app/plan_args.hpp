#pragma once
// Command-line arguments of porter-plan (see README.md beside this file). Parsing never exits or
// prints; a bad argument throws ArgsError with a message for the user.

#include <cstdint>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>

namespace porter::app {

struct ArgsError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

enum class Stages { kFront, kMid, kFull };
const char* to_string(Stages s);

/// The back-end safety term (--safety): ours or the paper's ablation baseline.
enum class SafetyArg { kKcSvsdf, kSvsdfPerLink };
const char* to_string(SafetyArg s);
/// The collision model (--collision): the front-end checker and, for spheres, the back-end term.
enum class CollisionArg { kKernels, kSpheres };
const char* to_string(CollisionArg c);

/// The final acceptance test (--acceptance): exact geometry with a clearance margin, or the kernel
/// check.
enum class AcceptanceArg { kExact, kKernels };
const char* to_string(AcceptanceArg a);

/// Each optional field overrides the planner settings (config/planner/*.yaml) when given.
struct PlanArgs {
  std::string scene_path;
  std::uint64_t seed = 0;
  bool seed_given = false;                  ///< false: the scene file's seed is used
  std::map<std::string, double> overrides;  ///< --set NAME=VALUE
  std::optional<std::string> payload_path;  ///< replaces the scene's payload
  std::optional<std::string> robot_path;    ///< robot.yaml (default: found with the config directory)
  /// Directory of the planner settings files (default: <config>/planner).
  std::optional<std::string> planner_config_dir;
  Stages stages = Stages::kFront;
  std::optional<double> frontend_budget_ms;
  std::optional<double> midend_budget_ms;
  std::optional<double> backend_budget_ms;
  std::optional<int> backend_max_iterations;  ///< L-BFGS cap (with a large budget: reproducible runs)
  std::optional<SafetyArg> safety;
  std::optional<CollisionArg> collision;
  /// The back-end's self-collision penalty (backend/self_collision_term.hpp), --self-collision-term.
  std::optional<bool> self_collision_term;
  /// --warm-start lowest-js|retry: the back-end's warm start when both mid-end solves were rejected
  /// (PipelineSettings::choose_warm_start_by_safety).
  std::optional<bool> choose_warm_start_by_safety;
  /// The final acceptance test: exact (FCL against the scene's obstacles, clearance >= the margin)
  /// or kernels (the kernel trajectory check on the voxel map).
  AcceptanceArg acceptance = AcceptanceArg::kKernels;
  double clearance_margin_m = 0.02;  ///< --clearance-margin-m, with --acceptance exact
  std::optional<std::string> out_path;
  bool quiet = false;
  bool help = false;
};

/// Parses argv[1..argc-1].
PlanArgs parse_plan_args(int argc, const char* const* argv);

/// The usage text.
std::string plan_usage();

}  // namespace porter::app
