#include <gtest/gtest.h>

#include <random>

#include "collision_test_utils.hpp"
#include "porter/planner/collision/map_kernel.hpp"

namespace porter::planner {
namespace {

void expect_identical(const MapKernel& a, const MapKernel& b) {
  ASSERT_EQ(a.padded_dims(), b.padded_dims());
  const Eigen::Vector3i n = a.padded_dims();
  for (int z = 0; z < n.z(); ++z)
    for (int y = 0; y < n.y(); ++y)
      for (int x = 0; x < n.x(); ++x) {
        ASSERT_EQ(a.in_base(x, y, z), b.in_base(x, y, z)) << x << " " << y << " " << z;
        ASSERT_EQ(a.in_arm(x, y, z), b.in_arm(x, y, z)) << x << " " << y << " " << z;
        // Cell centres of the distance field (cells of 2 voxels starting at the padding).
        if (x % 2 == 0 && y % 2 == 0 && z % 2 == 0) {
          ASSERT_EQ(a.clearance_units(x + 1.f, y + 1.f, z + 1.f), b.clearance_units(x + 1.f, y + 1.f, z + 1.f));
        }
      }
  for (int y = 0; y < n.y(); y += 3)
    for (int x = 0; x < n.x(); x += 5) ASSERT_EQ(a.base_columns_set(0, 0, x, y), b.base_columns_set(0, 0, x, y));
  for (int y = 0; y < n.y(); ++y)
    for (int x = 0; x < n.x(); ++x) ASSERT_EQ(a.base_disc_clear(x, y), b.base_disc_clear(x, y)) << x << " " << y;
}

TEST(MapKernelUpdate, IncrementalEqualsRebuildAndReportsTheChangedBox) {
  OccupancyGrid grid({-2.0, -1.0, 0.0}, 0.1, {70, 30, 20});
  std::mt19937_64 rng(11);
  for (int i = 0; i < 150; ++i)
    grid.set(static_cast<int>(test::uniform(rng, 0, 70)), static_cast<int>(test::uniform(rng, 0, 30)),
             static_cast<int>(test::uniform(rng, 0, 20)));
  MapKernelSettings s;
  s.safety_margin_m = 0.12;
  s.distance_cap_m = 0.6;
  MapKernel incremental(s, 4, 5, 5);
  const MapUpdateStats first = incremental.set_map(grid);
  EXPECT_FALSE(first.incremental);
  EXPECT_TRUE(incremental.set_map(grid).incremental);
  EXPECT_EQ(incremental.set_map(grid).changed_voxels, 0);
  int x0 = 0, y0 = 0;
  for (int round = 0; round < 4; ++round) {
    // A block appears (even rounds) and vanishes again (odd rounds) while a voxel in the far
    // corner toggles, as a mapper update would do.
    if (round % 2 == 0) {
      x0 = static_cast<int>(test::uniform(rng, 0, 60));
      y0 = static_cast<int>(test::uniform(rng, 0, 24));
    }
    for (int z = 0; z < 6; ++z)
      for (int y = y0; y < y0 + 4; ++y)
        for (int x = x0; x < x0 + 5; ++x) grid.set(x, y, z, round % 2 == 0);
    grid.set(69, 29, 19, round % 2 == 1);
    const MapUpdateStats st = incremental.set_map(grid);
    EXPECT_TRUE(st.incremental);
    EXPECT_GT(st.changed_voxels, 0);
    EXPECT_LE(st.changed_lo.x(), x0);
    EXPECT_GE(st.changed_hi.x(), x0 + 4);
    MapKernel fresh(s, 4, 5, 5);
    fresh.set_map(grid);
    expect_identical(incremental, fresh);
  }
  // A grid of another size is a full rebuild.
  const OccupancyGrid other({-2.0, -1.0, 0.0}, 0.1, {60, 30, 20});
  EXPECT_FALSE(incremental.set_map(other).incremental);
  MapKernel fresh(s, 4, 5, 5);
  fresh.set_map(other);
  expect_identical(incremental, fresh);
}

TEST(MapKernelUpdate, ScatteredChangesUpdateInSeparateRegionsAndEqualARebuild) {
  // A grid wide enough for many change tiles (kChangeTileVoxels columns each): a mapper's update
  // changes a few voxels here and there; each round changes a random number of scattered voxels
  // (1 to 300: a few tiles, many tiles merged, or more than the merge's 64 boxes).
  OccupancyGrid grid({-5.0, -4.0, 0.0}, 0.05, {330, 250, 30});
  std::mt19937_64 rng(29);
  auto random_voxel = [&](bool value) {
    grid.set(static_cast<int>(test::uniform(rng, 0, 330)), static_cast<int>(test::uniform(rng, 0, 250)),
             static_cast<int>(test::uniform(rng, 0, 30)), value);
  };
  for (int i = 0; i < 2000; ++i) random_voxel(true);
  MapKernelSettings s;
  s.safety_margin_m = 0.1;
  s.distance_cap_m = 0.5;
  MapKernel incremental(s, 4, 5, 5);
  EXPECT_FALSE(incremental.set_map(grid).incremental);
  for (const int changes : {1, 2, 5, 20, 80, 300}) {
    for (int i = 0; i < changes; ++i) random_voxel(test::uniform(rng, 0, 1) < 0.5);
    const MapUpdateStats st = incremental.set_map(grid);
    EXPECT_TRUE(st.incremental);
    MapKernel fresh(s, 4, 5, 5);
    fresh.set_map(grid);
    expect_identical(incremental, fresh);
  }
}

}  // namespace
}  // namespace porter::planner
