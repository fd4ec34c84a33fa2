#include <gtest/gtest.h>
#include <octomap/OcTree.h>

#include "porter/planner/collision/octomap_grid.hpp"

namespace porter::planner {
namespace {

TEST(OctomapGrid, OccupiedLeavesBecomeVoxelsOnTheTreeLattice) {
  octomap::OcTree tree(0.05);
  tree.updateNode(octomap::point3d(1.02f, 0.51f, 0.33f), true);
  tree.updateNode(octomap::point3d(-0.37f, 0.12f, 0.01f), true);
  tree.updateNode(octomap::point3d(0.2f, 0.2f, 0.2f), false);
  // A pruned 0.1 m block: 8 occupied children collapse into one inner leaf.
  for (int k = 0; k < 8; ++k)
    tree.updateNode(
        octomap::point3d(0.425f + 0.05f * (k & 1), 0.025f + 0.05f * ((k >> 1) & 1), 1.025f + 0.05f * (k >> 2)), true);
  tree.prune();
  const Eigen::AlignedBox3d bounds(Eigen::Vector3d(-1.0, -1.0, 0.0), Eigen::Vector3d(2.0, 1.0, 1.5));
  const OccupancyGrid grid = occupancy_from_octomap(tree, bounds);
  EXPECT_NEAR(grid.resolution_m(), 0.05, 1e-12);
  EXPECT_TRUE(grid.origin_W().isApprox(Eigen::Vector3d(-1.0, -1.0, 0.0)));
  EXPECT_EQ(grid.dims(), Eigen::Vector3i(60, 40, 30));
  EXPECT_TRUE(grid.occupied_at(Eigen::Vector3d(1.02, 0.51, 0.33)));
  EXPECT_TRUE(grid.occupied_at(Eigen::Vector3d(-0.37, 0.12, 0.01)));
  EXPECT_FALSE(grid.occupied_at(Eigen::Vector3d(0.2, 0.2, 0.2)));
  for (int k = 0; k < 8; ++k)
    EXPECT_TRUE(grid.occupied_at(
        Eigen::Vector3d(0.425 + 0.05 * (k & 1), 0.025 + 0.05 * ((k >> 1) & 1), 1.025 + 0.05 * (k >> 2))));
  EXPECT_EQ(grid.count(), 10);
  // Unset bounds: the tree's own bounding box.
  Eigen::AlignedBox3d none;
  none.setEmpty();
  EXPECT_EQ(occupancy_from_octomap(tree, none).count(), 10);
}

}  // namespace
}  // namespace porter::planner
