#pragma once
// Exact voxelization of obstacles into an OccupancyGrid: a voxel is occupied when a solid
// obstacle reaches into it, i.e. intersects its box shrunk by kVoxelFaceTolerance_m on every
// side (voxelization_box_W). Solids are primitives with volume and closed meshes; surfaces (open
// meshes, flat boxes) occupy every voxel whose closed box they touch. An obstacle face that lies on a voxel face does not occupy the voxel
// beyond it: with closed boxes every opening aligned with the grid (a door, the bridge hole)
// would lose one voxel on each side, 10 cm of a 1.1 m opening at 5 cm. An obstacle reaching less
// than 1 um into a voxel is ignored there; the robot's checks treat occupied boxes as closed, so
// touching an obstacle's face still counts as contact.
//
// Speed: each shape only visits the voxels of its bounding box. Primitives run the exact
// shape/box test per voxel there.
// Meshes are rasterized triangle by triangle (exact triangle/box test over each triangle's
// bounds), and for a closed mesh the voxels between surface voxels along each x row are filled
// with one winding-number test per run. The result equals testing every voxel's
// voxelization_box_W (solids) or closed box (surfaces) with shape_intersects_aabb, up to
// voxels a closed mesh reaches into by less than the tolerance (checked in
// tests/core/test_scene_voxelizer.cpp).
//
// Frames: shapes are in the grid's frame (W for scenes). Thread-safety: reentrant; the grid
// being written must not be shared.

#include "porter/core/geometry.hpp"
#include "porter/core/occupancy_grid.hpp"
#include "porter/core/scene.hpp"

namespace porter {

/// How far inside its faces a voxel's test box lies (m).
constexpr double kVoxelFaceTolerance_m = 1e-6;

/// The box an obstacle must meet to occupy voxel (ix, iy, iz): its box shrunk by
/// kVoxelFaceTolerance_m on every side.
Eigen::AlignedBox3d voxelization_box_W(const OccupancyGrid& grid, int ix, int iy, int iz);

/// Sets every voxel of `grid` that the shape reaches into (never clears one).
void voxelize_shape(const CollisionShape& shape_W, OccupancyGrid& grid);

/// OccupancyGrid::covering(scene.bounds_W, scene.resolution_m) with every obstacle voxelized.
OccupancyGrid voxelize(const Scene& scene);

}  // namespace porter
