#include "porter/core/scene_voxelizer.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "geometry_internal.hpp"

namespace porter {
namespace {

/// Inclusive voxel index range [lo, hi] of the voxels whose closed boxes may touch `box`,
/// clamped to the grid; empty (lo > hi on some axis) when the box misses the grid.
struct IndexRange {
  Eigen::Vector3i lo, hi;
  bool empty() const { return (lo.array() > hi.array()).any(); }
};

IndexRange voxel_range(const OccupancyGrid& grid, const Eigen::AlignedBox3d& box) {
  IndexRange r;
  if (box.isEmpty()) {
    r.lo = Eigen::Vector3i::Zero();
    r.hi = Eigen::Vector3i::Constant(-1);
    return r;
  }
  // One extra voxel on each side (rounding at voxel faces); the exact test decides.
  r.lo = (grid.world_to_index(box.min()).array() - 1).max(0);
  r.hi = (grid.world_to_index(box.max()).array() + 1).min(grid.dims().array() - 1);
  return r;
}

/// A primitive with volume: its faces never occupy the voxel beyond them. A flat one (a box
/// with a zero side) is all face and keeps closed-box semantics, or a sheet lying on a voxel face
/// would vanish.
bool solid_primitive(const CollisionShape& shape) {
  const Eigen::AlignedBox3d b = shape_bounds(shape);
  return !b.isEmpty() && (b.sizes().array() > 4.0 * kVoxelFaceTolerance_m).all();
}

void voxelize_primitive(const CollisionShape& shape, OccupancyGrid& grid, const IndexRange& r) {
  const bool solid = solid_primitive(shape);
  for (int iz = r.lo.z(); iz <= r.hi.z(); ++iz)
    for (int iy = r.lo.y(); iy <= r.hi.y(); ++iy)
      for (int ix = r.lo.x(); ix <= r.hi.x(); ++ix)
        if (!grid.occupied(ix, iy, iz) &&
            shape_intersects_aabb(shape, solid ? voxelization_box_W(grid, ix, iy, iz) : grid.voxel_box_W(ix, iy, iz)))
          grid.set(ix, iy, iz);
}

/// Closed meshes are solids: a voxel is occupied when a triangle reaches into it, or when it is
/// inside the mesh. Voxels whose closed boxes no triangle meets come in runs along x that are
/// wholly inside or outside (one winding-number test per run); a voxel that a triangle only
/// touches on its boundary is wholly inside or outside too (one test at its centre). Open meshes
/// are surfaces with no inside: closed-box semantics.
void voxelize_mesh(const CollisionShape& shape, OccupancyGrid& grid, const IndexRange& r) {
  const TriangleMesh mesh = shape_to_mesh(shape);  // in the grid's frame
  const Eigen::Vector3i n = r.hi - r.lo + Eigen::Vector3i::Ones();
  enum : unsigned char { kClear = 0, kTouched = 1, kReached = 2 };
  std::vector<unsigned char> surface(static_cast<std::size_t>(n.x()) * n.y() * n.z(), kClear);
  auto local = [&](int ix, int iy, int iz) {
    return static_cast<std::size_t>(ix - r.lo.x()) +
           static_cast<std::size_t>(n.x()) * ((iy - r.lo.y()) + static_cast<std::size_t>(n.y()) * (iz - r.lo.z()));
  };
  const bool solid = mesh.closed;
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d& a = mesh.vertices_m[t[0]];
    const Eigen::Vector3d& b = mesh.vertices_m[t[1]];
    const Eigen::Vector3d& c = mesh.vertices_m[t[2]];
    const Eigen::AlignedBox3d tb(a.cwiseMin(b).cwiseMin(c), a.cwiseMax(b).cwiseMax(c));
    IndexRange tr = voxel_range(grid, tb);
    tr.lo = tr.lo.cwiseMax(r.lo);
    tr.hi = tr.hi.cwiseMin(r.hi);
    for (int iz = tr.lo.z(); iz <= tr.hi.z(); ++iz)
      for (int iy = tr.lo.y(); iy <= tr.hi.y(); ++iy)
        for (int ix = tr.lo.x(); ix <= tr.hi.x(); ++ix) {
          unsigned char& s = surface[local(ix, iy, iz)];
          if (s == kReached) continue;
          if (s == kClear) {
            if (!triangle_intersects_aabb(a, b, c, grid.voxel_box_W(ix, iy, iz))) continue;
            s = kTouched;
          }
          if (!solid || triangle_intersects_aabb(a, b, c, voxelization_box_W(grid, ix, iy, iz))) {
            s = kReached;
            grid.set(ix, iy, iz);
          }
        }
  }
  if (!solid) return;
  const Eigen::AlignedBox3d mesh_bounds = mesh.bounds();
  auto inside = [&](const Eigen::Vector3d& p) { return mesh_bounds.contains(p) && detail::mesh_winding_inside(mesh, p); };
  for (int iz = r.lo.z(); iz <= r.hi.z(); ++iz)
    for (int iy = r.lo.y(); iy <= r.hi.y(); ++iy) {
      int ix = r.lo.x();
      while (ix <= r.hi.x()) {
        const unsigned char s = surface[local(ix, iy, iz)];
        if (s != kClear) {
          if (s == kTouched && inside(grid.voxel_center_W(ix, iy, iz))) grid.set(ix, iy, iz);
          ++ix;
          continue;
        }
        int end = ix;
        while (end + 1 <= r.hi.x() && surface[local(end + 1, iy, iz)] == kClear) ++end;
        if (inside(grid.voxel_center_W(ix, iy, iz)))
          for (int k = ix; k <= end; ++k) grid.set(k, iy, iz);
        ix = end + 1;
      }
    }
}

}  // namespace

Eigen::AlignedBox3d voxelization_box_W(const OccupancyGrid& grid, int ix, int iy, int iz) {
  const Eigen::AlignedBox3d b = grid.voxel_box_W(ix, iy, iz);
  const Eigen::Vector3d t = Eigen::Vector3d::Constant(kVoxelFaceTolerance_m);
  return Eigen::AlignedBox3d(b.min() + t, b.max() - t);
}

void voxelize_shape(const CollisionShape& shape_W, OccupancyGrid& grid) {
  if (grid.num_voxels() == 0) return;
  const IndexRange r = voxel_range(grid, shape_bounds(shape_W));
  if (r.empty()) return;
  if (const auto* m = std::get_if<MeshShape>(&shape_W.geometry)) {
    if (m->mesh) voxelize_mesh(shape_W, grid, r);
    return;
  }
  voxelize_primitive(shape_W, grid, r);
}

OccupancyGrid voxelize(const Scene& scene) {
  OccupancyGrid grid = OccupancyGrid::covering(scene.bounds_W, scene.resolution_m);
  for (const auto& obstacle : scene.obstacles) voxelize_shape(obstacle, grid);
  return grid;
}

}  // namespace porter
