#pragma once
// Exact voxelization of obstacles into an OccupancyGrid: a voxel is occupied when its closed
// box intersects an obstacle (shape_intersects_aabb semantics, so touching counts).
//
// Speed: each shape only visits the voxels of its bounding box. Primitives run the exact
// shape/box test per voxel there (cylinders first decide from the centre's signed distance).
// Meshes are rasterized triangle by triangle (exact triangle/box test over each triangle's
// bounds), and for a closed mesh the voxels between surface voxels along each x row are filled
// with one winding-number test per run. The result equals testing every voxel with
// shape_intersects_aabb (checked in tests/core/test_scene_voxelizer.cpp).
//
// Frames: shapes are in the grid's frame (W for scenes). Thread-safety: reentrant; the grid
// being written must not be shared.

#include "porter/core/geometry.hpp"
#include "porter/core/occupancy_grid.hpp"
#include "porter/core/scene.hpp"

namespace porter {

/// Sets every voxel of `grid` that the shape intersects (never clears one).
void voxelize_shape(const CollisionShape& shape_W, OccupancyGrid& grid);

/// OccupancyGrid::covering(scene.bounds_W, scene.resolution_m) with every obstacle voxelized.
OccupancyGrid voxelize(const Scene& scene);

}  // namespace porter
