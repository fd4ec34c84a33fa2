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
  for (int k = lo.z(); k <= hi.z(); ++k) {
    for (int j = lo.y(); j <= hi.y(); ++j) {
      for (int i = lo.x(); i <= hi.x(); ++i) {
        if (!map.occupied(i, j, k)) continue;
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
  }
  if (settings.ground && region.min().z() <= 0.0) {
    const std::uint32_t links = ((1u << kNumLinks) - 1) & ~1u;
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
