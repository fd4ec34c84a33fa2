#include "porter/backend/obstacle_points.hpp"

#include <algorithm>
#include <cmath>

namespace porter::backend {

std::vector<ObstaclePoint> collect_obstacle_points(const OccupancyGrid& map,
                                                   const Eigen::AlignedBox3d& region,
                                                   const ObstaclePointSettings& settings) {
  std::vector<ObstaclePoint> out;
  if (map.num_voxels() == 0 || region.isEmpty()) return out;
  const double res = map.resolution_m();
  const Eigen::Vector3i dims = map.dims();
  Eigen::Vector3i lo, hi;
  for (int a = 0; a < 3; ++a) {
    lo[a] = std::max(0, static_cast<int>(std::floor((region.min()[a] - map.origin_W()[a]) / res)));
    hi[a] = std::min(dims[a] - 1, static_cast<int>(std::floor((region.max()[a] - map.origin_W()[a]) / res)));
  }
  auto occupied_or_outside = [&](int i, int j, int k) {
    return !map.in_bounds(i, j, k) || map.occupied(i, j, k);
  };
  // Only the set bits of the storage are visited (a map is mostly free space: the forest scene's
  // 3.5 M voxels are 55 k words, most of them zero), in increasing linear index, i.e. z, then y,
  // then x ascending: the order of a plain triple loop over the voxels.
  const std::vector<std::uint64_t>& words = map.words();
  const std::int64_t nx = dims.x(), ny = dims.y();
  const std::int64_t n = map.num_voxels();
  const std::int64_t first_word = (lo.x() + nx * (lo.y() + ny * static_cast<std::int64_t>(lo.z()))) >> 6;
  const std::int64_t last_word = std::min<std::int64_t>(
      static_cast<std::int64_t>(words.size()) - 1, (hi.x() + nx * (hi.y() + ny * static_cast<std::int64_t>(hi.z()))) >> 6);
  for (std::int64_t w = std::max<std::int64_t>(0, first_word); w <= last_word; ++w) {
    std::uint64_t bits = words[static_cast<std::size_t>(w)];
    while (bits != 0) {
      // C++17 has no std::countr_zero; bits != 0 here.
      const std::int64_t idx = (w << 6) + __builtin_ctzll(bits);
      bits &= bits - 1;
      if (idx >= n) break;
      const int i = static_cast<int>(idx % nx);
      const std::int64_t row = idx / nx;
      const int j = static_cast<int>(row % ny);
      const int k = static_cast<int>(row / ny);
      if (i < lo.x() || i > hi.x() || j < lo.y() || j > hi.y() || k < lo.z() || k > hi.z()) continue;
      if (settings.surface_only && occupied_or_outside(i - 1, j, k) && occupied_or_outside(i + 1, j, k) &&
          occupied_or_outside(i, j - 1, k) && occupied_or_outside(i, j + 1, k) &&
          occupied_or_outside(i, j, k - 1) && occupied_or_outside(i, j, k + 1)) {
        continue;
      }
      const Eigen::Vector3d c = map.voxel_center_W(i, j, k);
      if (!region.contains(c)) continue;
      out.push_back({c, (1u << kNumLinks) - 1, false});
    }
  }
  if (settings.ground && region.min().z() <= 0.0) {
    const std::uint32_t links = ((1u << kNumLinks) - 1) & ~1u;
    out.reserve(out.size() + static_cast<std::size_t>(hi.x() - lo.x() + 1) * static_cast<std::size_t>(hi.y() - lo.y() + 1));
    for (int j = lo.y(); j <= hi.y(); ++j) {
      for (int i = lo.x(); i <= hi.x(); ++i) {
        Eigen::Vector3d c = map.voxel_center_W(i, j, 0);
        c.z() = -0.5 * res;
        if (c.x() < region.min().x() || c.x() > region.max().x() || c.y() < region.min().y() ||
            c.y() > region.max().y()) {
          continue;
        }
        out.push_back({c, links, true});
      }
    }
  }
  return out;
}

}  // namespace porter::backend
