#pragma once
// Shared by the pipeline tests: the shipped scenes, robot and planner settings from the source
// tree, a Planner on them, and requests from a scene's start and goal.

#include <cstdint>
#include <memory>
#include <string>

#include "porter/core/occupancy_grid.hpp"
#include "porter/core/payload.hpp"
#include "porter/core/payload_loader.hpp"
#include "porter/core/robot_loader.hpp"
#include "porter/core/scene_loader.hpp"
#include "porter/core/scene_voxelizer.hpp"
#include "porter/pipeline/planner.hpp"
#include "porter/pipeline/settings_yaml.hpp"

namespace porter::pipeline::testing {

inline std::string source_dir() { return PORTER_SOURCE_DIR; }

inline Scene scene(const std::string& name, double h_b = -1.0, std::uint64_t seed = 0) {
  SceneLoadOptions options;
  if (h_b > 0.0) options.parameter_overrides["h_b"] = h_b;
  if (seed > 0) options.seed = seed;
  return load_scene(source_dir() + "/config/scenes/" + name + ".yaml", options);
}

inline RobotModel robot_for(const Scene& s) {
  return attach_payload(load_robot_model(source_dir() + "/config/robots/scout_mini_piper/robot.yaml"),
                        load_payload(s.payload_file));
}

/// The shipped settings (config/planner/) at the scene's resolution.
inline PlannerSettings shipped_settings(const Scene& s) {
  PlannerSettings settings = load_planner_settings(source_dir() + "/config/planner");
  settings.kernels.kernels.resolution_m = s.resolution_m;
  return settings;
}

/// Budgets large enough that every stage stops on its iteration counts or convergence, never on
/// time: the same result on any machine (back-end capped at its shipped 200 iterations).
inline void generous_budgets(PlannerSettings& s) {
  s.pipeline.frontend_budget_s = 20.0;
  s.pipeline.midend_budget_s = 20.0;
  s.pipeline.backend_budget_s = 120.0;
}

inline PlanRequest request(const Scene& s, Stages stages = Stages::kFull) {
  PlanRequest r;
  r.start = StartState::at_rest(s.start);
  r.goal = GoalSpec::exact(s.goal);
  r.seed = s.seed;
  r.stages = stages;
  return r;
}

}  // namespace porter::pipeline::testing
