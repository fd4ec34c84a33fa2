// collect_obstacle_points visits only the set bits of the map's storage; it must return exactly
// what the plain triple loop over every voxel below returns (the slow reference), same order.
// With a CellMask it returns the subsequence the mask contains, with keys that identify a point
// across selections; CellMask::covers(box) implies contains() for every point of the box.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "porter/backend/obstacle_points.hpp"

namespace porter::backend {
namespace {

std::vector<ObstaclePoint> reference_points(const OccupancyGrid& map, const Eigen::AlignedBox3d& region,
                                            const ObstaclePointSettings& settings) {
  std::vector<ObstaclePoint> out;
  const Eigen::Vector3i d = map.dims();
  auto solid = [&](int i, int j, int k) { return !map.in_bounds(i, j, k) || map.occupied(i, j, k); };
  for (int k = 0; k < d.z(); ++k)
    for (int j = 0; j < d.y(); ++j)
      for (int i = 0; i < d.x(); ++i) {
        if (!map.occupied(i, j, k)) continue;
        if (settings.surface_only && solid(i - 1, j, k) && solid(i + 1, j, k) && solid(i, j - 1, k) &&
            solid(i, j + 1, k) && solid(i, j, k - 1) && solid(i, j, k + 1))
          continue;
        const Eigen::Vector3d c = map.voxel_center_W(i, j, k);
        if (region.contains(c)) out.push_back({c, (1u << kNumLinks) - 1, false});
      }
  if (settings.ground && region.min().z() <= 0.0) {
    for (int j = 0; j < d.y(); ++j)
      for (int i = 0; i < d.x(); ++i) {
        Eigen::Vector3d c = map.voxel_center_W(i, j, 0);
        c.z() = -0.5 * map.resolution_m();
        if (c.x() < region.min().x() || c.x() > region.max().x() || c.y() < region.min().y() || c.y() > region.max().y())
          continue;
        out.push_back({c, ((1u << kNumLinks) - 1) & ~1u, true});
      }
  }
  return out;
}

TEST(ObstaclePoints, MatchTheVoxelLoopOnRandomMapsAndRegions) {
  std::mt19937 rng(11u);
  std::uniform_int_distribution<int> size(1, 70);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int compared = 0;
  for (int trial = 0; trial < 60; ++trial) {
    // Odd sizes, so rows straddle words; blocks of solid voxels (interior ones are dropped) and
    // scattered single voxels.
    const Eigen::Vector3i dims(size(rng), size(rng), 1 + size(rng) / 4);
    OccupancyGrid map(Eigen::Vector3d(-1.3, 0.4, 0.0), 0.05, dims);
    const double fill = trial % 3 == 0 ? 0.0 : u(rng) * 0.3;
    for (int k = 0; k < dims.z(); ++k)
      for (int j = 0; j < dims.y(); ++j)
        for (int i = 0; i < dims.x(); ++i)
          if (u(rng) < fill) map.set(i, j, k);
    for (int b = 0; b < 3; ++b) {
      const int i0 = static_cast<int>(u(rng) * dims.x()), j0 = static_cast<int>(u(rng) * dims.y());
      for (int k = 0; k < dims.z(); ++k)
        for (int j = j0; j < std::min(dims.y(), j0 + 6); ++j)
          for (int i = i0; i < std::min(dims.x(), i0 + 6); ++i) map.set(i, j, k);
    }
    const Eigen::AlignedBox3d full = map.bounds_W();
    Eigen::AlignedBox3d part = full;
    const Eigen::Vector3d a = full.min() + full.sizes().cwiseProduct(Eigen::Vector3d(u(rng), u(rng), u(rng)));
    const Eigen::Vector3d b = full.min() + full.sizes().cwiseProduct(Eigen::Vector3d(u(rng), u(rng), u(rng)));
    part = Eigen::AlignedBox3d(a.cwiseMin(b) - Eigen::Vector3d(0, 0, trial % 2 ? 0.1 : 0.0), a.cwiseMax(b));
    for (const Eigen::AlignedBox3d& region : {full, part}) {
      for (const bool surface : {true, false}) {
        ObstaclePointSettings s;
        s.surface_only = surface;
        s.ground = trial % 4 != 1;
        const std::vector<ObstaclePoint> fast = collect_obstacle_points(map, region, s);
        const std::vector<ObstaclePoint> ref = reference_points(map, region, s);
        ASSERT_EQ(fast.size(), ref.size()) << "trial " << trial;
        for (std::size_t n = 0; n < ref.size(); ++n) {
          ASSERT_EQ(fast[n].p_W, ref[n].p_W) << "trial " << trial << " point " << n;
          ASSERT_EQ(fast[n].links, ref[n].links);
          ASSERT_EQ(fast[n].ground, ref[n].ground);
        }
        compared += static_cast<int>(ref.size());
      }
    }
  }
  EXPECT_GT(compared, 10000);  // not vacuous
}

TEST(ObstaclePoints, MaskedCollectionIsTheMaskedSubsequenceWithStableKeys) {
  std::mt19937 rng(23u);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int kept_total = 0, dropped_total = 0;
  for (int trial = 0; trial < 30; ++trial) {
    const Eigen::Vector3i dims(20 + trial, 31, 9);
    OccupancyGrid map(Eigen::Vector3d(0.3, -0.8, 0.0), 0.05, dims);
    for (int k = 0; k < dims.z(); ++k)
      for (int j = 0; j < dims.y(); ++j)
        for (int i = 0; i < dims.x(); ++i)
          if (u(rng) < 0.2) map.set(i, j, k);
    Eigen::AlignedBox3d bounds = map.bounds_W();
    bounds.min().z() -= map.resolution_m();
    ObstaclePointSettings s;
    s.ground = trial % 2 == 0;
    std::vector<std::uint64_t> all_keys;
    const std::vector<ObstaclePoint> all = collect_obstacle_points(map, map.bounds_W(), s, nullptr, &all_keys);
    ASSERT_EQ(all_keys.size(), all.size());
    for (std::size_t n = 1; n < all_keys.size(); ++n) ASSERT_LT(all_keys[n - 1], all_keys[n]);
    // Two nested masks of random boxes (the second adds to the first, as a selection grows).
    CellMask mask(bounds, 0.12 + 0.05 * u(rng));
    std::vector<std::uint64_t> previous_keys;
    for (int round = 0; round < 2; ++round) {
      for (int b = 0; b < 2; ++b) {
        const Eigen::Vector3d a = bounds.min() + bounds.sizes().cwiseProduct(Eigen::Vector3d(u(rng), u(rng), u(rng)));
        const Eigen::Vector3d size(0.3 * u(rng), 0.3 * u(rng), 0.3 * u(rng));
        mask.add(Eigen::AlignedBox3d(a, a + size));
      }
      std::vector<std::uint64_t> keys;
      const std::vector<ObstaclePoint> kept = collect_obstacle_points(map, map.bounds_W(), s, &mask, &keys);
      std::size_t next = 0;
      for (std::size_t n = 0; n < all.size(); ++n) {
        if (!mask.contains(all[n].p_W)) {
          ++dropped_total;
          continue;
        }
        ASSERT_LT(next, kept.size());
        ASSERT_EQ(kept[next].p_W, all[n].p_W);
        ASSERT_EQ(kept[next].ground, all[n].ground);
        ASSERT_EQ(keys[next], all_keys[n]) << "a point's key does not depend on the mask";
        ++next;
      }
      ASSERT_EQ(next, kept.size());
      kept_total += static_cast<int>(kept.size());
      // The grown mask keeps every point of the smaller one.
      std::size_t m = 0;
      for (std::uint64_t k : previous_keys) {
        while (m < keys.size() && keys[m] < k) ++m;
        ASSERT_LT(m, keys.size());
        ASSERT_EQ(keys[m], k);
      }
      previous_keys = keys;
    }
    // covers(box) => contains(p) for every p in the box; a box with an unmarked cell is not covered.
    for (int b = 0; b < 40; ++b) {
      const Eigen::Vector3d a = bounds.min() + bounds.sizes().cwiseProduct(Eigen::Vector3d(u(rng), u(rng), u(rng)));
      const Eigen::AlignedBox3d box(a, a + Eigen::Vector3d(0.2 * u(rng), 0.2 * u(rng), 0.2 * u(rng)));
      bool all_in = true;
      for (int n = 0; n < 200; ++n) {
        const Eigen::Vector3d p = box.min() + box.sizes().cwiseProduct(Eigen::Vector3d(u(rng), u(rng), u(rng)));
        const bool in = mask.contains(p) || !bounds.contains(p);
        all_in = all_in && in;
        if (mask.covers(box)) {
          ASSERT_TRUE(in) << "trial " << trial;
        }
      }
      if (!all_in) {
        EXPECT_FALSE(mask.covers(box));
      }
    }
  }
  EXPECT_GT(kept_total, 1000);
  EXPECT_GT(dropped_total, 1000);
}

}  // namespace
}  // namespace porter::backend
