#include "porter/planner/collision/link_distance.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>
#include <variant>

#include "edt.hpp"
#include "porter/core/occupancy_grid.hpp"
#include "porter/core/scene_voxelizer.hpp"

namespace porter::planner {

LinkDistance::LinkDistance(const std::vector<CollisionShape>& shapes_L) : shapes_(shapes_L) {
  bounds_.setEmpty();
  for (std::size_t i = 0; i < shapes_.size(); ++i) {
    const CollisionShape& s = shapes_[i];
    Prim p;
    p.shape = static_cast<int>(i);
    const Eigen::Isometry3d T_S_L = s.T_parent_shape.inverse();
    p.R_S_L = T_S_L.linear().cast<float>();
    p.t_S_L = T_S_L.translation().cast<float>();
    const Eigen::AlignedBox3d b = shape_bounds(s);
    bounds_.extend(b);
    // Grow the float box by a hair so rounding never puts a shape point outside it.
    p.bounds_L = Eigen::AlignedBox3f(b.min().cast<float>() - Eigen::Vector3f::Constant(1e-5f),
                                     b.max().cast<float>() + Eigen::Vector3f::Constant(1e-5f));
    std::visit(
        [&p](const auto& g) {
          using G = std::decay_t<decltype(g)>;
          if constexpr (std::is_same_v<G, Box>) {
            p.kind = Kind::kBox;
            p.half_m = Eigen::Vector3d(0.5 * g.size_m).cast<float>();
          } else if constexpr (std::is_same_v<G, Cylinder>) {
            p.kind = Kind::kCylinder;
            p.half_m = Eigen::Vector3f(static_cast<float>(g.radius_m), static_cast<float>(g.radius_m),
                                       static_cast<float>(0.5 * g.length_m));
          } else if constexpr (std::is_same_v<G, Sphere>) {
            p.kind = Kind::kSphere;
            p.half_m = Eigen::Vector3f::Constant(static_cast<float>(g.radius_m));
          } else {
            p.kind = Kind::kMesh;
          }
        },
        s.geometry);
    prims_.push_back(p);
  }
}

BoxUnionBound::BoxUnionBound(const std::vector<CollisionShape>& shapes_L) {
  std::vector<Eigen::AlignedBox3d> boxes;
  for (const auto& s : shapes_L) boxes.push_back(shape_bounds(s));
  // Merge the pair whose union box adds the least volume until kMaxBoxes are left.
  while (boxes.size() > static_cast<std::size_t>(kMaxBoxes)) {
    std::size_t bi = 0, bj = 1;
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < boxes.size(); ++i)
      for (std::size_t j = i + 1; j < boxes.size(); ++j) {
        const double added = boxes[i].merged(boxes[j]).volume() - boxes[i].volume() - boxes[j].volume();
        if (added < best) {
          best = added;
          bi = i;
          bj = j;
        }
      }
    boxes[bi].extend(boxes[bj]);
    boxes.erase(boxes.begin() + static_cast<std::ptrdiff_t>(bj));
  }
  for (const auto& b : boxes) {
    Box& out = boxes_[static_cast<std::size_t>(count_++)];
    for (int a = 0; a < 3; ++a) {
      out.lo[a] = static_cast<float>(b.min()[a]) - 1e-5f;
      out.hi[a] = static_cast<float>(b.max()[a]) + 1e-5f;
    }
  }
}

float LinkDistance::prim_distance(const Prim& prim, const Eigen::Vector3f& p_L) {
  const Eigen::Vector3f q = prim.R_S_L * p_L + prim.t_S_L;
  switch (prim.kind) {
    case Kind::kBox: {
      const Eigen::Vector3f d = q.cwiseAbs() - prim.half_m;
      return d.cwiseMax(0.f).norm() + std::min(d.maxCoeff(), 0.f);
    }
    case Kind::kCylinder: {
      const float dr = std::sqrt(q.x() * q.x() + q.y() * q.y()) - prim.half_m.x();
      const float dz = std::abs(q.z()) - prim.half_m.z();
      const float out = std::sqrt(std::max(dr, 0.f) * std::max(dr, 0.f) + std::max(dz, 0.f) * std::max(dz, 0.f));
      return out + std::min(std::max(dr, dz), 0.f);
    }
    case Kind::kSphere:
      return q.norm() - prim.half_m.x();
    case Kind::kMesh:
      break;
  }
  return std::numeric_limits<float>::quiet_NaN();  // meshes take the double path
}

