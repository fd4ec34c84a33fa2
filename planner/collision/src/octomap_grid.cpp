#include "porter/planner/collision/octomap_grid.hpp"

#include <octomap/OcTree.h>

#include <algorithm>
#include <cmath>

namespace porter::planner {

OccupancyGrid occupancy_from_octomap(const octomap::OcTree& tree, const Eigen::AlignedBox3d& bounds_W) {
  const double res = tree.getResolution();
  Eigen::AlignedBox3d bounds = bounds_W;
  if (bounds.isEmpty()) {
    double x0, y0, z0, x1, y1, z1;
    tree.getMetricMin(x0, y0, z0);
    tree.getMetricMax(x1, y1, z1);
    bounds = Eigen::AlignedBox3d(Eigen::Vector3d(x0, y0, z0), Eigen::Vector3d(x1, y1, z1));
  }
  // Snap outwards to the tree's voxel boundaries (multiples of res).
  const Eigen::Vector3d lo = (bounds.min() / res).array().floor() * res;
  const Eigen::Vector3d hi = (bounds.max() / res).array().ceil() * res;
  OccupancyGrid grid(lo, res, ((hi - lo) / res).array().round().cast<int>().max(1).matrix());
  mark_octomap_leaves(tree, true, grid);
  return grid;
}

void mark_octomap_leaves(const octomap::OcTree& tree, bool occupied, OccupancyGrid& grid) {
  const double res = grid.resolution_m();
  const Eigen::Vector3i& n = grid.dims();
  const Eigen::Vector3d& lo = grid.origin_W();
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it) {
    if (tree.isNodeOccupied(*it) != occupied) continue;
    const double half = 0.5 * it.getSize();
    const Eigen::Vector3d c(it.getX(), it.getY(), it.getZ());
    // Voxels whose centres lie inside the leaf's cube (the cube is a union of whole voxels).
    Eigen::Vector3i a, b;
    for (int k = 0; k < 3; ++k) {
      a[k] = std::max(0, static_cast<int>(std::ceil((c[k] - half - lo[k]) / res - 0.5)));
      b[k] = std::min(n[k] - 1, static_cast<int>(std::floor((c[k] + half - lo[k]) / res - 0.5)));
    }
    for (int z = a.z(); z <= b.z(); ++z)
      for (int y = a.y(); y <= b.y(); ++y)
        for (int x = a.x(); x <= b.x(); ++x) grid.set(x, y, z);
  }
}

}  // namespace porter::planner
