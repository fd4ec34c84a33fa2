#pragma once
// First-hit ray casting against a scene's exact obstacles (for the LiDAR simulator and tests).
//
// Obstacles are solids: a ray starting inside one hits at distance 0. The ground (z = 0) is not
// an obstacle and is not hit. Each obstacle's world bounds are computed once at construction and
// used as a slab-test prefilter; shapes are then tested only while they could beat the best hit.
//
// Thread-safety: cast() is const and reentrant; one caster may serve many threads.

#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "porter/core/geometry.hpp"
#include "porter/core/scene.hpp"

namespace porter {

struct SceneRayHit {
  double distance_m = -1.0;  ///< along the ray, in [0, max_range]; negative when nothing was hit
  int obstacle_index = -1;   ///< into Scene::obstacles; -1 when nothing was hit
  bool hit() const { return obstacle_index >= 0; }
};

class SceneRayCaster {
 public:
  /// Copies the obstacles (meshes are shared, not copied).
  explicit SceneRayCaster(const Scene& scene);
  explicit SceneRayCaster(std::vector<CollisionShape> obstacles_W);

  /// unit_dir_W must have unit length. A negative or NaN max_range_m never hits.
  SceneRayHit cast(const Eigen::Vector3d& origin_W, const Eigen::Vector3d& unit_dir_W,
                   double max_range_m) const;

  std::size_t size() const { return obstacles_.size(); }

 private:
  std::vector<CollisionShape> obstacles_;
  std::vector<Eigen::AlignedBox3d> bounds_W_;
};

}  // namespace porter
