#pragma once
// Porter shapes as FCL 0.7 objects (test-support library; independent of the kernel checker).
//   - shape_to_fcl: primitives stay primitives (exact), meshes become OBBRSS BVHs;
//   - mesh_to_fcl:  any shape triangulated (porter::shape_to_mesh), for "mesh-level" FCL;
//   - FclWorld:     a robot's links as FCL meshes checked per configuration against either a
//                   scene's exact obstacles (meshes in a dynamic AABB tree) or an occupancy
//                   grid (an fcl::OcTree of its occupied voxels: the map the kernels see), plus
//                   the non-allowed link pairs: the FCL yardsticks of tests/bench/bench_collision.cpp.

#include <fcl/fcl.h>

#include <memory>
#include <vector>

#include "porter/core/geometry.hpp"
#include "porter/core/occupancy_grid.hpp"
#include "porter/core/robot_model.hpp"
#include "porter/core/types.hpp"

namespace porter::test {

std::shared_ptr<fcl::CollisionGeometryd> shape_to_fcl(const CollisionShape& shape);
std::shared_ptr<fcl::CollisionGeometryd> mesh_to_fcl(const TriangleMesh& mesh);

class FclWorld {
 public:
  FclWorld(const RobotModel& model, const std::vector<CollisionShape>& obstacles_W);
  /// Obstacles = the grid's occupied voxels, as an octomap::OcTree at the grid's resolution.
  FclWorld(const RobotModel& model, const OccupancyGrid& occupancy_W);
  /// Whole-body check with mesh-level FCL: any link against any obstacle, any non-allowed pair.
  /// (The ground and the map bounds are not modelled: obstacles only.)
  bool in_collision(const RobotConfiguration& config);

 private:
  RobotModel model_;
  std::vector<std::unique_ptr<fcl::CollisionObjectd>> obstacles_;
  fcl::DynamicAABBTreeCollisionManagerd manager_;
  std::vector<std::unique_ptr<fcl::CollisionObjectd>> links_;  ///< one merged mesh per link (may be null)
  std::unique_ptr<fcl::CollisionObjectd> octree_;              ///< set by the grid constructor
  void build_links();
};

}  // namespace porter::test
