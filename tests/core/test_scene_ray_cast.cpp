// Ray casting against scenes (scene_ray_cast.hpp).

#include <random>

#include <gtest/gtest.h>

#include "porter/core/scene_loader.hpp"
#include "porter/core/scene_ray_cast.hpp"

namespace porter {
namespace {

Scene box_scene() {
  Scene s;
  s.bounds_W = Eigen::AlignedBox3d(Eigen::Vector3d(-10, -10, 0), Eigen::Vector3d(10, 10, 3));
  auto add_box = [&](const Eigen::Vector3d& c, const Eigen::Vector3d& size, double yaw, const char* name) {
    CollisionShape b;
    b.geometry = Box{size};
    b.T_parent_shape.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    b.T_parent_shape.translation() = c;
    b.name = name;
    s.obstacles.push_back(b);
  };
  add_box({5, 0, 1}, {1, 4, 2}, 0.0, "near");
  add_box({8, 0, 1}, {1, 10, 2}, 0.0, "far");
  add_box({0, 5, 1}, {2, 2, 2}, M_PI / 4, "diamond");
  return s;
}

TEST(SceneRayCast, FirstHitInABoxScene) {
  const SceneRayCaster caster(box_scene());
  const Eigen::Vector3d o(0, 0, 1);
  SceneRayHit h = caster.cast(o, Eigen::Vector3d::UnitX(), 20);
  EXPECT_EQ(h.obstacle_index, 0);
  EXPECT_NEAR(h.distance_m, 4.5, 1e-12);
  // Passing beside the near box (|y| > 2) hits the far one.
  h = caster.cast({0, 3, 1}, Eigen::Vector3d::UnitX(), 20);
  EXPECT_EQ(h.obstacle_index, 1);
  EXPECT_NEAR(h.distance_m, 7.5, 1e-12);
  // Over everything, and out of range.
  EXPECT_FALSE(caster.cast({0, 0, 2.5}, Eigen::Vector3d::UnitX(), 20).hit());
  h = caster.cast(o, Eigen::Vector3d::UnitX(), 4.0);
  EXPECT_FALSE(h.hit());
  EXPECT_LT(h.distance_m, 0.0);
  // The diamond's corner points at the origin: hit at 5 - sqrt(2).
  h = caster.cast(o, Eigen::Vector3d::UnitY(), 20);
  EXPECT_EQ(h.obstacle_index, 2);
  EXPECT_NEAR(h.distance_m, 5 - std::sqrt(2.0), 1e-12);
  // Starting inside an obstacle.
  h = caster.cast({5, 0, 1}, Eigen::Vector3d::UnitZ(), 20);
  EXPECT_EQ(h.obstacle_index, 0);
  EXPECT_EQ(h.distance_m, 0.0);
  // The ground is not an obstacle.
  EXPECT_FALSE(caster.cast({0, 0, 1}, -Eigen::Vector3d::UnitZ(), 20).hit());
}

TEST(SceneRayCast, ForestMatchesBruteForce) {
  const Scene s = load_scene(std::string(PORTER_SOURCE_DIR) + "/config/scenes/forest.yaml");
  const SceneRayCaster caster(s);
  std::mt19937_64 rng(41);
  std::uniform_real_distribution<double> ux(0.0, 20.0), uy(-4.0, 4.0), uz(0.1, 2.0), ud(-1.0, 1.0);
  int hits = 0;
  for (int k = 0; k < 3000; ++k) {
    const Eigen::Vector3d o(ux(rng), uy(rng), uz(rng));
    const Eigen::Vector3d d = Eigen::Vector3d(ud(rng), ud(rng), 0.3 * ud(rng)).normalized();
    const SceneRayHit h = caster.cast(o, d, 15.0);
    double best = -1.0;
    int best_i = -1;
    for (std::size_t i = 0; i < s.obstacles.size(); ++i) {
      const double t = shape_ray_cast(s.obstacles[i], o, d, 15.0);
      if (t >= 0.0 && (best < 0.0 || t < best)) {
        best = t;
        best_i = static_cast<int>(i);
      }
    }
    ASSERT_EQ(h.hit(), best_i >= 0) << k;
    if (best_i >= 0) {
      EXPECT_NEAR(h.distance_m, best, 1e-12) << k;
      ++hits;
    }
  }
  EXPECT_GT(hits, 1000);
}

}  // namespace
}  // namespace porter
