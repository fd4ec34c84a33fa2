#pragma once
// A world the robot works in: exact obstacle geometry, the planning bounds and resolution, and
// the task (start, goal, payload). Read by the simulator, the planner CLI, the benchmarks and
// the validator. Built by load_scene() (scene_loader.hpp) from config/scenes/*.yaml; turned into
// voxels by voxelize() (scene_voxelizer.hpp) and ray-cast by SceneRayCaster (scene_ray_cast.hpp).
//
// Frames and units: everything is in the world frame W (z up, metres, radians). z = 0 is the
// ground the base drives on. The ground is NOT an obstacle: the planner keeps the links above
// it separately.
//
// Thread-safety: a value type (obstacle meshes are shared immutable data); the free function is
// reentrant.

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "porter/core/geometry.hpp"
#include "porter/core/types.hpp"

namespace porter {

struct Scene {
  std::string name;
  std::string description;
  std::string source_file;          ///< file it was loaded from ("" when built in code)
  Eigen::AlignedBox3d bounds_W;     ///< the planning volume; outside it counts as blocked
  double resolution_m = 0.05;       ///< voxel edge length for voxelize()
  RobotConfiguration start;
  RobotConfiguration goal;
  std::string payload_file;         ///< resolved path of the payload YAML ("" when none)
  std::uint64_t seed = 0;           ///< seed the random generators used
  std::map<std::string, double> parameters;  ///< parameter values used (defaults + overrides)
  /// Obstacles, each placed in W by its T_parent_shape (= T_W_shape). Names are unique within
  /// a loaded scene (a bridge yields "<name>.left_wall", "<name>.right_wall", "<name>.deck").
  std::vector<CollisionShape> obstacles;
};

/// Distance in the ground plane from the point p_xy_W to the obstacle's footprint (its
/// vertical projection onto z = 0); 0 when the point lies under, over or inside it.
/// Exact for boxes, spheres, vertical cylinders and meshes (the footprint of a mesh is the union
/// of its projected triangles). A cylinder whose axis is not vertical is approximated by a
/// circumscribed 64-gon prism, so the distance may be underestimated by at most 0.12 % of the
/// radius (never overestimated).
double footprint_distance(const CollisionShape& obstacle_W, const Eigen::Vector2d& p_xy_W);

/// The distance evaluations one footprint_distance call makes for this obstacle: 1 for a box or
/// cylinder with a vertical axis and for a sphere, else the triangles of the mesh it projects
/// (12 for a tilted box, 256 for a tilted cylinder's prism, the mesh's own). Builds no mesh for
/// a mesh obstacle; builds the tilted shape's mesh once to count it.
std::size_t footprint_cost(const CollisionShape& obstacle_W);

}  // namespace porter
