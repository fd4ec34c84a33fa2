// The sphere baseline's ESDF: the separable transform against brute force, the field's values at
// voxel centres, and its gradient against finite differences.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "porter/baselines/distance_field.hpp"

namespace porter::baselines {
namespace {

TEST(DistanceField, TransformMatchesBruteForce) {
  std::mt19937 rng(1);
  const Eigen::Vector3i dims(13, 9, 7);
  std::vector<double> f(static_cast<std::size_t>(dims.prod()), std::numeric_limits<double>::infinity());
  std::vector<Eigen::Vector3i> sites;
  for (int n = 0; n < 12; ++n) {
    const Eigen::Vector3i s(static_cast<int>(rng() % 13), static_cast<int>(rng() % 9), static_cast<int>(rng() % 7));
    sites.push_back(s);
    f[static_cast<std::size_t>(s.x() + 13 * (s.y() + 9 * s.z()))] = 0.0;
  }
  squared_distance_transform(f, dims);
  for (int k = 0; k < 7; ++k)
    for (int j = 0; j < 9; ++j)
      for (int i = 0; i < 13; ++i) {
        double best = std::numeric_limits<double>::infinity();
        for (const auto& s : sites) best = std::min(best, static_cast<double>((s - Eigen::Vector3i(i, j, k)).squaredNorm()));
        ASSERT_EQ(f[static_cast<std::size_t>(i + 13 * (j + 9 * k))], best);
      }
  std::vector<double> empty(27, std::numeric_limits<double>::infinity());
  squared_distance_transform(empty, Eigen::Vector3i(3, 3, 3));
  for (double v : empty) EXPECT_EQ(v, std::numeric_limits<double>::infinity());
}

TEST(DistanceField, SignedValuesAtVoxelCentresAndGradient) {
  OccupancyGrid grid(Eigen::Vector3d(-1.0, -1.0, 0.0), 0.05, Eigen::Vector3i(40, 40, 30));
  for (int k = 5; k < 15; ++k)
    for (int j = 10; j < 30; ++j)
      for (int i = 18; i < 22; ++i) grid.set(i, j, k);  // a wall 20 cm thick
  const DistanceField field = DistanceField::build(grid, Eigen::AlignedBox3d(), 0.6);
  auto brute = [&](int i, int j, int k) {
    const bool occ = grid.occupied(i, j, k);
    double best = std::numeric_limits<double>::infinity();
    for (int c = 0; c < 30; ++c)
      for (int b = 0; b < 40; ++b)
        for (int a = 0; a < 40; ++a)
          if (grid.occupied(a, b, c) != occ) best = std::min(best, std::sqrt(double((a - i) * (a - i) + (b - j) * (b - j) + (c - k) * (c - k))));
    const double d = best * 0.05 - 0.025;
    return std::clamp(occ ? -d : d, -0.6, 0.6);
  };
  std::mt19937 rng(2);
  for (int n = 0; n < 200; ++n) {
    const int i = static_cast<int>(rng() % 40), j = static_cast<int>(rng() % 40), k = static_cast<int>(rng() % 30);
    EXPECT_NEAR(field.grid().value(i, j, k), brute(i, j, k), 1e-6) << i << " " << j << " " << k;
  }
  // In front of the wall's face (x = 0 m at i = 18 -> face at x = -0.1), the field is the distance.
  EXPECT_NEAR(field.distance(Eigen::Vector3d(-0.4, 0.0, 0.5)), 0.3, 0.01);
  // The gradient is the interpolant's.
  const double h = 1e-6;
  for (int n = 0; n < 200; ++n) {
    std::uniform_real_distribution<double> u(0.05, 0.95);
    const Eigen::Vector3d p(-1.0 + 2.0 * u(rng), -1.0 + 2.0 * u(rng), 1.5 * u(rng));
    Eigen::Vector3d g;
    field.distance(p, &g);
    for (int a = 0; a < 3; ++a) {
      Eigen::Vector3d dp = Eigen::Vector3d::Zero();
      dp[a] = h;
      EXPECT_NEAR((field.distance(p + dp) - field.distance(p - dp)) / (2 * h), g[a], 1e-5);
    }
  }
}

}  // namespace
}  // namespace porter::baselines
