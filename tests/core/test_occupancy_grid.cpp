// OccupancyGrid: geometry of the voxel lattice, index <-> world helpers, bit storage.

#include <random>

#include <gtest/gtest.h>

#include "porter/core/occupancy_grid.hpp"

namespace porter {
namespace {

TEST(OccupancyGrid, CoveringRoundsUpButNotForRoundingNoise) {
  const Eigen::AlignedBox3d b(Eigen::Vector3d(-1, -2, 0), Eigen::Vector3d(1.02, 2, 2.5));
  const OccupancyGrid g = OccupancyGrid::covering(b, 0.05);
  EXPECT_EQ(g.dims(), Eigen::Vector3i(41, 80, 50));  // 2.02 / 0.05 = 40.4 -> 41; 4 / 0.05 -> 80
  EXPECT_TRUE(g.origin_W().isApprox(b.min()));
  EXPECT_EQ(g.num_voxels(), 41 * 80 * 50);
  EXPECT_EQ(g.count(), 0);
  EXPECT_TRUE(g.bounds_W().contains(b));
  // 0.3 / 0.1 is 2.9999999999999996 in floating point: still 3 voxels.
  EXPECT_EQ(OccupancyGrid::covering(Eigen::AlignedBox3d(Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(0.3)), 0.1)
                .dims(),
            Eigen::Vector3i(3, 3, 3));
}

TEST(OccupancyGrid, IndexWorldRoundTrip) {
  const OccupancyGrid g(Eigen::Vector3d(-1.0, 0.5, 0.0), 0.1, Eigen::Vector3i(20, 10, 5));
  std::mt19937_64 rng(1);
  for (int k = 0; k < 1000; ++k) {
    const Eigen::Vector3i i(rng() % 20, rng() % 10, rng() % 5);
    const Eigen::Vector3d c = g.voxel_center_W(i.x(), i.y(), i.z());
    EXPECT_EQ(g.world_to_index(c), i);
    EXPECT_TRUE(g.voxel_box_W(i.x(), i.y(), i.z()).contains(c));
    EXPECT_NEAR(g.voxel_box_W(i.x(), i.y(), i.z()).sizes().maxCoeff(), 0.1, 1e-12);
    Eigen::Vector3i j;
    ASSERT_TRUE(g.world_to_index_checked(c, &j));
    EXPECT_EQ(j, i);
  }
  Eigen::Vector3i j(7, 7, 7);
  EXPECT_FALSE(g.world_to_index_checked(Eigen::Vector3d(-1.01, 0.6, 0.1), &j));
  EXPECT_FALSE(g.world_to_index_checked(Eigen::Vector3d(1.0, 0.6, 0.1), &j));  // far face is outside
  EXPECT_FALSE(g.world_to_index_checked(Eigen::Vector3d(1e30, 0.6, 0.1), &j));
  EXPECT_FALSE(g.world_to_index_checked(Eigen::Vector3d(std::nan(""), 0.6, 0.1), &j));
  EXPECT_EQ(j, Eigen::Vector3i(7, 7, 7));
}

TEST(OccupancyGrid, SetClearCountAndOutsideQueries) {
  OccupancyGrid g(Eigen::Vector3d::Zero(), 0.5, Eigen::Vector3i(7, 3, 5));  // 105 voxels, 2 words
  g.set(0, 0, 0);
  g.set(6, 2, 4);
  g.set(3, 1, 2);
  g.set(3, 1, 2);
  EXPECT_EQ(g.count(), 3);
  EXPECT_TRUE(g.occupied(6, 2, 4));
  EXPECT_TRUE(g.occupied_at(Eigen::Vector3d(3.2, 1.2, 2.3)));
  EXPECT_FALSE(g.occupied_at(Eigen::Vector3d(3.6, 1.2, 2.3)));  // past the far face
  EXPECT_FALSE(g.occupied(7, 2, 4));
  EXPECT_FALSE(g.occupied(-1, 0, 0));
  g.set(3, 1, 2, false);
  EXPECT_EQ(g.count(), 2);
  g.clear();
  EXPECT_EQ(g.count(), 0);
}

TEST(OccupancyGrid, BitLayoutIsXFastest) {
  OccupancyGrid g(Eigen::Vector3d::Zero(), 1.0, Eigen::Vector3i(64, 2, 2));
  g.set(5, 1, 1);
  const std::int64_t k = 5 + 64 * (1 + 2 * 1);
  EXPECT_EQ(g.linear_index(5, 1, 1), k);
  ASSERT_EQ(g.words().size(), 4u);
  EXPECT_EQ(g.words()[static_cast<std::size_t>(k / 64)], std::uint64_t{1} << 5);
}

}  // namespace
}  // namespace porter
