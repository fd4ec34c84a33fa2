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

/// A union of axis-aligned boxes rasterised on a uniform grid of cells (world frame): contains(p)
/// is true for every point of every added box (and for the rest of the cells they touch), false
/// for points whose cell no added box touches. covers(box) is true only when every cell the box
/// touches is marked, so that covers(b) implies contains(p) for every p in b.
class CellMask {
 public:
  CellMask() = default;
  /// Cells of edge cell_m over `bounds_W` (points outside it are never contained). cell_m > 0.
  CellMask(const Eigen::AlignedBox3d& bounds_W, double cell_m);
  bool empty() const { return bits_.empty(); }
  void add(const Eigen::AlignedBox3d& box_W);
  bool contains(const Eigen::Vector3d& p_W) const;
  bool covers(const Eigen::AlignedBox3d& box_W) const;
  /// Marked cells (for the benchmark's figures).
  std::int64_t count() const;

 private:
  /// Cell range of a box clipped to the grid; false when it misses the grid.
  bool range(const Eigen::AlignedBox3d& box_W, Eigen::Vector3i& lo, Eigen::Vector3i& hi) const;
  std::size_t index(int x, int y, int z) const {
    return static_cast<std::size_t>(x) + static_cast<std::size_t>(dims_.x()) *
                                             (static_cast<std::size_t>(y) + static_cast<std::size_t>(dims_.y()) * z);
  }
  Eigen::AlignedBox3d bounds_;
  double cell_m_ = 1.0;
  Eigen::Vector3i dims_ = Eigen::Vector3i::Zero();
  std::vector<std::uint8_t> bits_;
};

/// The map's obstacle points whose voxel centre lies in region_W.
std::vector<ObstaclePoint> collect_obstacle_points(const OccupancyGrid& map_W,
                                                   const Eigen::AlignedBox3d& region_W,
                                                   const ObstaclePointSettings& settings);

/// The same, keeping only points that `keep` contains (null: all); the result is the subsequence
/// of the unmasked result that `keep` contains, in the same order. keys_out (optional) receives one
/// key per point, increasing along the result: the voxel's linear index for a map point,
/// num_voxels + the column's index (i + nx j) for a ground point. A point's key does not depend on
/// the mask, so two selections from one map can be matched point by point.
std::vector<ObstaclePoint> collect_obstacle_points(const OccupancyGrid& map_W,
                                                   const Eigen::AlignedBox3d& region_W,
                                                   const ObstaclePointSettings& settings, const CellMask* keep,
                                                   std::vector<std::uint64_t>* keys_out);

}  // namespace porter::backend
