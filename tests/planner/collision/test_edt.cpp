// The distance transform's fast forms against the plain ones (planner/collision/src/edt.hpp, a
// private header of porter_collision): the sampled transform equals the full one on the lattice
// it promises (and agrees on which values reach far2), the in-place vertex dilation equals the
// box dilation, and the full transform equals brute force.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "edt.hpp"

namespace porter::planner::edt {
namespace {

std::vector<std::uint8_t> random_sites(std::mt19937& rng, int n, double p) {
  std::bernoulli_distribution site(p);
  std::vector<std::uint8_t> s(static_cast<std::size_t>(n));
  for (auto& v : s) v = site(rng) ? 1 : 0;
  return s;
}

TEST(Edt, FullTransformEqualsBruteForce) {
  std::mt19937 rng(3);
  const int nx = 9, ny = 7, nz = 6;
  const auto site = random_sites(rng, nx * ny * nz, 0.03);
  std::vector<std::int32_t> d2;
  squared_distance_3d(site, nx, ny, nz, d2);
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x) {
        std::int32_t best = kFar;
        for (int c = 0; c < nz; ++c)
          for (int b = 0; b < ny; ++b)
            for (int a = 0; a < nx; ++a)
              if (site[static_cast<std::size_t>(a + nx * (b + ny * c))])
                best = std::min(best, (x - a) * (x - a) + (y - b) * (y - b) + (z - c) * (z - c));
        ASSERT_EQ(d2[static_cast<std::size_t>(x + nx * (y + ny * z))], best) << x << " " << y << " " << z;
      }
}

TEST(Edt, SampledTransformEqualsTheFullOneOnItsLattice) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 40; ++trial) {
    std::uniform_int_distribution<int> size(1, 40);
    const int nx = size(rng), ny = size(rng), nz = size(rng);
    const double density = trial % 4 == 0 ? 0.0 : (trial % 4 == 1 ? 0.001 : (trial % 4 == 2 ? 0.01 : 0.2));
    const auto site = random_sites(rng, nx * ny * nz, density);
    std::vector<std::int32_t> full, sampled;
    squared_distance_3d(site, nx, ny, nz, full);
    const int step = 1 + trial % 3;
    const int x0 = std::uniform_int_distribution<int>(0, step - 1)(rng);
    const int y0 = std::uniform_int_distribution<int>(0, step - 1)(rng);
    const std::int32_t far2 = trial % 2 == 0 ? kFar : std::uniform_int_distribution<std::int32_t>(1, 300)(rng);
    squared_distance_3d_sampled(site, nx, ny, nz, x0, y0, step, sampled, far2);
    for (int z = 0; z < nz; ++z)
      for (int y = y0; y < ny; y += step)
        for (int x = x0; x < nx; x += step) {
          const std::size_t i = static_cast<std::size_t>(x + nx * (y + ny * z));
          if (full[i] < far2) {
            ASSERT_EQ(sampled[i], full[i]) << "trial " << trial << " at " << x << " " << y << " " << z;
          } else {
            ASSERT_GE(sampled[i], far2) << "trial " << trial << " at " << x << " " << y << " " << z;
          }
        }
  }
}

TEST(Edt, InPlaceVertexDilationEqualsTheBoxDilation) {
  std::mt19937 rng(13);
  for (int trial = 0; trial < 20; ++trial) {
    std::uniform_int_distribution<int> size(1, 17);
    const int nx = size(rng), ny = size(rng), nz = size(rng);
    auto a = random_sites(rng, nx * ny * nz, 0.05 * (trial % 5));
    auto b = a;
    dilate_to_vertices(a, nx, ny, nz);
    dilate_box(b, nx, ny, nz, 0, 1);
    ASSERT_EQ(a, b) << "trial " << trial;
  }
}

}  // namespace
}  // namespace porter::planner::edt
