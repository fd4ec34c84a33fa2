#include "scene_paths.hpp"

#include <cstdlib>
#include <map>
#include <memory>

#include "porter/core/payload.hpp"
#include "porter/core/payload_loader.hpp"
#include "porter/core/robot_loader.hpp"
#include "porter/core/scene_loader.hpp"
#include "porter/core/scene_voxelizer.hpp"
#include "porter/frontend/frontend.hpp"
#include "porter/planner/collision/kernel_collision_checker.hpp"

namespace porter::midend::testing {

std::string source_dir() {
  const char* env = std::getenv("PORTER_SOURCE_DIR");
  return env ? env : PORTER_SOURCE_DIR;
}

const RobotModel& shipped_robot(const std::string& payload_file) {
  static std::map<std::string, std::unique_ptr<RobotModel>> cache;
  auto it = cache.find(payload_file);
  if (it != cache.end()) return *it->second;
  const RobotModel bare = load_robot_model(source_dir() + "/config/robots/scout_mini_piper/robot.yaml");
  auto model = std::make_unique<RobotModel>(
      payload_file.empty() ? bare : attach_payload(bare, load_payload(payload_file)));
  return *cache.emplace(payload_file, std::move(model)).first->second;
}

std::optional<ScenePath> frontend_path(const std::string& scene_name, std::uint64_t seed,
                                       double budget_s) {
  SceneLoadOptions options;
  options.seed = seed;
  const Scene scene = load_scene(source_dir() + "/config/scenes/" + scene_name + ".yaml", options);
  const RobotModel& model = shipped_robot(scene.payload_file);
  const OccupancyGrid grid = voxelize(scene);
  planner::KernelCollisionChecker checker(model);
  checker.set_map(grid);
  frontend::FrontEnd fe(model, checker);
  fe.set_map(grid);
  const frontend::FrontendResult r = fe.plan(scene.start, scene.goal, budget_s, scene.seed);
  if (r.status != planner::Status::kSuccess) return std::nullopt;
  ScenePath out;
  out.scene = scene_name;
  out.seed = seed;
  out.path = r.path;
  out.frontend_s = r.elapsed_s;
  return out;
}

std::optional<ScenePath> first_frontend_path(const std::string& scene, std::uint64_t first_seed,
                                             int max_tries, double budget_s) {
  for (int k = 0; k < max_tries; ++k) {
    std::optional<ScenePath> p = frontend_path(scene, first_seed + static_cast<std::uint64_t>(k), budget_s);
    if (p) return p;
  }
  return std::nullopt;
}

}  // namespace porter::midend::testing
