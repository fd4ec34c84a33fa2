#include "porter/core/scene_ray_cast.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace porter {
namespace {

/// Entry distance of the ray into the box (0 when it starts inside), or +inf on a miss.
double slab_entry(const Eigen::Vector3d& o, const Eigen::Vector3d& inv_d, const Eigen::AlignedBox3d& box) {
  double t_enter = 0.0, t_exit = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 3; ++i) {
    double t1 = (box.min()[i] - o[i]) * inv_d[i];
    double t2 = (box.max()[i] - o[i]) * inv_d[i];
    if (std::isnan(t1) || std::isnan(t2)) {  // direction component 0 and origin on a face plane
      if (o[i] < box.min()[i] || o[i] > box.max()[i]) return std::numeric_limits<double>::infinity();
      continue;
    }
    if (t1 > t2) std::swap(t1, t2);
    t_enter = std::max(t_enter, t1);
    t_exit = std::min(t_exit, t2);
  }
  return t_enter <= t_exit ? t_enter : std::numeric_limits<double>::infinity();
}

}  // namespace

SceneRayCaster::SceneRayCaster(const Scene& scene) : SceneRayCaster(scene.obstacles) {}

SceneRayCaster::SceneRayCaster(std::vector<CollisionShape> obstacles_W) : obstacles_(std::move(obstacles_W)) {
  bounds_W_.reserve(obstacles_.size());
  for (const auto& o : obstacles_) bounds_W_.push_back(shape_bounds(o));
}

SceneRayHit SceneRayCaster::cast(const Eigen::Vector3d& origin_W, const Eigen::Vector3d& unit_dir_W,
                                 double max_range_m) const {
  SceneRayHit best;
  if (!(max_range_m >= 0.0)) return best;
  const Eigen::Vector3d inv_d = unit_dir_W.cwiseInverse();
  double best_t = max_range_m;
  for (std::size_t i = 0; i < obstacles_.size(); ++i) {
    const double entry = slab_entry(origin_W, inv_d, bounds_W_[i]);
    if (entry > best_t) continue;
    const double t = shape_ray_cast(obstacles_[i], origin_W, unit_dir_W, best_t);
    if (t >= 0.0 && (!best.hit() || t < best_t)) {
      best_t = t;
      best.distance_m = t;
      best.obstacle_index = static_cast<int>(i);
    }
  }
  return best;
}

}  // namespace porter
