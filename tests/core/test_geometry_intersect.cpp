// Shape / box and triangle / box intersection (geometry.hpp) against brute-force sampling
// references and exact tangent-plane constructions.

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "porter/core/geometry.hpp"
#include "test_geometry_helpers.hpp"

namespace porter {
namespace {

using test::random_point;
using test::random_pose;

const char* kTypeNames[] = {"box", "sphere", "cylinder", "L mesh", "box mesh"};

Eigen::AlignedBox3d random_box_near(std::mt19937_64& rng, const CollisionShape& s) {
  Eigen::AlignedBox3d b = shape_bounds(s);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const Eigen::Vector3d lo = b.min().array() - 0.3, span = b.sizes().array() + 0.6;
  const Eigen::Vector3d c = lo + span.cwiseProduct(Eigen::Vector3d(u(rng), u(rng), u(rng)));
  // Sizes from thin slabs to chunky boxes.
  const Eigen::Vector3d size(0.01 + 0.4 * u(rng) * u(rng), 0.01 + 0.4 * u(rng), 0.01 + 0.4 * u(rng));
  return Eigen::AlignedBox3d(c - 0.5 * size, c + 0.5 * size);
}

TEST(GeometryAabb, ShapesAgreeWithDenseSampling) {
  // No false negatives: a sample of the box inside the shape forces "intersects". Any positive
  // is a true overlap within the sampling tolerance: the signed distance is 1-Lipschitz, so some
  // sample lies within half a sampling-cell diagonal of the contact point.
  std::mt19937_64 rng(11);
  const int n = 9;
  for (int type = 0; type < 5; ++type) {
    int positives = 0, negatives = 0;
    for (int trial = 0; trial < 300; ++trial) {
      const CollisionShape s = test::random_shape(rng, type);
      const Eigen::AlignedBox3d box = random_box_near(rng, s);
      const Eigen::Vector3d step = box.sizes() / (n - 1);
      const double tol = 0.5 * step.norm() + 1e-9;
      bool sample_inside = false;
      double min_sd = 1e300;
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
          for (int k = 0; k < n; ++k) {
            const Eigen::Vector3d p = box.min() + step.cwiseProduct(Eigen::Vector3d(i, j, k));
            sample_inside = sample_inside || shape_contains(s, p);
            min_sd = std::min(min_sd, shape_signed_distance(s, p));
          }
      const bool got = shape_intersects_aabb(s, box);
      if (sample_inside) {
        EXPECT_TRUE(got) << kTypeNames[type] << " trial " << trial;
      }
      if (got) {
        EXPECT_LE(min_sd, tol) << kTypeNames[type] << " trial " << trial;
      }
      (got ? positives : negatives)++;
    }
    EXPECT_GT(positives, 40) << kTypeNames[type];
    EXPECT_GT(negatives, 40) << kTypeNames[type];
  }
}

/// Farthest point of a convex shape along n (parent frame).
Eigen::Vector3d support(const CollisionShape& s, const Eigen::Vector3d& n) {
  const Eigen::Isometry3d& T = s.T_parent_shape;
  const Eigen::Vector3d nl = T.linear().transpose() * n;
  Eigen::Vector3d p;
  if (const auto* b = std::get_if<Box>(&s.geometry)) {
    p = 0.5 * b->size_m.cwiseProduct(nl.cwiseSign());
  } else if (const auto* sp = std::get_if<Sphere>(&s.geometry)) {
    p = sp->radius_m * nl.normalized();
  } else if (const auto* c = std::get_if<Cylinder>(&s.geometry)) {
    p << c->radius_m * nl.head<2>().normalized(), (nl.z() > 0 ? 0.5 : -0.5) * c->length_m;
  } else {
    const auto& m = *std::get<MeshShape>(s.geometry).mesh;
    p = m.vertices_m[0];
    for (const auto& v : m.vertices_m)
      if (v.dot(nl) > p.dot(nl)) p = v;
  }
  return T * p;
}

TEST(GeometryAabb, ExactAtTangentPlanes) {
  // A box whose nearest corner sits 1e-6 outside a supporting plane of a convex shape must be
  // reported separate; 1e-6 inside (the corner is then inside the shape), intersecting.
  std::mt19937_64 rng(12);
  for (const int type : {0, 1, 2, 4}) {
    for (int trial = 0; trial < 300; ++trial) {
      const CollisionShape s = test::random_shape(rng, type);
      const Eigen::Vector3d n = random_point(rng, 1.0).normalized();
      const Eigen::Vector3d p = support(s, n);
      const Eigen::Vector3d sigma = n.cwiseSign();
      const Eigen::Vector3d size = Eigen::Vector3d::Constant(0.3);
      for (const double delta : {1e-6, -1e-6}) {
        const Eigen::Vector3d corner = p + delta * n;
        const Eigen::Vector3d far = corner + sigma.cwiseProduct(size);
        const Eigen::AlignedBox3d box(corner.cwiseMin(far), corner.cwiseMax(far));
        if (delta > 0) {
          EXPECT_FALSE(shape_intersects_aabb(s, box)) << kTypeNames[type] << " trial " << trial;
        } else {
          ASSERT_TRUE(shape_contains(s, corner)) << kTypeNames[type];
          EXPECT_TRUE(shape_intersects_aabb(s, box)) << kTypeNames[type] << " trial " << trial;
        }
      }
    }
  }
}

TEST(GeometryAabb, ClosedMeshCountsBoxesWhollyInside) {
  const CollisionShape l{MeshShape{test::l_prism()}, Eigen::Isometry3d::Identity(), "L"};
  const Eigen::AlignedBox3d inside(Eigen::Vector3d(0.4, 0.4, 0.4), Eigen::Vector3d(0.6, 0.6, 0.6));
  const Eigen::AlignedBox3d notch(Eigen::Vector3d(1.4, 1.4, 0.4), Eigen::Vector3d(1.6, 1.6, 0.6));
  EXPECT_TRUE(shape_intersects_aabb(l, inside));
  EXPECT_FALSE(shape_intersects_aabb(l, notch));
  auto open = test::l_prism();
  open->closed = false;
  const CollisionShape surface{MeshShape{open}, Eigen::Isometry3d::Identity(), "open L"};
  EXPECT_FALSE(shape_intersects_aabb(surface, inside));  // a surface has no interior
}

TEST(GeometryAabb, TouchingCountsAsIntersecting) {
  const CollisionShape box{Box{Eigen::Vector3d(1, 1, 1)}, Eigen::Isometry3d::Identity(), "b"};
  const Eigen::AlignedBox3d touching(Eigen::Vector3d(0.5, -0.1, -0.1), Eigen::Vector3d(0.7, 0.1, 0.1));
  EXPECT_TRUE(shape_intersects_aabb(box, touching));
  EXPECT_FALSE(shape_intersects_aabb(box, Eigen::AlignedBox3d()));  // empty box
}

TEST(GeometryTriangle, AgreesWithDenseSampling) {
  std::mt19937_64 rng(13);
  const int n = 40;
  int positives = 0, negatives = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const Eigen::Vector3d a = random_point(rng, 1), b = random_point(rng, 1), c = random_point(rng, 1);
    const Eigen::Vector3d center = random_point(rng, 0.8);
    const Eigen::Vector3d half = 0.02 + 0.3 * random_point(rng, 1).cwiseAbs().array();
    const Eigen::AlignedBox3d box(center - half, center + half);
    bool sample_inside = false;
    double min_dist = 1e300;
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        const Eigen::Vector3d p = a + (b - a) * (double(i) / n) + (c - a) * (double(j) / n);
        sample_inside = sample_inside || box.contains(p);
        min_dist = std::min(min_dist, (p.cwiseMax(box.min()).cwiseMin(box.max()) - p).norm());
      }
    const double tol = std::max({(b - a).norm(), (c - a).norm(), (c - b).norm()}) / n + 1e-12;
    const bool got = triangle_intersects_aabb(a, b, c, box);
    if (sample_inside) {
      EXPECT_TRUE(got) << trial;
    }
    if (got) {
      EXPECT_LE(min_dist, tol) << trial;
    }
    (got ? positives : negatives)++;
  }
  EXPECT_GT(positives, 200);
  EXPECT_GT(negatives, 300);
}

