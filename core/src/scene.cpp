#include "porter/core/scene.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace porter {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// 2D distance from the origin-centred rectangle of half extents h to q (0 inside).
double rectangle_distance(const Eigen::Vector2d& q, const Eigen::Vector2d& h) {
  return (q.cwiseAbs() - h).cwiseMax(0.0).norm();
}

/// Distance in the plane z = 0 from p to the union of the triangles projected onto it.
double projected_mesh_distance(const TriangleMesh& m, const Eigen::Vector2d& p) {
  double best = std::numeric_limits<double>::infinity();
  const Eigen::Vector3d p3(p.x(), p.y(), 0.0);
  auto flat = [](const Eigen::Vector3d& v) { return Eigen::Vector3d(v.x(), v.y(), 0.0); };
  for (const auto& t : m.triangles) {
    const Eigen::Vector3d q = closest_point_on_triangle(p3, flat(m.vertices_m[t[0]]), flat(m.vertices_m[t[1]]),
                                                        flat(m.vertices_m[t[2]]));
    best = std::min(best, (q - p3).norm());
    if (best == 0.0) break;
  }
  return best;
}

/// True when the shape's local z axis is vertical, so its footprint is a 2D section.
bool vertical_axis(const Eigen::Isometry3d& T) { return std::abs(std::abs(T.linear()(2, 2)) - 1.0) <= 1e-12; }

/// The shape's frame seen from above: p in the shape's local xy plane.
Eigen::Vector2d local_xy(const Eigen::Isometry3d& T, const Eigen::Vector2d& p) {
  const Eigen::Vector3d d(p.x() - T.translation().x(), p.y() - T.translation().y(), 0.0);
  return (T.linear().transpose() * d).head<2>();
}

}  // namespace

double footprint_distance(const CollisionShape& obstacle_W, const Eigen::Vector2d& p_xy_W) {
  const Eigen::Isometry3d& T = obstacle_W.T_parent_shape;
  if (const auto* box = std::get_if<Box>(&obstacle_W.geometry)) {
    if (vertical_axis(T)) return rectangle_distance(local_xy(T, p_xy_W), 0.5 * box->size_m.head<2>());
    return projected_mesh_distance(shape_to_mesh(obstacle_W), p_xy_W);
  }
  if (const auto* s = std::get_if<Sphere>(&obstacle_W.geometry))
    return std::max(0.0, (p_xy_W - T.translation().head<2>()).norm() - s->radius_m);
  if (const auto* c = std::get_if<Cylinder>(&obstacle_W.geometry)) {
    if (vertical_axis(T)) return std::max(0.0, local_xy(T, p_xy_W).norm() - c->radius_m);
    constexpr int kSegments = 64;
    CollisionShape prism = obstacle_W;
    prism.geometry = Cylinder{c->radius_m / std::cos(kPi / kSegments), c->length_m};
    return projected_mesh_distance(shape_to_mesh(prism, kSegments), p_xy_W);
  }
  const auto& m = std::get<MeshShape>(obstacle_W.geometry);
  if (!m.mesh) return std::numeric_limits<double>::infinity();
  return projected_mesh_distance(shape_to_mesh(obstacle_W), p_xy_W);
}

std::size_t footprint_cost(const CollisionShape& obstacle_W) {
  const Eigen::Isometry3d& T = obstacle_W.T_parent_shape;
  if (std::holds_alternative<Box>(obstacle_W.geometry)) {
    return vertical_axis(T) ? 1 : std::max<std::size_t>(1, shape_to_mesh(obstacle_W).triangles.size());
  }
  if (std::holds_alternative<Sphere>(obstacle_W.geometry)) return 1;
  if (const auto* c = std::get_if<Cylinder>(&obstacle_W.geometry)) {
    if (vertical_axis(T)) return 1;
    constexpr int kSegments = 64;  // as footprint_distance
    CollisionShape prism = obstacle_W;
    prism.geometry = Cylinder{c->radius_m / std::cos(kPi / kSegments), c->length_m};
    return std::max<std::size_t>(1, shape_to_mesh(prism, kSegments).triangles.size());
  }
  const auto& m = std::get<MeshShape>(obstacle_W.geometry);
  return m.mesh ? std::max<std::size_t>(1, m.mesh->triangles.size()) : 1;
}

}  // namespace porter
