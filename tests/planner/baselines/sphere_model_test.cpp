// The sphere baseline's body model and checker: the cover contains the geometry; the checker
// never misses a collision of the exact geometry (conservative) and flags the ground; the factory
// and flag names.

#include <gtest/gtest.h>

#include <random>

#include "backend_fixtures.hpp"
#include "porter/baselines/safety_models.hpp"
#include "porter/baselines/sphere_collision_checker.hpp"
#include "porter/baselines/sphere_cover.hpp"
#include "porter/core/kinematics.hpp"
#include "porter/core/scene_voxelizer.hpp"

namespace porter::baselines {
namespace {

TEST(SphereCover, ContainsTheSurfaceOfTheGeometry) {
  const RobotModel& model = backend::testing::robot("t_bar");
  const RobotSpheres spheres = cover_robot(model);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int l = 0; l < kNumLinks; ++l) {
    const Link& link = model.links[static_cast<std::size_t>(l)];
    const LinkSpheres& s = spheres[static_cast<std::size_t>(l)];
    ASSERT_FALSE(s.centers_L.empty()) << "link " << l;
    EXPECT_NEAR(s.radius_m, 0.06 * std::sqrt(3.0) / 2, 1e-12);
    // Points just outside the geometry (within 3 mm of it): their nearest geometry point is on the
    // surface, which the kept cells hold, so they are within radius + 3 mm of a sphere centre.
    // (Interior cells carry no sphere: an obstacle reaches the inside only through the surface.)
    int inside_points = 0;
    for (int n = 0; n < 200000 && inside_points < 300; ++n) {
      const Eigen::Vector3d p = link.bounds.min() - Eigen::Vector3d::Constant(0.01) +
                                (link.bounds.sizes() + Eigen::Vector3d::Constant(0.02)).cwiseProduct(Eigen::Vector3d(u(rng), u(rng), u(rng)));
      double d = 1e9;
      for (const CollisionShape& shape : link.shapes) d = std::min(d, shape_signed_distance(shape, p));
      if (d < 0.0 || d > 0.003) continue;
      ++inside_points;
      double nearest = 1e9;
      for (const Eigen::Vector3d& c : s.centers_L) nearest = std::min(nearest, (c - p).norm());
      EXPECT_LE(nearest, s.radius_m + 0.003 + 1e-12) << "link " << l;
    }
    EXPECT_GT(inside_points, 10) << "link " << l;
  }
}

TEST(SphereCollisionChecker, ConservativeAgainstTheExactGeometry) {
  const RobotModel& model = backend::testing::robot("t_bar");
  Scene scene;
  scene.bounds_W = Eigen::AlignedBox3d(Eigen::Vector3d(-3, -3, 0), Eigen::Vector3d(3, 3, 2.5));
  scene.resolution_m = 0.05;
  CollisionShape wall;
  wall.geometry = Box{Eigen::Vector3d(0.3, 4.0, 2.0)};
  wall.T_parent_shape.translation() = Eigen::Vector3d(1.0, 0.0, 1.0);
  scene.obstacles.push_back(wall);
  const OccupancyGrid grid = voxelize(scene);
  SphereCheckerSettings settings;
  settings.check_self_collision = false;
  SphereCollisionChecker checker(model, settings);
  checker.set_map(grid);
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  KinematicsWorkspace ws;
  int exact_hits = 0, flagged = 0;
  for (int n = 0; n < 300; ++n) {
    RobotConfiguration c;
    c.base = {0.2 + 0.5 * u(rng), 0.5 * u(rng), 0.4 * u(rng)};
    c.q_rad << 0.3 * u(rng), 0.9 + 0.3 * u(rng), -1.2 + 0.3 * u(rng), 0.3 * u(rng), 0.5 + 0.3 * u(rng), 0.3 * u(rng);
    forward_kinematics(model, c, ws);
    bool exact = false;
    for (int l = 0; l < kNumLinks && !exact; ++l) {
      for (const CollisionShape& shape : model.links[static_cast<std::size_t>(l)].shapes) {
        CollisionShape placed = shape;
        placed.T_parent_shape = ws.T_W_L[static_cast<std::size_t>(l)] * shape.T_parent_shape;
        exact = exact || shape_intersects_aabb(placed, Eigen::AlignedBox3d(Eigen::Vector3d(0.85, -2, 0), Eigen::Vector3d(1.15, 2, 2)));
        if (l >= 1) exact = exact || shape_bounds(placed).min().z() < 0.0;
      }
    }
    const bool hit = checker.check(c).in_collision;
    exact_hits += exact;
    flagged += hit;
    if (exact) {
      EXPECT_TRUE(hit) << "missed a collision at sample " << n;
    }
  }
  EXPECT_GT(exact_hits, 20);
  EXPECT_GT(flagged, exact_hits);  // and it is conservative: it flags more
  // Far from everything: free; below the map's ground: the arm may not go there.
  RobotConfiguration free;
  free.base = {-1.5, 0.0, 0.0};
  free.q_rad << 0.0, 0.6, -0.9, 0.0, 0.5, 0.0;
  EXPECT_FALSE(checker.check(free).in_collision);
  EXPECT_FALSE(checker.check_base(free.base).in_collision);
  RobotConfiguration outside = free;
  outside.base.x_m = 10.0;
  EXPECT_TRUE(checker.check(outside).in_collision);
  EXPECT_EQ(checker.name(), "spheres");
}

TEST(SafetyModels, NamesAndFactory) {
  for (SafetyModel m : {SafetyModel::kKcSvsdf, SafetyModel::kSvsdfPerLink, SafetyModel::kSpheres}) {
    EXPECT_EQ(parse_safety_model(to_string(m)), m);
  }
  for (CollisionModel m : {CollisionModel::kKernels, CollisionModel::kSpheres}) {
    EXPECT_EQ(parse_collision_model(to_string(m)), m);
  }
  EXPECT_FALSE(parse_safety_model("svsdf").has_value());
  EXPECT_FALSE(parse_collision_model("").has_value());
  const RobotModel& model = backend::testing::robot("t_bar");
  const backend::RobotSdf& sdf = backend::testing::robot_sdf("t_bar");
  EXPECT_EQ(make_safety_term(SafetyModel::kKcSvsdf, model, &sdf)->name(), "kc_svsdf");
  EXPECT_EQ(make_safety_term(SafetyModel::kSvsdfPerLink, model, &sdf)->name(), "svsdf_per_link");
  EXPECT_EQ(make_safety_term(SafetyModel::kSpheres, model, nullptr)->name(), "spheres");
  EXPECT_EQ(make_safety_term(SafetyModel::kKcSvsdf, model, nullptr), nullptr);
}

}  // namespace
}  // namespace porter::baselines
