#include "porter/baselines/sphere_cover.hpp"

#include <cmath>

#include "porter/core/geometry.hpp"

namespace porter::baselines {

LinkSpheres cover_shapes(const std::vector<CollisionShape>& shapes, double cell) {
  LinkSpheres out;
  out.radius_m = 0.5 * std::sqrt(3.0) * cell;
  Eigen::AlignedBox3d bounds;
  for (const CollisionShape& s : shapes) bounds.extend(shape_bounds(s));
  if (bounds.isEmpty()) return out;
  const Eigen::Vector3d origin = bounds.min();
  Eigen::Vector3i n;
  for (int a = 0; a < 3; ++a) n[a] = std::max(1, static_cast<int>(std::ceil(bounds.sizes()[a] / cell - 1e-9)));
  std::vector<char> hit(static_cast<std::size_t>(n.prod()), 0);
  auto index = [&](int i, int j, int k) {
    return static_cast<std::size_t>(i) + static_cast<std::size_t>(n.x()) * (static_cast<std::size_t>(j) + static_cast<std::size_t>(n.y()) * k);
  };
  for (int k = 0; k < n.z(); ++k)
    for (int j = 0; j < n.y(); ++j)
      for (int i = 0; i < n.x(); ++i) {
        const Eigen::Vector3d lo = origin + cell * Eigen::Vector3d(i, j, k);
        const Eigen::AlignedBox3d box(lo, lo + Eigen::Vector3d::Constant(cell));
        for (const CollisionShape& s : shapes) {
          if (shape_intersects_aabb(s, box)) {
            hit[index(i, j, k)] = 1;
            break;
          }
        }
      }
  auto occupied = [&](int i, int j, int k) {
    return i >= 0 && j >= 0 && k >= 0 && i < n.x() && j < n.y() && k < n.z() && hit[index(i, j, k)];
  };
  for (int k = 0; k < n.z(); ++k)
    for (int j = 0; j < n.y(); ++j)
      for (int i = 0; i < n.x(); ++i) {
        if (!hit[index(i, j, k)]) continue;
        bool interior = true;  // all 26 neighbours meet the geometry: the surface cannot pass here
        for (int c = -1; c <= 1 && interior; ++c)
          for (int b = -1; b <= 1 && interior; ++b)
            for (int a = -1; a <= 1 && interior; ++a) interior = occupied(i + a, j + b, k + c);
        if (interior) continue;
        out.centers_L.push_back(origin + cell * (Eigen::Vector3d(i, j, k) + Eigen::Vector3d::Constant(0.5)));
      }
  return out;
}

RobotSpheres cover_robot(const RobotModel& model, const SphereCoverSettings& settings) {
  RobotSpheres spheres;
  for (int j = 0; j < kNumLinks; ++j) {
    spheres[static_cast<std::size_t>(j)] = cover_shapes(model.links[static_cast<std::size_t>(j)].shapes, settings.cell_m);
  }
  return spheres;
}

}  // namespace porter::baselines