double LinkDistance::signed_distance(const Eigen::Vector3d& p_L) const {
  double best = std::numeric_limits<double>::infinity();
  const Eigen::Vector3f pf = p_L.cast<float>();
  for (const Prim& prim : prims_) {
    // A shape cannot be closer than its bounding box; skip the expensive ones that cannot win.
    const double box_gap = static_cast<double>(prim.bounds_L.exteriorDistance(pf)) - 1e-5;
    if (box_gap >= best) continue;
    best = std::min(best, shape_signed_distance(shapes_[static_cast<std::size_t>(prim.shape)], p_L));
  }
  return best;
}

bool LinkDistance::within(const Eigen::Vector3f& p_L, float threshold_m) const {
  for (const Prim& prim : prims_) {
    if (prim.bounds_L.exteriorDistance(p_L) > threshold_m) continue;
    if (prim.kind == Kind::kMesh) {
      if (shape_signed_distance(shapes_[static_cast<std::size_t>(prim.shape)], p_L.cast<double>()) <= threshold_m)
        return true;
    } else if (prim_distance(prim, p_L) <= threshold_m) {
      return true;
    }
  }
  return false;
}

DistanceGrid::DistanceGrid(const std::vector<CollisionShape>& shapes_L, double voxel_m, double margin_m) {
  voxel_ = static_cast<float>(voxel_m);
  inv_voxel_ = static_cast<float>(1.0 / voxel_m);
  // The byte unit s/8 and float rounding of the query point: shave 1e-5 m off every value.
  unit_ = static_cast<float>(voxel_m / 8.0);
  Eigen::AlignedBox3d bounds;
  bounds.setEmpty();
  for (const auto& s : shapes_L) bounds.extend(shape_bounds(s));
  if (bounds.isEmpty()) return;
  // Lattice-aligned box: whole voxels covering bounds grown by the margin (and one voxel more,
  // so the occupied voxels never touch the box's faces).
  const Eigen::Vector3i lo = ((bounds.min().array() - margin_m) / voxel_m).floor().cast<int>() - 1;
  const Eigen::Vector3i hi = ((bounds.max().array() + margin_m) / voxel_m).ceil().cast<int>() + 1;
  dims_ = hi - lo;
  const Eigen::Vector3d origin = voxel_m * lo.cast<double>();
  origin_ = origin.cast<float>();
  extent_ = dims_.cast<float>();
  // The margin actually guaranteed: from the bounds to the box's faces, minus float rounding.
  const double true_margin =
      std::min((bounds.min() - origin).minCoeff(), (origin + voxel_m * dims_.cast<double>() - bounds.max()).minCoeff());
  margin_ = static_cast<float>(true_margin) - 1e-5f;
  OccupancyGrid raster(origin, voxel_m, dims_);
  for (const auto& s : shapes_L) voxelize_shape(s, raster);
  const std::size_t n = static_cast<std::size_t>(dims_.prod());
  std::vector<std::uint8_t> site(n, 0);
  for (int z = 0; z < dims_.z(); ++z)
    for (int y = 0; y < dims_.y(); ++y)
      for (int x = 0; x < dims_.x(); ++x)
        if (raster.occupied(x, y, z)) {
          site[static_cast<std::size_t>(raster.linear_index(x, y, z))] = 1;
          centres_.push_back(raster.voxel_center_W(x, y, z).cast<float>());
        }
  edt::dilate26(site, dims_.x(), dims_.y(), dims_.z());
  std::vector<std::int32_t> d2;
  edt::squared_distance_3d(site, dims_.x(), dims_.y(), dims_.z(), d2);
  values_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double d = voxel_m * std::sqrt(static_cast<double>(d2[i])) - 1e-5;
    values_[i] = static_cast<std::uint8_t>(std::min(255.0, std::max(0.0, std::floor(d / (voxel_m / 8.0)))));
  }
}

}  // namespace porter::planner
