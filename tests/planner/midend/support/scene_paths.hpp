#pragma once
// Real front-end paths for mid-end tests and benchmarks: loads a shipped scene
// (config/scenes/<name>.yaml) with its payload, runs porter::frontend::FrontEnd with the
// chain-decomposed kernel checker exactly as porter-plan does, and returns the path. The
// front-end is deterministic for a given scene, seed and (generous) budget.
//
// Not thread-safe (model cache). Throws porter::LoadError when a config file is bad.

#include <cstdint>
#include <optional>
#include <string>

#include "porter/core/robot_model.hpp"
#include "porter/planner/whole_body_path.hpp"

namespace porter::midend::testing {

/// The source tree (PORTER_SOURCE_DIR from the environment, else the compile-time value).
std::string source_dir();

struct ScenePath {
  std::string scene;
  std::uint64_t seed = 0;
  planner::WholeBodyPath path;
  double frontend_s = 0.0;  ///< front-end wall time (information only)
};

/// The shipped robot (config/robots/scout_mini_piper/robot.yaml) with `payload_file` attached
/// ("" for none). Cached per payload file; the reference stays valid for the process.
const RobotModel& shipped_robot(const std::string& payload_file);

/// Runs the front-end on config/scenes/<scene>.yaml with `seed` (scene generators and planner,
/// as porter-plan --seed) and `budget_s`; nullopt when it finds no path.
std::optional<ScenePath> frontend_path(const std::string& scene, std::uint64_t seed,
                                       double budget_s = 1.0);

/// The first path over seeds first_seed, first_seed + 1, ... (at most max_tries of them);
/// nullopt when none succeeds.
std::optional<ScenePath> first_frontend_path(const std::string& scene, std::uint64_t first_seed,
                                             int max_tries, double budget_s = 1.0);

}  // namespace porter::midend::testing
