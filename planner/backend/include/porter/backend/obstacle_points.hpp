#pragma once
// Obstacle points for the SVSDF safety penalty (paper eq. safety_penalty's x_obs): centres of the
// occupied voxels of the map that face free space (interior voxels are never the nearest obstacle
// to a link that is outside the obstacle), inside a region of interest, plus optional ground points.
//
// The ground (z = 0 in W) is not in the map (scene.hpp) but links must stay above it (collision
// contract, collision_checker.hpp). Ground points are a layer of voxel centres at z = -res/2 under
// the region, applying to every link but the base (whose wheels stand on it).
//
// Frames and units: world W, metres. Pure functions; thread-safe.

#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "porter/core/occupancy_grid.hpp"
#include "porter/core/types.hpp"

namespace porter::backend {

struct ObstaclePoint {
  Eigen::Vector3d p_W = Eigen::Vector3d::Zero();
  std::uint32_t links = (1u << kNumLinks) - 1;  ///< bit j: the point applies to link j
  bool ground = false;                           ///< a ground point (its own margin)
};

struct ObstaclePointSettings {
  /// Only voxels with a free 6-neighbour (neighbours outside the grid count as occupied).
  bool surface_only = true;
  /// Add the ground layer (for links 1..7).
  bool ground = true;
};

/// The map's obstacle points whose voxel centre lies in region_W.
std::vector<ObstaclePoint> collect_obstacle_points(const OccupancyGrid& map_W,
                                                   const Eigen::AlignedBox3d& region_W,
                                                   const ObstaclePointSettings& settings);

}  // namespace porter::backend
