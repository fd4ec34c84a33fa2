// Bounds, distances and point containment for the exact collision geometry (geometry.hpp).
// Intersection with boxes lives in geometry_aabb.cpp, ray casts in geometry_ray.cpp and
// triangulation in geometry_mesh.cpp.

#include <algorithm>
#include <cmath>
#include <limits>

#include "geometry_internal.hpp"
#include "porter/core/geometry.hpp"

namespace porter {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kPi = 3.14159265358979323846;
/// Distance under which a point counts as lying on a mesh surface (open meshes, ties).
constexpr double kOnSurfaceTolerance_m = 1e-12;

Eigen::Vector3d closest_point_on_segment(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                         const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double len2 = ab.squaredNorm();
  if (len2 <= 0.0) return a;
  const double t = std::clamp((p - a).dot(ab) / len2, 0.0, 1.0);
  return a + t * ab;
}

}  // namespace

Eigen::AlignedBox3d TriangleMesh::bounds() const {
  Eigen::AlignedBox3d b;  // empty
  for (const auto& v : vertices_m) b.extend(v);
  return b;
}

Eigen::AlignedBox3d shape_bounds(const CollisionShape& shape, const Eigen::Isometry3d& T_frame_parent) {
  const Eigen::Isometry3d T = T_frame_parent * shape.T_parent_shape;
  const Eigen::Matrix3d R = T.linear();
  const Eigen::Vector3d t = T.translation();
  return std::visit(
      detail::Overloaded{
          [&](const Box& box) {
            const Eigen::Vector3d ext = R.cwiseAbs() * (0.5 * box.size_m);
            return Eigen::AlignedBox3d(t - ext, t + ext);
          },
          [&](const Sphere& s) {
            const Eigen::Vector3d ext = Eigen::Vector3d::Constant(s.radius_m);
            return Eigen::AlignedBox3d(t - ext, t + ext);
          },
          [&](const Cylinder& c) {
            // Per world axis i: half length times |u_i| plus the radius of the cap disc's
            // projection, r * sqrt(1 - u_i^2), u the cylinder axis.
            const Eigen::Vector3d u = R.col(2);
            Eigen::Vector3d ext;
            for (int i = 0; i < 3; ++i)
              ext[i] = 0.5 * c.length_m * std::abs(u[i]) +
                       c.radius_m * std::sqrt(std::max(0.0, 1.0 - u[i] * u[i]));
            return Eigen::AlignedBox3d(t - ext, t + ext);
          },
          [&](const MeshShape& m) {
            Eigen::AlignedBox3d b;
            if (m.mesh)
              for (const auto& v : m.mesh->vertices_m) b.extend(T * v);
            return b;
          }},
      shape.geometry);
}

double shape_max_distance(const CollisionShape& shape, const Eigen::Vector3d& center_parent) {
  const Eigen::Vector3d c = detail::to_shape_frame(shape, center_parent);
  return std::visit(
      detail::Overloaded{
          [&](const Box& box) { return (c.cwiseAbs() + 0.5 * box.size_m).norm(); },
          [&](const Sphere& s) { return c.norm() + s.radius_m; },
          [&](const Cylinder& cyl) {
            // The farthest point is on the rim of the farther cap, opposite the point radially.
            const double radial = c.head<2>().norm() + cyl.radius_m;
            const double axial = std::abs(c.z()) + 0.5 * cyl.length_m;
            return std::hypot(radial, axial);
          },
          [&](const MeshShape& m) {
            double d2 = 0.0;
            if (m.mesh)
              for (const auto& v : m.mesh->vertices_m) d2 = std::max(d2, (v - c).squaredNorm());
            return std::sqrt(d2);
          }},
      shape.geometry);
}

double shape_signed_distance(const CollisionShape& shape, const Eigen::Vector3d& p_parent) {
  const Eigen::Vector3d p = detail::to_shape_frame(shape, p_parent);
  return std::visit(
      detail::Overloaded{
          [&](const Box& box) {
            const Eigen::Vector3d q = p.cwiseAbs() - 0.5 * box.size_m;
            return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
          },
          [&](const Sphere& s) { return p.norm() - s.radius_m; },
          [&](const Cylinder& cyl) {
            const Eigen::Vector2d d(p.head<2>().norm() - cyl.radius_m,
                                    std::abs(p.z()) - 0.5 * cyl.length_m);
            return d.cwiseMax(0.0).norm() + std::min(d.maxCoeff(), 0.0);
          },
          [&](const MeshShape& m) {
            if (!m.mesh) return kInf;
            const double d = detail::mesh_unsigned_distance(*m.mesh, p);
            if (m.mesh->closed && d > 0.0 && detail::mesh_winding_inside(*m.mesh, p)) return -d;
            return d;
          }},
      shape.geometry);
}

