#pragma once
// OctoMap tree -> OccupancyGrid, for KernelCollisionChecker::set_map(). In the separate target
// porter::collision_octomap so the kernel library does not depend on OctoMap.
//
// The grid's voxels are the tree's voxels at its finest resolution (OctoMap voxel k covers
// [k res, (k + 1) res) on each axis, so z = 0 is a voxel boundary as the map kernel requires).
// A voxel is occupied when it lies inside an occupied leaf (tree->isNodeOccupied; pruned inner
// leaves mark every voxel they cover). Unknown space is free: the mapper decides what it marks.
//
// Frames and units: the tree's frame is W; metres.
// Thread-safety: reentrant; the tree is only read.

#include <Eigen/Geometry>

#include "porter/core/occupancy_grid.hpp"

namespace octomap {
class OcTree;
}

namespace porter::planner {

/// The grid over `bounds_W` (grown outwards to whole tree voxels) with the tree's occupied
/// voxels. An empty bounds box uses the tree's metric bounding box.
OccupancyGrid occupancy_from_octomap(const octomap::OcTree& tree, const Eigen::AlignedBox3d& bounds_W);

/// Sets, on `grid` (its own origin, resolution and size; the tree's resolution must be the
/// grid's), every voxel whose centre lies inside a leaf of the tree that is occupied
/// (`occupied` = true) or known free (`occupied` = false). Leaves may span several voxels;
/// voxels outside the grid are skipped.
void mark_octomap_leaves(const octomap::OcTree& tree, bool occupied, OccupancyGrid& grid);

}  // namespace porter::planner
