#pragma once
// Shared helpers of the collision tests and the collision benchmark: shipped configs, seeded
// configuration generators.

#include <cstdlib>
#include <random>
#include <string>

#include "porter/core/payload_loader.hpp"
#include "porter/core/robot_loader.hpp"
#include "porter/core/robot_model.hpp"
#include "porter/core/scene.hpp"
#include "porter/core/scene_loader.hpp"

namespace porter::test {

inline std::string source_dir() {
  const char* env = std::getenv("PORTER_SOURCE_DIR");
  return env ? env : PORTER_SOURCE_DIR;
}

/// The shipped robot, as its config describes it.
inline RobotModel shipped_robot() {
  return load_robot_model(source_dir() + "/config/robots/scout_mini_piper/robot.yaml");
}

inline RobotModel shipped_robot_with(const std::string& payload) {
  return attach_payload(shipped_robot(), load_payload(source_dir() + "/config/payloads/" + payload + ".yaml"));
}

inline Scene shipped_scene(const std::string& name) {
  return load_scene(source_dir() + "/config/scenes/" + name + ".yaml");
}

/// Deterministic uniform draws (the standard distributions differ between libraries).
inline double uniform(std::mt19937_64& rng, double lo, double hi) {
  return lo + (hi - lo) * static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

/// n points uniform in the box [-1, 1] x [-0.2, 0.3] x [0, 2] (float), for tree tests.
inline std::vector<Eigen::Vector3f> random_cloud(int n, std::mt19937_64& rng) {
  std::vector<Eigen::Vector3f> p;
  for (int i = 0; i < n; ++i)
    p.emplace_back(static_cast<float>(uniform(rng, -1, 1)), static_cast<float>(uniform(rng, -0.2, 0.3)),
                   static_cast<float>(uniform(rng, 0, 2)));
  return p;
}

inline JointVector random_joints(const RobotModel& model, std::mt19937_64& rng) {
  JointVector q;
  for (int j = 0; j < kNumArmJoints; ++j)
    q[j] = uniform(rng, model.joints[static_cast<std::size_t>(j)].lower_rad,
                   model.joints[static_cast<std::size_t>(j)].upper_rad);
  return q;
}

/// Base uniformly inside the scene's x-y bounds shrunk by `inset_m`, any yaw, joints in limits.
inline RobotConfiguration random_configuration(const RobotModel& model, const Scene& scene, std::mt19937_64& rng,
                                               double inset_m = 0.0) {
  RobotConfiguration c;
  c.base.x_m = uniform(rng, scene.bounds_W.min().x() + inset_m, scene.bounds_W.max().x() - inset_m);
  c.base.y_m = uniform(rng, scene.bounds_W.min().y() + inset_m, scene.bounds_W.max().y() - inset_m);
  c.base.yaw_rad = uniform(rng, -3.14159265358979, 3.14159265358979);
  c.q_rad = random_joints(model, rng);
  return c;
}

}  // namespace porter::test
