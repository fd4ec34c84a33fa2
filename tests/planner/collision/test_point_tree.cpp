#include <gtest/gtest.h>

#include <random>
#include <set>
#include <tuple>

#include "collision_test_utils.hpp"
#include "porter/planner/collision/point_tree.hpp"

namespace porter::planner {
namespace {

TEST(PointTree, EveryNodeSphereContainsItsSubtree) {
  std::mt19937_64 rng(3);
  PointTreePool pool;
  const auto pts = test::random_cloud(1000, rng);
  const int t = pool.add_tree(pts, 7);
  ASSERT_EQ(pool.tree_size(t), pts.size());
  for (std::uint32_t i = pool.tree_begin(t); i < pool.tree_end(t); ++i) {
    const PointTreeNode& n = pool.nodes()[i];
    ASSERT_GT(n.skip, i);
    ASSERT_LE(n.skip, pool.tree_end(t));
    if (n.num_points > 0) {
      EXPECT_LE(n.num_points, 7u);
      EXPECT_EQ(n.skip, i + 1);
    }
    for (std::uint32_t k = i; k < n.skip; ++k) {
      const PointTreeNode& leaf = pool.nodes()[k];
      for (std::uint32_t p = leaf.first_point; p < leaf.first_point + leaf.num_points; ++p) {
        const Eigen::Vector3f d(pool.x()[p] - n.cx, pool.y()[p] - n.cy, pool.z()[p] - n.cz);
        EXPECT_LE(d.norm(), n.radius_m);
      }
    }
  }
}

TEST(PointTree, WalkVisitsEveryPointOnceAndStopsAtAHit) {
  std::mt19937_64 rng(4);
  PointTreePool pool;
  pool.add_tree(test::random_cloud(10, rng), 4);
  const auto pts = test::random_cloud(500, rng);
  const int t = pool.add_tree(pts, 16);
  pool.add_tree({}, 4);
  std::multiset<std::tuple<float, float, float>> seen, expected;
  for (const auto& p : pts) expected.insert({p.x(), p.y(), p.z()});
  EXPECT_FALSE(point_tree_any(
      pool, t, [](const PointTreeNode&) { return false; },
      [&](float x, float y, float z) {
        seen.insert({x, y, z});
        return false;
      }));
  EXPECT_EQ(seen, expected);
  int visited = 0;
  EXPECT_TRUE(point_tree_any(
      pool, t, [](const PointTreeNode&) { return false; }, [&](float, float, float) { return ++visited == 3; }));
  EXPECT_EQ(visited, 3);
  EXPECT_FALSE(point_tree_any(
      pool, 2, [](const PointTreeNode&) { return false; }, [](float, float, float) { return true; }));
  EXPECT_EQ(pool.tree_size(2), 0u);
  // Skipping the root skips everything.
  EXPECT_FALSE(point_tree_any(
      pool, t, [](const PointTreeNode&) { return true; }, [](float, float, float) { return true; }));
}

}  // namespace
}  // namespace porter::planner
