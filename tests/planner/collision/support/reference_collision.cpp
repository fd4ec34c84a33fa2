#include "reference_collision.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "porter/core/scene_voxelizer.hpp"

namespace porter::test {

namespace {

CollisionShape placed(const CollisionShape& s, const Eigen::Isometry3d& T_W_L) {
  CollisionShape out = s;
  out.T_parent_shape = T_W_L * s.T_parent_shape;
  return out;
}

}  // namespace

ReferenceEnvironment::ReferenceEnvironment(const OccupancyGrid& grid, double safety_margin_m) : grid_(grid) {
  const double h = grid.resolution_m();
  ground_index_ = static_cast<int>(std::lround(-grid.origin_W().z() / h));
  const Eigen::Vector3i n = grid.dims();
  margin_set_.assign(static_cast<std::size_t>(grid.num_voxels()), false);
  const int k = safety_margin_m > 0.0 ? static_cast<int>(std::ceil(safety_margin_m / h)) + 1 : 0;
  auto gap = [](int d) { return std::max(std::abs(d) - 1, 0); };
  for (int z = 0; z < n.z(); ++z)
    for (int y = 0; y < n.y(); ++y)
      for (int x = 0; x < n.x(); ++x) {
        if (!grid.occupied(x, y, z)) continue;
        for (int dz = -k; dz <= k; ++dz)
          for (int dy = -k; dy <= k; ++dy)
            for (int dx = -k; dx <= k; ++dx) {
              const Eigen::Vector3i v(x + dx, y + dy, z + dz);
              if (!grid.in_bounds(v)) continue;
              const double g = h * std::sqrt(double(gap(dx) * gap(dx) + gap(dy) * gap(dy) + gap(dz) * gap(dz)));
              const bool in = (dx == 0 && dy == 0 && dz == 0) || g < safety_margin_m;
              if (in) margin_set_[static_cast<std::size_t>(grid.linear_index(v.x(), v.y(), v.z()))] = true;
            }
      }
}

bool ReferenceEnvironment::in_margin_set(const Eigen::Vector3i& idx) const {
  return grid_.in_bounds(idx) && margin_set_[static_cast<std::size_t>(grid_.linear_index(idx.x(), idx.y(), idx.z()))];
}

bool ReferenceEnvironment::flagged(const Eigen::Vector3i& idx, bool base_link) const {
  const Eigen::Vector3i n = grid_.dims();
  if (idx.z() < ground_index_) return !base_link;                                       // below the ground
  if (idx.x() < 0 || idx.y() < 0 || idx.x() >= n.x() || idx.y() >= n.y()) return true;  // outside horizontally
  if (idx.z() >= n.z()) return true;                                                    // above the map
  if (idx.z() < 0) return true;  // between the ground and a map starting above it
  return in_margin_set(idx);
}

bool ReferenceEnvironment::link_collides(const RobotModel& model, const KinematicsWorkspace& ws, int link) const {
  const double h = grid_.resolution_m();
  const Eigen::Vector3d o = grid_.origin_W();
  for (const CollisionShape& s : model.links[static_cast<std::size_t>(link)].shapes) {
    const CollisionShape sw = placed(s, ws.T_W_L[static_cast<std::size_t>(link)]);
    const Eigen::AlignedBox3d b = shape_bounds(sw);
    const Eigen::Vector3i lo = ((b.min() - o) / h).array().floor().cast<int>() - 1;
    const Eigen::Vector3i hi = ((b.max() - o) / h).array().floor().cast<int>() + 1;
    OccupancyGrid local(o + h * lo.cast<double>(), h, hi - lo + Eigen::Vector3i::Ones());
    voxelize_shape(sw, local);
    const Eigen::Vector3i d = local.dims();
    for (int z = 0; z < d.z(); ++z)
      for (int y = 0; y < d.y(); ++y)
        for (int x = 0; x < d.x(); ++x)
          if (local.occupied(x, y, z) && flagged(lo + Eigen::Vector3i(x, y, z), link == 0)) return true;
  }
  return false;
}

int ReferenceEnvironment::first_colliding_link(const RobotModel& model, const RobotConfiguration& config) const {
  KinematicsWorkspace ws;
  forward_kinematics(model, config, ws);
  for (int link = 0; link < kNumLinks; ++link)
    if (link_collides(model, ws, link)) return link;
  return -1;
}

bool ReferenceEnvironment::link_within(const RobotModel& model, const KinematicsWorkspace& ws, int link,
                                       double distance_m) const {
  const double h = grid_.resolution_m();
  const Eigen::Vector3d o = grid_.origin_W();
  std::vector<CollisionShape> shapes;
  Eigen::AlignedBox3d b;
  b.setEmpty();
  for (const CollisionShape& s : model.links[static_cast<std::size_t>(link)].shapes) {
    shapes.push_back(placed(s, ws.T_W_L[static_cast<std::size_t>(link)]));
    b.extend(shape_bounds(shapes.back()));
  }
  if (shapes.empty()) return false;
  const Eigen::Vector3i lo = ((b.min().array() - distance_m - o.array()) / h).floor().cast<int>() - 1;
  const Eigen::Vector3i hi = ((b.max().array() + distance_m - o.array()) / h).floor().cast<int>() + 1;
  for (int z = lo.z(); z <= hi.z(); ++z)
    for (int y = lo.y(); y <= hi.y(); ++y)
      for (int x = lo.x(); x <= hi.x(); ++x) {
        if (!flagged(Eigen::Vector3i(x, y, z), link == 0)) continue;
        const Eigen::Vector3d c = o + h * Eigen::Vector3d(x + 0.5, y + 0.5, z + 0.5);
        if (b.exteriorDistance(c) > distance_m) continue;
        for (const auto& s : shapes)
          if (shape_signed_distance(s, c) <= distance_m) return true;
      }
  return false;
}

}  // namespace porter::test
