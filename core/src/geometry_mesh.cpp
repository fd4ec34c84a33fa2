// Triangulation of shapes (geometry.hpp): closed, outward-oriented, vertices shared between
// neighbouring triangles so that every edge is used by exactly two triangles.

#include <algorithm>
#include <cmath>

#include "geometry_internal.hpp"
#include "porter/core/geometry.hpp"

namespace porter {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// Adds triangle (i, j, k) wound counter-clockwise seen from outside. Only for the convex
/// primitives below, which contain their own frame's origin: outward means the normal points
/// away from the origin.
void add_outward(TriangleMesh& m, int i, int j, int k) {
  const Eigen::Vector3d& a = m.vertices_m[i];
  const Eigen::Vector3d& b = m.vertices_m[j];
  const Eigen::Vector3d& c = m.vertices_m[k];
  const Eigen::Vector3d n = (b - a).cross(c - a);
  if (n.dot(a + b + c) >= 0.0)
    m.triangles.emplace_back(i, j, k);
  else
    m.triangles.emplace_back(i, k, j);
}

TriangleMesh box_mesh(const Box& box) {
  TriangleMesh m;
  const Eigen::Vector3d h = 0.5 * box.size_m;
  for (int k = 0; k < 8; ++k)  // corner k: bit i set means +h_i
    m.vertices_m.emplace_back((k & 1) ? h.x() : -h.x(), (k & 2) ? h.y() : -h.y(), (k & 4) ? h.z() : -h.z());
  for (int axis = 0; axis < 3; ++axis) {
    const int u = 1 << ((axis + 1) % 3), v = 1 << ((axis + 2) % 3);
    for (const int side : {0, 1 << axis}) {
      add_outward(m, side, side | u, side | u | v);
      add_outward(m, side, side | u | v, side | v);
    }
  }
  return m;
}

TriangleMesh cylinder_mesh(const Cylinder& cyl, int segments) {
  TriangleMesh m;
  const int n = std::max(3, segments);
  const double h = 0.5 * cyl.length_m;
  for (const double z : {-h, h})
    for (int k = 0; k < n; ++k) {
      const double a = 2.0 * kPi * k / n;
      m.vertices_m.emplace_back(cyl.radius_m * std::cos(a), cyl.radius_m * std::sin(a), z);
    }
  const int bottom = static_cast<int>(m.vertices_m.size());
  m.vertices_m.emplace_back(0.0, 0.0, -h);
  const int top = bottom + 1;
  m.vertices_m.emplace_back(0.0, 0.0, h);
  for (int k = 0; k < n; ++k) {
    const int k1 = (k + 1) % n;
    add_outward(m, k, k1, n + k1);
    add_outward(m, k, n + k1, n + k);
    add_outward(m, bottom, k, k1);
    add_outward(m, top, n + k, n + k1);
  }
  return m;
}

TriangleMesh sphere_mesh(const Sphere& s, int segments) {
  TriangleMesh m;
  const int lon = std::max(3, segments);
  const int lat = std::max(2, segments / 2);
  m.vertices_m.emplace_back(0.0, 0.0, -s.radius_m);  // south pole, index 0
  for (int i = 1; i < lat; ++i) {                     // rings, i = 1 .. lat-1
    const double theta = kPi * i / lat - 0.5 * kPi;
    for (int k = 0; k < lon; ++k) {
      const double phi = 2.0 * kPi * k / lon;
      m.vertices_m.emplace_back(s.radius_m * std::cos(theta) * std::cos(phi),
                                s.radius_m * std::cos(theta) * std::sin(phi), s.radius_m * std::sin(theta));
    }
  }
  const int north = static_cast<int>(m.vertices_m.size());
  m.vertices_m.emplace_back(0.0, 0.0, s.radius_m);
  auto ring = [lon](int i, int k) { return 1 + (i - 1) * lon + (k % lon); };
  for (int k = 0; k < lon; ++k) {
    add_outward(m, 0, ring(1, k), ring(1, k + 1));
    add_outward(m, north, ring(lat - 1, k), ring(lat - 1, k + 1));
    for (int i = 1; i + 1 < lat; ++i) {
      add_outward(m, ring(i, k), ring(i, k + 1), ring(i + 1, k + 1));
      add_outward(m, ring(i, k), ring(i + 1, k + 1), ring(i + 1, k));
    }
  }
  return m;
}

}  // namespace

TriangleMesh shape_to_mesh(const CollisionShape& shape, int segments) {
  TriangleMesh m = std::visit(
      detail::Overloaded{[&](const Box& b) { return box_mesh(b); },
                 [&](const Cylinder& c) { return cylinder_mesh(c, segments); },
                 [&](const Sphere& s) { return sphere_mesh(s, segments); },
                 [&](const MeshShape& ms) { return ms.mesh ? *ms.mesh : TriangleMesh{}; }},
      shape.geometry);
  if (!std::holds_alternative<MeshShape>(shape.geometry)) m.closed = true;
  if (m.source.empty()) m.source = shape.name;
  for (auto& v : m.vertices_m) v = shape.T_parent_shape * v;
  return m;
}

}  // namespace porter
