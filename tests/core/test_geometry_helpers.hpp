#pragma once
// Shared fixtures for the geometry tests: random poses and shapes, and a non-convex closed
// mesh (an L-shaped prism) with an analytic description to check against.

#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "porter/core/geometry.hpp"

namespace porter::test {

inline Eigen::Isometry3d random_pose(std::mt19937_64& rng, double spread_m = 1.0) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::Quaterniond q(u(rng), u(rng), u(rng), u(rng));
  if (q.norm() < 1e-3) q = Eigen::Quaterniond::Identity();
  q.normalize();
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = q.toRotationMatrix();
  T.translation() = spread_m * Eigen::Vector3d(u(rng), u(rng), u(rng));
  return T;
}

inline Eigen::Vector3d random_point(std::mt19937_64& rng, double half_extent_m) {
  std::uniform_real_distribution<double> u(-half_extent_m, half_extent_m);
  return {u(rng), u(rng), u(rng)};
}

/// Closed, outward-oriented prism extruded from a counter-clockwise polygon that is star-shaped
/// with respect to its first vertex (capped with a fan from it), z in [z0, z1].
inline std::shared_ptr<TriangleMesh> extrude(const std::vector<Eigen::Vector2d>& poly, double z0, double z1) {
  auto m = std::make_shared<TriangleMesh>();
  const int n = static_cast<int>(poly.size());
  for (const auto& p : poly) m->vertices_m.emplace_back(p.x(), p.y(), z0);
  for (const auto& p : poly) m->vertices_m.emplace_back(p.x(), p.y(), z1);
  for (int i = 1; i + 1 < n; ++i) {
    m->triangles.emplace_back(n, n + i, n + i + 1);  // top, CCW seen from +z
    m->triangles.emplace_back(0, i + 1, i);          // bottom, reversed
  }
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    m->triangles.emplace_back(i, j, j + n);
    m->triangles.emplace_back(i, j + n, i + n);
  }
  m->closed = true;
  m->source = "extruded polygon";
  return m;
}

/// The L: [0,2]x[0,1] union [0,1]x[0,2], z in [0, 1]. Non-convex (notch at [1,2]x[1,2]).
inline std::shared_ptr<TriangleMesh> l_prism() {
  return extrude({{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}}, 0.0, 1.0);
}

/// Analytic distance to the L prism from outside (min of the two boxes' distances) and
/// containment.
inline double l_prism_outside_distance(const Eigen::Vector3d& p) {
  auto box_dist = [&](const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
    return (p.cwiseMax(lo).cwiseMin(hi) - p).norm();
  };
  return std::min(box_dist({0, 0, 0}, {2, 1, 1}), box_dist({0, 0, 0}, {1, 2, 1}));
}
inline bool l_prism_contains(const Eigen::Vector3d& p) { return l_prism_outside_distance(p) == 0.0; }

/// One of each shape type at a random pose; index picks the type (0 box, 1 sphere, 2 cylinder,
/// 3 L mesh, 4 box mesh).
inline CollisionShape random_shape(std::mt19937_64& rng, int type) {
  std::uniform_real_distribution<double> size(0.2, 1.5);
  CollisionShape s;
  s.T_parent_shape = random_pose(rng);
  switch (type) {
    case 0: s.geometry = Box{Eigen::Vector3d(size(rng), size(rng), size(rng))}; s.name = "box"; break;
    case 1: s.geometry = Sphere{size(rng)}; s.name = "sphere"; break;
    case 2: s.geometry = Cylinder{0.5 * size(rng), 2.0 * size(rng)}; s.name = "cylinder"; break;
    case 3: s.geometry = MeshShape{l_prism()}; s.name = "L"; break;
    default: {
      CollisionShape b;
      b.geometry = Box{Eigen::Vector3d(size(rng), size(rng), size(rng))};
      s.geometry = MeshShape{std::make_shared<TriangleMesh>(shape_to_mesh(b))};
      s.name = "box mesh";
    }
  }
  return s;
}

}  // namespace porter::test
