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
  // One extra voxel on each side: a shape exactly on a voxel face touches both neighbours, and
  // the exact test decides.
  r.lo = (grid.world_to_index(box.min()).array() - 1).max(0);
  r.hi = (grid.world_to_index(box.max()).array() + 1).min(grid.dims().array() - 1);
  return r;
}

void voxelize_primitive(const CollisionShape& shape, OccupancyGrid& grid, const IndexRange& r) {
  for (int iz = r.lo.z(); iz <= r.hi.z(); ++iz)
    for (int iy = r.lo.y(); iy <= r.hi.y(); ++iy)
      for (int ix = r.lo.x(); ix <= r.hi.x(); ++ix)
        if (!grid.occupied(ix, iy, iz) && shape_intersects_aabb(shape, grid.voxel_box_W(ix, iy, iz)))
          grid.set(ix, iy, iz);
}

void voxelize_mesh(const CollisionShape& shape, OccupancyGrid& grid, const IndexRange& r) {
  const TriangleMesh mesh = shape_to_mesh(shape);  // in the grid's frame
  const Eigen::Vector3i n = r.hi - r.lo + Eigen::Vector3i::Ones();
  std::vector<unsigned char> surface(static_cast<std::size_t>(n.x()) * n.y() * n.z(), 0);
  auto local = [&](int ix, int iy, int iz) {
    return static_cast<std::size_t>(ix - r.lo.x()) +
           static_cast<std::size_t>(n.x()) * ((iy - r.lo.y()) + static_cast<std::size_t>(n.y()) * (iz - r.lo.z()));
  };
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
          if (!s && triangle_intersects_aabb(a, b, c, grid.voxel_box_W(ix, iy, iz))) {
            s = 1;
            grid.set(ix, iy, iz);
          }
        }
  }
  if (!mesh.closed) return;
  // Voxels between surface voxels along a row form a box that no triangle meets, so the whole
  // run is inside or outside; one winding-number test at its first centre decides.
  const Eigen::AlignedBox3d mesh_bounds = mesh.bounds();
  for (int iz = r.lo.z(); iz <= r.hi.z(); ++iz)
    for (int iy = r.lo.y(); iy <= r.hi.y(); ++iy) {
      int ix = r.lo.x();
      while (ix <= r.hi.x()) {
        if (surface[local(ix, iy, iz)]) {
          ++ix;
          continue;
        }
        int end = ix;
        while (end + 1 <= r.hi.x() && !surface[local(end + 1, iy, iz)]) ++end;
        const Eigen::Vector3d p = grid.voxel_center_W(ix, iy, iz);
        if (mesh_bounds.contains(p) && detail::mesh_winding_inside(mesh, p))
          for (int k = ix; k <= end; ++k) grid.set(k, iy, iz);
        ix = end + 1;
      }
    }
}

}  // namespace

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
