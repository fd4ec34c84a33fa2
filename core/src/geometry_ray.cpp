// Ray casts against single shapes (geometry.hpp).
//
// Shapes are solids: a ray that starts inside a primitive, or inside a closed mesh, hits at
// distance 0. Open meshes are two-sided surfaces.

#include <algorithm>
#include <cmath>
#include <limits>

#include "geometry_internal.hpp"
#include "porter/core/geometry.hpp"

namespace porter {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kMiss = -1.0;

/// Slab test against [lo, hi]; returns the entry distance (0 when starting inside) or kMiss.
double ray_box(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Eigen::Vector3d& lo,
               const Eigen::Vector3d& hi) {
  double t_enter = -kInf, t_exit = kInf;
  for (int i = 0; i < 3; ++i) {
    if (d[i] == 0.0) {
      if (o[i] < lo[i] || o[i] > hi[i]) return kMiss;
      continue;
    }
    double t1 = (lo[i] - o[i]) / d[i], t2 = (hi[i] - o[i]) / d[i];
    if (t1 > t2) std::swap(t1, t2);
    t_enter = std::max(t_enter, t1);
    t_exit = std::min(t_exit, t2);
    if (t_enter > t_exit) return kMiss;
  }
  if (t_exit < 0.0) return kMiss;
  return std::max(t_enter, 0.0);
}

double ray_sphere(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double r) {
  const double c = o.squaredNorm() - r * r;
  if (c <= 0.0) return 0.0;
  const double b = o.dot(d);
  const double disc = b * b - c;
  if (disc < 0.0) return kMiss;
  const double t = -b - std::sqrt(disc);
  return t >= 0.0 ? t : kMiss;  // c > 0: both roots share a sign
}

double ray_cylinder(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double r, double length) {
  const double h = 0.5 * length;
  const double c = o.head<2>().squaredNorm() - r * r;
  if (c <= 0.0 && std::abs(o.z()) <= h) return 0.0;
  double best = kInf;
  // Side: the entry root of the infinite cylinder, kept when it lands between the caps. With
  // the origin outside the finite cylinder the first hit is this root or a cap.
  const double a = d.head<2>().squaredNorm();
  if (a > 0.0 && c > 0.0) {
    const double b = o.head<2>().dot(d.head<2>());
    const double disc = b * b - a * c;
    if (disc >= 0.0) {
      const double t = (-b - std::sqrt(disc)) / a;
      if (t >= 0.0 && std::abs(o.z() + t * d.z()) <= h) best = t;
    }
  }
  if (d.z() != 0.0) {
    for (const double zc : {-h, h}) {
      const double t = (zc - o.z()) / d.z();
      if (t >= 0.0 && t < best && (o.head<2>() + t * d.head<2>()).squaredNorm() <= r * r) best = t;
    }
  }
  return best < kInf ? best : kMiss;
}

/// Möller–Trumbore, two-sided; distance or kMiss.
double ray_triangle(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Eigen::Vector3d& a,
                    const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d e1 = b - a, e2 = c - a;
  const Eigen::Vector3d pvec = d.cross(e2);
  const double det = e1.dot(pvec);
  if (det == 0.0) return kMiss;  // parallel (or degenerate triangle)
  const double inv = 1.0 / det;
  const Eigen::Vector3d tvec = o - a;
  const double u = tvec.dot(pvec) * inv;
  if (u < 0.0 || u > 1.0) return kMiss;
  const Eigen::Vector3d qvec = tvec.cross(e1);
  const double v = d.dot(qvec) * inv;
  if (v < 0.0 || u + v > 1.0) return kMiss;
  const double t = e2.dot(qvec) * inv;
  return t >= 0.0 ? t : kMiss;
}

double ray_mesh(const TriangleMesh& mesh, const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                double max_range_m) {
  const Eigen::AlignedBox3d bounds = mesh.bounds();
  if (bounds.isEmpty()) return kMiss;
  const double t_box = ray_box(o, d, bounds.min(), bounds.max());
  if (t_box < 0.0 || t_box > max_range_m) return kMiss;
  if (mesh.closed && t_box == 0.0 && detail::mesh_winding_inside(mesh, o)) return 0.0;
  double best = kInf;
  for (const auto& tri : mesh.triangles) {
    const double t = ray_triangle(o, d, mesh.vertices_m[tri[0]], mesh.vertices_m[tri[1]],
                                  mesh.vertices_m[tri[2]]);
    if (t >= 0.0 && t < best) best = t;
  }
  return best < kInf ? best : kMiss;
}

}  // namespace

double shape_ray_cast(const CollisionShape& shape, const Eigen::Vector3d& origin_parent,
                      const Eigen::Vector3d& unit_dir_parent, double max_range_m) {
  if (!(max_range_m >= 0.0)) return kMiss;
  const Eigen::Vector3d o = detail::to_shape_frame(shape, origin_parent);
  const Eigen::Vector3d d = shape.T_parent_shape.linear().transpose() * unit_dir_parent;
  const double t = std::visit(
      detail::Overloaded{
          [&](const Box& b) { return ray_box(o, d, -0.5 * b.size_m, 0.5 * b.size_m); },
          [&](const Sphere& s) { return ray_sphere(o, d, s.radius_m); },
          [&](const Cylinder& c) { return ray_cylinder(o, d, c.radius_m, c.length_m); },
          [&](const MeshShape& m) { return m.mesh ? ray_mesh(*m.mesh, o, d, max_range_m) : kMiss; }},
      shape.geometry);
  return (t >= 0.0 && t <= max_range_m) ? t : kMiss;
}

}  // namespace porter
