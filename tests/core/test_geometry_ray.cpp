// Ray casts and triangulations of the exact geometry (geometry.hpp).

#include <cmath>
#include <map>
#include <random>
#include <utility>

#include <gtest/gtest.h>

#include "porter/core/geometry.hpp"
#include "test_geometry_helpers.hpp"

namespace porter {
namespace {

using test::random_point;
using test::random_pose;

CollisionShape at(ShapeGeometry g, const Eigen::Vector3d& t) {
  CollisionShape s;
  s.geometry = std::move(g);
  s.T_parent_shape.translation() = t;
  return s;
}

TEST(GeometryRay, AnalyticHits) {
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX();
  const CollisionShape box = at(Box{Eigen::Vector3d(2, 2, 2)}, {5, 0, 0});
  EXPECT_NEAR(shape_ray_cast(box, Eigen::Vector3d::Zero(), x, 10), 4.0, 1e-12);
  EXPECT_LT(shape_ray_cast(box, Eigen::Vector3d::Zero(), x, 3.9), 0.0);        // beyond range
  EXPECT_LT(shape_ray_cast(box, Eigen::Vector3d::Zero(), -x, 100), 0.0);       // behind
  EXPECT_LT(shape_ray_cast(box, {0, 1.01, 0}, x, 100), 0.0);                   // beside
  EXPECT_EQ(shape_ray_cast(box, {5, 0.5, 0}, x, 100), 0.0);                    // from inside
  const CollisionShape sphere = at(Sphere{1.0}, {0, 0, 3});
  EXPECT_NEAR(shape_ray_cast(sphere, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 10), 2.0, 1e-12);
  // Grazing offset 0.6: chord entry at 3 - sqrt(1 - 0.36) = 2.2.
  EXPECT_NEAR(shape_ray_cast(sphere, {0.6, 0, 0}, Eigen::Vector3d::UnitZ(), 10), 2.2, 1e-12);
  const CollisionShape cyl = at(Cylinder{0.5, 2.0}, {3, 0, 0});
  EXPECT_NEAR(shape_ray_cast(cyl, Eigen::Vector3d::Zero(), x, 10), 2.5, 1e-12);              // side
  EXPECT_NEAR(shape_ray_cast(cyl, {3.2, 0, -4}, Eigen::Vector3d::UnitZ(), 10), 3.0, 1e-12);  // cap
  EXPECT_LT(shape_ray_cast(cyl, {0, 0, 1.01}, x, 10), 0.0);                                  // above
  // Slanted rays near the top rim: one enters through the cap, one misses the cap and enters
  // through the side.
  EXPECT_NEAR(shape_ray_cast(cyl, {3, 0, 2}, {0.28, 0, -0.96}, 10), 1.0 / 0.96, 1e-12);
  EXPECT_NEAR(shape_ray_cast(cyl, {2, 0, 1.5}, {0.6, 0, -0.8}, 10), 0.5 / 0.6, 1e-12);
  EXPECT_LT(shape_ray_cast(cyl, {3, 0, 2}, {0.6, 0, -0.8}, 10), 0.0);  // passes over the rim
}

TEST(GeometryRay, RandomRaysConsistentWithSignedDistance) {
  // A reported hit lies on the surface with no inside point before it; a miss passes no inside
  // sample. Checked for every shape type, including the non-convex L.
  std::mt19937_64 rng(21);
  for (int type = 0; type < 5; ++type) {
    int hits = 0, misses = 0;
    for (int trial = 0; trial < 400; ++trial) {
      const CollisionShape s = test::random_shape(rng, type);
      const Eigen::Vector3d o = s.T_parent_shape * random_point(rng, 4.0);
      if (shape_contains(s, o)) continue;
      const Eigen::Vector3d target = s.T_parent_shape * random_point(rng, 1.0);
      const Eigen::Vector3d d = (target - o).normalized();
      const double range = 10.0;
      const double t = shape_ray_cast(s, o, d, range);
      const double t_end = t >= 0.0 ? t : range;
      for (int k = 0; k < 400; ++k) {
        const double tk = t_end * k / 400.0;
        EXPECT_GT(shape_signed_distance(s, o + tk * d), -1e-9) << type << " trial " << trial;
      }
      if (t >= 0.0) {
        EXPECT_NEAR(shape_signed_distance(s, o + t * d), 0.0, 1e-9) << type << " trial " << trial;
        ++hits;
      } else {
        ++misses;
      }
    }
    EXPECT_GT(hits, 50) << type;
    EXPECT_GT(misses, 20) << type;
  }
}

TEST(GeometryRay, MeshOfBoxMatchesBox) {
  std::mt19937_64 rng(22);
  for (int trial = 0; trial < 500; ++trial) {
    CollisionShape box;
    box.geometry = Box{Eigen::Vector3d(0.5, 1.0, 0.3)};
    box.T_parent_shape = random_pose(rng);
    const CollisionShape mesh{MeshShape{std::make_shared<TriangleMesh>(shape_to_mesh(box))},
                              Eigen::Isometry3d::Identity(), "m"};
    const Eigen::Vector3d o = random_point(rng, 3.0);
    const Eigen::Vector3d d = (box.T_parent_shape * random_point(rng, 0.4) - o).normalized();
    const double a = shape_ray_cast(box, o, d, 10), b = shape_ray_cast(mesh, o, d, 10);
    EXPECT_NEAR(a, b, 1e-9) << trial;
  }
}

/// Every directed edge used exactly once and its reverse exactly once: closed and consistently
/// oriented.
bool closed_and_oriented(const TriangleMesh& m) {
  std::map<std::pair<int, int>, int> directed;
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
  for (const auto& [e, count] : directed)
    if (count != 1 || directed.count({e.second, e.first}) != 1 || directed.at({e.second, e.first}) != 1)
      return false;
  return true;
}

double signed_volume(const TriangleMesh& m) {
  double v = 0.0;
  for (const auto& t : m.triangles)
    v += m.vertices_m[t[0]].dot(m.vertices_m[t[1]].cross(m.vertices_m[t[2]])) / 6.0;
  return v;
}

TEST(GeometryToMesh, ClosedOutwardAndRightVolume) {
  std::mt19937_64 rng(23);
  const Eigen::Isometry3d T = random_pose(rng);
  CollisionShape s;
  s.T_parent_shape = T;
  s.geometry = Box{Eigen::Vector3d(0.4, 0.7, 1.1)};
  TriangleMesh m = shape_to_mesh(s);
  EXPECT_TRUE(m.closed);
  EXPECT_TRUE(closed_and_oriented(m));
  EXPECT_EQ(m.triangles.size(), 12u);
  EXPECT_NEAR(signed_volume(m), 0.4 * 0.7 * 1.1, 1e-12);
  for (const int n : {3, 7, 32}) {
    s.geometry = Cylinder{0.3, 0.9};
    m = shape_to_mesh(s, n);
    EXPECT_TRUE(m.closed && closed_and_oriented(m)) << n;
    EXPECT_EQ(m.triangles.size(), static_cast<std::size_t>(4 * n));
    EXPECT_NEAR(signed_volume(m), 0.5 * n * 0.09 * std::sin(2 * M_PI / n) * 0.9, 1e-12) << n;
    s.geometry = Sphere{0.5};
    m = shape_to_mesh(s, n + 1);
    EXPECT_TRUE(m.closed && closed_and_oriented(m)) << n;
    EXPECT_GT(signed_volume(m), 0.0);
    EXPECT_LT(signed_volume(m), 4.0 / 3.0 * M_PI * 0.125);  // inscribed
  }
  s.geometry = Sphere{0.5};
  EXPECT_NEAR(signed_volume(shape_to_mesh(s, 128)), 4.0 / 3.0 * M_PI * 0.125, 2e-3);
  // Meshes keep their triangles and closedness; a broken one stays marked open.
  s.geometry = MeshShape{test::l_prism()};
  m = shape_to_mesh(s);
  EXPECT_TRUE(m.closed && closed_and_oriented(m));
  EXPECT_NEAR(signed_volume(m), 3.0, 1e-12);
  auto open = test::l_prism();
  open->triangles.pop_back();
  open->closed = false;
  s.geometry = MeshShape{open};
  m = shape_to_mesh(s);
  EXPECT_FALSE(m.closed);
  EXPECT_FALSE(closed_and_oriented(m));
}

}  // namespace
}  // namespace porter