bool shape_contains(const CollisionShape& shape, const Eigen::Vector3d& p_parent) {
  const Eigen::Vector3d p = detail::to_shape_frame(shape, p_parent);
  return std::visit(
      detail::Overloaded{
          [&](const Box& box) { return (p.cwiseAbs().array() <= 0.5 * box.size_m.array()).all(); },
          [&](const Sphere& s) { return p.squaredNorm() <= s.radius_m * s.radius_m; },
          [&](const Cylinder& cyl) {
            return p.head<2>().squaredNorm() <= cyl.radius_m * cyl.radius_m &&
                   std::abs(p.z()) <= 0.5 * cyl.length_m;
          },
          [&](const MeshShape& m) {
            if (!m.mesh) return false;
            if (m.mesh->closed) {
              const double w = std::abs(detail::mesh_winding_number(*m.mesh, p));
              if (w > 0.75) return true;
              if (w < 0.25) return false;
              // Near the surface the winding number is close to 1/2 and rounding decides; the
              // surface itself counts as contained.
              if (detail::mesh_unsigned_distance(*m.mesh, p) <= kOnSurfaceTolerance_m) return true;
              return w > 0.5;
            }
            // An open mesh is a surface without interior: only points on it are contained.
            return detail::mesh_unsigned_distance(*m.mesh, p) <= kOnSurfaceTolerance_m;
          }},
      shape.geometry);
}

Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                          const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  // Ericson, Real-Time Collision Detection §5.1.5 (Voronoi regions), with a fallback to the
  // edges for degenerate (zero-area) triangles where the barycentric solve is ill-posed.
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double area2 = ab.cross(ac).squaredNorm();
  const double scale2 = std::max({ab.squaredNorm(), ac.squaredNorm(), (c - b).squaredNorm()});
  if (area2 <= 1e-24 * scale2 * scale2) {
    Eigen::Vector3d best = closest_point_on_segment(p, a, b);
    for (const Eigen::Vector3d& q : {closest_point_on_segment(p, b, c), closest_point_on_segment(p, c, a)})
      if ((q - p).squaredNorm() < (best - p).squaredNorm()) best = q;
    return best;
  }
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + (d1 / (d1 - d3)) * ab;
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0)
    return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

namespace detail {

double mesh_winding_number(const TriangleMesh& mesh, const Eigen::Vector3d& p) {
  double omega = 0.0;
  for (const auto& tri : mesh.triangles) {
    const Eigen::Vector3d a = mesh.vertices_m[tri[0]] - p;
    const Eigen::Vector3d b = mesh.vertices_m[tri[1]] - p;
    const Eigen::Vector3d c = mesh.vertices_m[tri[2]] - p;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double num = a.dot(b.cross(c));
    const double den = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
    omega += 2.0 * std::atan2(num, den);
  }
  return omega / (4.0 * kPi);
}

double mesh_unsigned_distance(const TriangleMesh& mesh, const Eigen::Vector3d& p) {
  double best2 = kInf;
  for (const auto& tri : mesh.triangles) {
    const Eigen::Vector3d& a = mesh.vertices_m[tri[0]];
    const Eigen::Vector3d& b = mesh.vertices_m[tri[1]];
    const Eigen::Vector3d& c = mesh.vertices_m[tri[2]];
    // Cheap rejection: the triangle's bounding box is already farther than the best so far.
    const Eigen::Vector3d lo = a.cwiseMin(b).cwiseMin(c), hi = a.cwiseMax(b).cwiseMax(c);
    const double box2 = (p.cwiseMax(lo).cwiseMin(hi) - p).squaredNorm();
    if (box2 >= best2) continue;
    best2 = std::min(best2, (closest_point_on_triangle(p, a, b, c) - p).squaredNorm());
  }
  return std::sqrt(best2);
}

}  // namespace detail
}  // namespace porter
