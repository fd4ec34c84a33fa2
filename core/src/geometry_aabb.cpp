// Shape / axis-aligned box intersection (geometry.hpp).
//
// Semantics: shapes and boxes are closed sets, so touching counts as intersecting. Exactness:
//   - box (any orientation): 15-axis separating-axis test; |R| is padded by 1e-12 against
//     rounding for near-parallel edges, so the test is exact up to ~1e-12 m and errs on the
//     side of "intersects";
//   - triangle: Akenine-Möller's 13-axis test, exact;
//   - sphere: closest point of the box to the centre, exact;
//   - cylinder (any orientation): the box is clipped to the cylinder's slab |z| <= L/2 in the
//     cylinder frame and the clipped polytope's projection onto the cap plane (a convex polygon)
//     is tested against the cap disc; exact up to rounding (~1e-12 m);
//   - mesh: per-triangle test; a closed mesh additionally counts boxes lying wholly inside it
//     (no triangle crosses the box, and the box centre has winding number > 1/2).

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "geometry_internal.hpp"
#include "porter/core/geometry.hpp"

namespace porter {
namespace {

/// Oriented box (rotation R, centre c, half extents hb) vs axis-aligned box (centre a, half ha).
bool obb_intersects_aabb(const Eigen::Matrix3d& R, const Eigen::Vector3d& c, const Eigen::Vector3d& hb,
                         const Eigen::Vector3d& a, const Eigen::Vector3d& ha) {
  // Ericson, Real-Time Collision Detection §4.4.1, with A the axis-aligned box.
  const Eigen::Vector3d t = c - a;
  const Eigen::Matrix3d absR = R.cwiseAbs().array() + 1e-12;
  for (int i = 0; i < 3; ++i)
    if (std::abs(t[i]) > ha[i] + absR.row(i).dot(hb)) return false;
  for (int j = 0; j < 3; ++j)
    if (std::abs(t.dot(R.col(j))) > absR.col(j).dot(ha) + hb[j]) return false;
  for (int i = 0; i < 3; ++i) {
    const int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
    for (int j = 0; j < 3; ++j) {
      const int j1 = (j + 1) % 3, j2 = (j + 2) % 3;
      const double ra = ha[i1] * absR(i2, j) + ha[i2] * absR(i1, j);
      const double rb = hb[j1] * absR(i, j2) + hb[j2] * absR(i, j1);
      if (std::abs(t[i2] * R(i1, j) - t[i1] * R(i2, j)) > ra + rb) return false;
    }
  }
  return true;
}

double cross2(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

double segment_distance2_to_origin(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp(-a.dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (a + t * ab).squaredNorm();
}

/// Does the convex hull of `pts` come within `radius` of the origin?
bool hull_within_radius_of_origin(std::vector<Eigen::Vector2d>& pts, double radius) {
  const double r2 = radius * radius;
  for (const auto& p : pts)
    if (p.squaredNorm() <= r2) return true;
  // Andrew's monotone chain, counter-clockwise, collinear points dropped.
  std::sort(pts.begin(), pts.end(), [](const Eigen::Vector2d& u, const Eigen::Vector2d& v) {
    return u.x() < v.x() || (u.x() == v.x() && u.y() < v.y());
  });
  std::vector<Eigen::Vector2d> hull(2 * pts.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    while (k >= 2 && cross2(hull[k - 2], hull[k - 1], pts[i]) <= 0.0) --k;
    hull[k++] = pts[i];
  }
  for (std::size_t i = pts.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && cross2(hull[k - 2], hull[k - 1], pts[i]) <= 0.0) --k;
    hull[k++] = pts[i];
  }
  hull.resize(k > 1 ? k - 1 : k);
  const std::size_t n = hull.size();
  if (n >= 3) {
    bool inside = true;
    for (std::size_t i = 0; i < n && inside; ++i)
      inside = cross2(hull[i], hull[(i + 1) % n], Eigen::Vector2d::Zero()) >= 0.0;
    if (inside) return true;
  }
  for (std::size_t i = 0; i < n; ++i)
    if (segment_distance2_to_origin(hull[i], hull[(i + 1) % n]) <= r2) return true;
  return false;
}

bool cylinder_intersects_aabb(const Cylinder& cyl, const Eigen::Isometry3d& T_parent_cyl,
                              const Eigen::AlignedBox3d& box) {
  const Eigen::Matrix3d Rt = T_parent_cyl.linear().transpose();
  const Eigen::Vector3d c_local = Rt * (box.center() - T_parent_cyl.translation());
  const Eigen::Vector3d half = 0.5 * box.sizes();
  // Quick decisions from the distance of the box centre: inside, or farther than the box reach.
  {
    const Eigen::Vector2d d(c_local.head<2>().norm() - cyl.radius_m,
                            std::abs(c_local.z()) - 0.5 * cyl.length_m);
    const double sd = d.cwiseMax(0.0).norm() + std::min(d.maxCoeff(), 0.0);
    if (sd <= 0.0) return true;
    if (sd > half.norm() * (1.0 + 1e-12)) return false;
  }
  // The box's corners in the cylinder frame: corner k = c + sum_i (+-half_i) * Rt.col(i).
  std::array<Eigen::Vector3d, 8> v;
  for (int k = 0; k < 8; ++k) {
    Eigen::Vector3d p = c_local;
    for (int i = 0; i < 3; ++i) p += ((k >> i) & 1 ? half[i] : -half[i]) * Rt.col(i);
    v[k] = p;
  }
  const double h = 0.5 * cyl.length_m;
  std::vector<Eigen::Vector2d> pts;
  pts.reserve(32);
  for (const auto& p : v)
    if (std::abs(p.z()) <= h) pts.emplace_back(p.head<2>());
  for (int k = 0; k < 8; ++k) {
    for (int i = 0; i < 3; ++i) {
      if ((k >> i) & 1) continue;
      const Eigen::Vector3d& p0 = v[k];
      const Eigen::Vector3d& p1 = v[k | (1 << i)];
      for (const double zc : {-h, h}) {
        const double s0 = p0.z() - zc, s1 = p1.z() - zc;
        if ((s0 < 0.0 && s1 > 0.0) || (s0 > 0.0 && s1 < 0.0)) {
          const double t = s0 / (s0 - s1);
          pts.emplace_back((p0 + t * (p1 - p0)).head<2>());
        }
      }
    }
  }
  if (pts.empty()) return false;  // the box misses the slab entirely
  return hull_within_radius_of_origin(pts, cyl.radius_m);
}

bool mesh_intersects_aabb(const TriangleMesh& mesh, const Eigen::Isometry3d& T_parent_mesh,
                          const Eigen::AlignedBox3d& box) {
  // Prefilter triangles in the mesh frame against the bounds of the box seen from there.
  const Eigen::Isometry3d T_mesh_parent = T_parent_mesh.inverse(Eigen::Isometry);
  const Eigen::Vector3d half = 0.5 * box.sizes();
  const Eigen::Vector3d c_mesh = T_mesh_parent * box.center();
  const Eigen::Vector3d ext = T_mesh_parent.linear().cwiseAbs() * half;
  const Eigen::AlignedBox3d box_mesh(c_mesh - ext, c_mesh + ext);
  for (const auto& tri : mesh.triangles) {
    const Eigen::Vector3d& a = mesh.vertices_m[tri[0]];
    const Eigen::Vector3d& b = mesh.vertices_m[tri[1]];
    const Eigen::Vector3d& c = mesh.vertices_m[tri[2]];
    const Eigen::Vector3d lo = a.cwiseMin(b).cwiseMin(c), hi = a.cwiseMax(b).cwiseMax(c);
    if ((lo.array() > box_mesh.max().array()).any() || (hi.array() < box_mesh.min().array()).any())
      continue;
    if (triangle_intersects_aabb(T_parent_mesh * a, T_parent_mesh * b, T_parent_mesh * c, box))
      return true;
  }
  if (!mesh.closed) return false;
  // No triangle meets the box, so the box is wholly inside or wholly outside.
  const Eigen::AlignedBox3d bounds = mesh.bounds();
  if (!bounds.contains(c_mesh)) return false;
  return detail::mesh_winding_inside(mesh, c_mesh);
}

}  // namespace

bool triangle_intersects_aabb(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                              const Eigen::Vector3d& c, const Eigen::AlignedBox3d& box) {
  if (box.isEmpty()) return false;
  const Eigen::Vector3d center = box.center();
  const Eigen::Vector3d e = 0.5 * box.sizes();
  const Eigen::Vector3d v0 = a - center, v1 = b - center, v2 = c - center;
  // Box face normals.
  for (int i = 0; i < 3; ++i) {
    if (std::max({v0[i], v1[i], v2[i]}) < -e[i]) return false;
    if (std::min({v0[i], v1[i], v2[i]}) > e[i]) return false;
  }
  const std::array<Eigen::Vector3d, 3> f = {v1 - v0, v2 - v1, v0 - v2};
  // The nine cross products of box axes with triangle edges.
  for (int i = 0; i < 3; ++i) {
    for (const auto& edge : f) {
      const Eigen::Vector3d ax = Eigen::Vector3d::Unit(i).cross(edge);
      const double p0 = v0.dot(ax), p1 = v1.dot(ax), p2 = v2.dot(ax);
      const double r = e.dot(ax.cwiseAbs());
      if (std::min({p0, p1, p2}) > r || std::max({p0, p1, p2}) < -r) return false;
    }
  }
  // Triangle plane.
  const Eigen::Vector3d n = f[0].cross(f[1]);
  return std::abs(n.dot(v0)) <= e.dot(n.cwiseAbs());
}

bool shape_intersects_aabb(const CollisionShape& shape, const Eigen::AlignedBox3d& box_parent) {
  if (box_parent.isEmpty()) return false;
  const Eigen::Isometry3d& T = shape.T_parent_shape;
  return std::visit(
      detail::Overloaded{
          [&](const Box& b) {
            return obb_intersects_aabb(T.linear(), T.translation(), 0.5 * b.size_m,
                                       box_parent.center(), 0.5 * box_parent.sizes());
          },
          [&](const Sphere& s) {
            const Eigen::Vector3d c = T.translation();
            const Eigen::Vector3d q = c.cwiseMax(box_parent.min()).cwiseMin(box_parent.max());
            return (q - c).squaredNorm() <= s.radius_m * s.radius_m;
          },
          [&](const Cylinder& c) { return cylinder_intersects_aabb(c, T, box_parent); },
          [&](const MeshShape& m) { return m.mesh && mesh_intersects_aabb(*m.mesh, T, box_parent); }},
      shape.geometry);
}

}  // namespace porter
