// collect_obstacle_points visits only the set bits of the map's storage; it must return exactly
// what the plain triple loop over every voxel below returns (the slow reference), same order.
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

}  // namespace
}  // namespace porter::backend
