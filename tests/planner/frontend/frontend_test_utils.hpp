#pragma once
// Helpers for the front-end tests: shipped configs, scenes built from YAML text, and a path
// validator that checks every property the front-end promises.

#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include "porter/core/payload.hpp"
#include "porter/core/payload_loader.hpp"
#include "porter/core/robot_loader.hpp"
#include "porter/core/scene_loader.hpp"
#include "porter/core/scene_voxelizer.hpp"
#include "porter/frontend/reeds_shepp.hpp"
#include "porter/planner/collision/collision_checker.hpp"
#include "porter/planner/whole_body_path.hpp"

namespace porter::test {

inline std::string source_dir() {
  const char* env = std::getenv("PORTER_SOURCE_DIR");
  return env ? env : PORTER_SOURCE_DIR;
}
inline std::string robot_yaml() { return source_dir() + "/config/robots/scout_mini_piper/robot.yaml"; }
inline std::string scene_yaml(const std::string& name) { return source_dir() + "/config/scenes/" + name + ".yaml"; }

/// The shipped robot with the scene's payload attached.
inline RobotModel model_for(const Scene& scene) {
  static const RobotModel bare = load_robot_model(robot_yaml());
  return scene.payload_file.empty() ? bare : attach_payload(bare, load_payload(scene.payload_file));
}

/// A scene from YAML text whose relative paths resolve against config/scenes/.
inline Scene scene_from_text(const std::string& yaml) {
  return parse_scene(yaml, source_dir() + "/config/scenes/test_scene.yaml");
}

struct PathCheckOptions {
  double turning_radius_m = 0.4;
  const RobotConfiguration* start = nullptr;  ///< when set, the first node must equal it
  const RobotConfiguration* goal = nullptr;   ///< when set, the last node must equal it
};

/// Every violated promise of a front-end path, as text (empty when the path is fine):
/// segment structure and shared gear nodes, eta alternation, increasing times, turning radius
/// and yaw tied to the driving direction, joint limits, joint speed limits per step, and every
/// node and edge free for each checker.
std::vector<std::string> check_path(const planner::WholeBodyPath& path, const RobotModel& model,
                                    const std::vector<const planner::CollisionChecker*>& checkers,
                                    const PathCheckOptions& options);

/// All nodes in order, without the duplicated gear-switch nodes, with the eta reaching each.
struct FlatNode {
  planner::PathNode node;
  int eta = 1;
};
std::vector<FlatNode> flatten(const planner::WholeBodyPath& path);

/// True when the two configurations are equal within tol (yaw compared on the circle).
bool same_config(const RobotConfiguration& a, const RobotConfiguration& b, double tol = 1e-9);

}  // namespace porter::test
