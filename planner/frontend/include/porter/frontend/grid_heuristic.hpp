#pragma once
// The Hybrid A* obstacle heuristic: shortest 8-connected grid distance in the plane from a cell
// to the goal, around the obstacles that any base pose would hit.
//
// Relaxation (why it is a valid pruning test): the base footprint contains a disc of radius
// r_in at height z_probe for every yaw (computed from the model's base geometry by
// base_inscribed_disc()). A grid cell is blocked when, for every base position inside it, that
// disc overlaps an occupied voxel of the z_probe layer or reaches outside the map's horizontal
// bounds. A base pose in a blocked cell is therefore in collision for any checker that honours
// the CollisionChecker contract, and a goal cell unreachable from the start cell means that no
// base path exists at all.
//
// Units: metres, world frame W. Thread-safety: build()/set_goal() need exclusive access;
// const queries may run concurrently.

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "porter/core/occupancy_grid.hpp"
#include "porter/core/robot_model.hpp"

namespace porter::frontend {

/// A horizontal disc in the base frame B that the base geometry contains at every yaw.
struct InscribedDisc {
  double radius_m = 0.0;  ///< 0 when no disc around B's origin is inside the base geometry
  double z_m = 0.0;       ///< height of the disc in B
};

/// Largest disc centred on B's z axis (radius resolution 5 mm) inside link 0's shapes, over
/// heights sampled through link 0's bounds.
InscribedDisc base_inscribed_disc(const RobotModel& model);

class GridHeuristic {
 public:
  /// Rebuilds the blocked-cell grid for `occupancy_W` at `resolution_m` (covers the map's
  /// horizontal bounds). Clears the goal.
  void build(const OccupancyGrid& occupancy_W, const InscribedDisc& disc, double resolution_m);

  /// Runs Dijkstra from the cell of (x, y). False when the point is outside the grid.
  bool set_goal(double x_m, double y_m);

  bool built() const { return nx_ > 0; }
  /// True when (x, y) lies outside the grid or in a blocked cell.
  bool blocked(double x_m, double y_m) const;
  /// Grid distance (m) from the cell of (x, y) to the goal cell minus one cell diagonal (so that
  /// the offset of the points inside their cells is covered); +inf when unreachable or outside.
  double distance(double x_m, double y_m) const;

  double resolution_m() const { return res_; }
  std::int64_t blocked_count() const;

 private:
  int cell_index(double x_m, double y_m) const;  // -1 outside

  double res_ = 0.1;
  Eigen::Vector2d origin_ = Eigen::Vector2d::Zero();
  int nx_ = 0, ny_ = 0;
  std::vector<std::uint8_t> blocked_;
  std::vector<float> dist_;
};

}  // namespace porter::frontend