TEST(GeometryTriangle, LargeTriangleThroughBoxAndNearMisses) {
  const Eigen::AlignedBox3d box(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 1));
  // No vertex inside, the triangle slices through the middle.
  EXPECT_TRUE(triangle_intersects_aabb({-5, -5, 0.5}, {10, -5, 0.5}, {-5, 10, 0.5}, box));
  // Same plane lifted just above the top face, and just touching it.
  EXPECT_FALSE(triangle_intersects_aabb({-5, -5, 1 + 1e-9}, {10, -5, 1 + 1e-9}, {-5, 10, 1 + 1e-9}, box));
  EXPECT_TRUE(triangle_intersects_aabb({-5, -5, 1}, {10, -5, 1}, {-5, 10, 1}, box));
  // Plane x + y = 2 + d cuts off the edge x = y = 1 only for d < 0 (triangle-normal axis).
  for (const double d : {1e-7, -1e-7}) {
    const double s = 2 + d;
    EXPECT_EQ(triangle_intersects_aabb({s, 0, -5}, {0, s, -5}, {s / 2, s / 2, 10}, box), d < 0);
  }
  // Edge AB runs along x + y = 2 + d at z = 0.5 and the triangle rises away from the box, while
  // its plane dips into the box below z = 0.5: only the edge-cross axis (1, 1, 0) separates.
  for (const double d : {1e-7, -1e-7}) {
    EXPECT_EQ(triangle_intersects_aabb({2 + d, 0, 0.5}, {0, 2 + d, 0.5}, {3, 3, 20}, box), d < 0);
  }
}

}  // namespace
}  // namespace porter
