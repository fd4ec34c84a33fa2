#pragma once
// Euclidean signed distance field (ESDF) of an occupancy grid, the map representation of the
// sphere baseline (REMANI / TOPAY query an ESDF at points on the robot; algorithms.md §2.2).
//
// Values live at voxel centres: outside obstacles, the distance from the centre to the nearest
// occupied voxel's centre minus half a voxel (the distance to that voxel's face along the axis
// joining them); inside, minus (the distance to the nearest free voxel's centre minus half a
// voxel). Computed exactly on the voxel lattice by the separable squared Euclidean distance
// transform (Felzenszwalb and Huttenlocher, one lower-envelope pass per axis), then interpolated
// with the C^1 B-spline of sdf_grid.hpp (its gradient is exact for the interpolant). Distances
// above max_distance_m are clamped to it.
//
// The ground (z = 0) and the outside of the map are not obstacles here: the sphere checker
// handles them separately (collision_checker.hpp contract).
//
// Frames and units: world W, metres. Thread-safety: immutable after build(); queries reentrant.

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "porter/backend/sdf_grid.hpp"
#include "porter/core/occupancy_grid.hpp"

namespace porter::baselines {

class DistanceField {
 public:
  DistanceField() = default;

  /// ESDF of the voxels of `occupancy_W` inside `region_W` (the whole grid when empty), clamped to
  /// +-max_distance_m. Obstacles outside the region are ignored: callers pass a region that covers
  /// the robot's reach plus max_distance_m.
  static DistanceField build(const OccupancyGrid& occupancy_W, const Eigen::AlignedBox3d& region_W,
                             double max_distance_m);

  bool empty() const { return grid_.empty(); }
  /// Signed distance at p_W (m) and its gradient (when non-null); p outside the field's box is
  /// clamped into it.
  double distance(const Eigen::Vector3d& p_W, Eigen::Vector3d* grad_W = nullptr) const {
    return grid_.smooth(p_W, grad_W);
  }
  const backend::SdfGrid& grid() const { return grid_; }
  double max_distance_m() const { return max_distance_m_; }

 private:
  backend::SdfGrid grid_;
  double max_distance_m_ = 0.0;
};

/// Squared Euclidean distance transform of a 3D lattice in place: on input 0 at sites and +inf
/// elsewhere; on output the squared distance (in cells^2) to the nearest site. Exposed for tests.
void squared_distance_transform(std::vector<double>& f, const Eigen::Vector3i& dims);

}  // namespace porter::baselines
