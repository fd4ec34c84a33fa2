#pragma once
// porter-planner's config file (config/planner/porter_planner.yaml) turned into parameters: the
// robot, the planner settings directory, the payloads it may carry, the map and state limits,
// the re-planning and braking parameters. Strict: every key is required; unknown keys and
// out-of-range values are LoadErrors naming the file and the key.
//
// Thread-safety: reentrant. Failure: throws porter::LoadError.

#include <map>
#include <string>

#include "porter/pipeline/planner_settings.hpp"
#include "porter/planner_daemon/goal_loop.hpp"

namespace porter::planner_app {

struct MapParams {
  double resolution_m = 0.05;  ///< voxel size maps must have (the kernels are built for it)
  double margin_m = 2.0;       ///< the grid covers the robot and the goal with this margin, m
  double block_m = 4.0;        ///< grid bounds are rounded outwards to multiples of this, m
  double min_height_m = 2.0;   ///< the grid reaches at least this high above z = 0, m
  double max_voxels = 5e7;     ///< a map needing a larger grid is refused
  std::size_t max_bytes = 64u << 20;  ///< largest octomap_t data accepted, bytes
  /// Unknown voxels directly below an occupied one, down to the first free voxel (or the
  /// ground), count as occupied (fill_unknown_below_occupied, planner_messages.hpp).
  bool fill_unknown_below = true;
  /// ...except in columns this close to the robot, m (its own body hides them).
  double fill_clear_radius_m = 1.2;
};

struct PlannerConfig {
  std::string file;
  std::string robot_file;
  std::string settings_dir;               ///< config/planner (pipeline.yaml, frontend.yaml, ...)
  std::string frame_id = "world";
  std::string payload_id;                 ///< carried at start ("none" = empty gripper)
  std::map<std::string, std::string> payloads;  ///< payload_id -> payload YAML
  pipeline::PlannerSettings settings;     ///< loaded from settings_dir, resolution from map
  MapParams map;
  planner_daemon::GoalLoopParams loop;
  double tick_hz = 10.0;                  ///< the worker's periodic check, Hz
};

PlannerConfig load_planner_config(const std::string& path);

/// The pipeline's longest plan, s: front-end + two mid-end solves + back-end budgets.
double worst_case_plan_s(const pipeline::PlannerSettings& settings);

}  // namespace porter::planner_app
