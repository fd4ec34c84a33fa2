// Distances, containment, bounds and closest points of the exact geometry (geometry.hpp),
// checked against independently written analytic references.

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "porter/core/geometry.hpp"
#include "test_geometry_helpers.hpp"

namespace porter {
namespace {

using test::random_point;
using test::random_pose;

// Reference box distance: clamp for outside points, nearest face for inside points.
double ref_box_sdf(const Eigen::Vector3d& p, const Eigen::Vector3d& size) {
  const Eigen::Vector3d h = 0.5 * size;
  const Eigen::Vector3d q = p.cwiseMax(-h).cwiseMin(h);
  if (q != p) return (q - p).norm();
  double face = 1e300;
  for (int i = 0; i < 3; ++i) face = std::min({face, h[i] - p[i], p[i] + h[i]});
  return -face;
}

// Reference cylinder distance by region: inside, beside the side, above/below a cap, or near
// the rim edge.
double ref_cylinder_sdf(const Eigen::Vector3d& p, double r, double length) {
  const double rho = std::hypot(p.x(), p.y()), h = 0.5 * length, az = std::abs(p.z());
  if (rho <= r && az <= h) return -std::min(r - rho, h - az);
  if (rho <= r) return az - h;
  if (az <= h) return rho - r;
  return std::hypot(rho - r, az - h);
}

CollisionShape make(ShapeGeometry g, const Eigen::Isometry3d& T) {
  CollisionShape s;
  s.geometry = std::move(g);
  s.T_parent_shape = T;
  return s;
}

TEST(GeometrySdf, BoxMatchesReferenceAtRandomPoints) {
  std::mt19937_64 rng(1);
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::Vector3d size(0.3 + trial * 0.05, 1.2, 0.7);
    const Eigen::Isometry3d T = random_pose(rng);
    const CollisionShape s = make(Box{size}, T);
    for (int k = 0; k < 500; ++k) {
      const Eigen::Vector3d p_local = random_point(rng, 1.2);
      const double ref = ref_box_sdf(p_local, size);
      EXPECT_NEAR(shape_signed_distance(s, T * p_local), ref, 1e-12);
      EXPECT_EQ(shape_contains(s, T * p_local), ref <= 0.0) << ref;
    }
  }
}

TEST(GeometrySdf, SphereMatchesReference) {
  std::mt19937_64 rng(2);
  const Eigen::Isometry3d T = random_pose(rng);
  const CollisionShape s = make(Sphere{0.8}, T);
  for (int k = 0; k < 2000; ++k) {
    const Eigen::Vector3d p = random_point(rng, 1.5);
    EXPECT_NEAR(shape_signed_distance(s, T * p), p.norm() - 0.8, 1e-12);
    EXPECT_EQ(shape_contains(s, T * p), p.norm() <= 0.8);
  }
}

TEST(GeometrySdf, CylinderMatchesReferenceIncludingCapsAndRim) {
  std::mt19937_64 rng(3);
  const double r = 0.4, length = 1.0;
  const Eigen::Isometry3d T = random_pose(rng);
  const CollisionShape s = make(Cylinder{r, length}, T);
  int regions[4] = {0, 0, 0, 0};  // inside, side, cap, rim
  for (int k = 0; k < 4000; ++k) {
    const Eigen::Vector3d p = random_point(rng, 1.0);
    const double rho = std::hypot(p.x(), p.y());
    const bool in_r = rho <= r, in_z = std::abs(p.z()) <= 0.5 * length;
    ++regions[in_r && in_z ? 0 : (in_z ? 1 : (in_r ? 2 : 3))];
    const double ref = ref_cylinder_sdf(p, r, length);
    EXPECT_NEAR(shape_signed_distance(s, T * p), ref, 1e-12) << p.transpose();
    EXPECT_EQ(shape_contains(s, T * p), ref <= 0.0);
  }
  for (int n : regions) EXPECT_GT(n, 100);  // every region was exercised
}

TEST(GeometrySdf, MeshOfBoxMatchesBoxSdf) {
  std::mt19937_64 rng(4);
  for (int trial = 0; trial < 10; ++trial) {
    const Eigen::Vector3d size(0.5, 0.9 + 0.1 * trial, 0.3);
    const CollisionShape box = make(Box{size}, random_pose(rng));
    const auto mesh = std::make_shared<TriangleMesh>(shape_to_mesh(box));
    const CollisionShape as_mesh = make(MeshShape{mesh}, Eigen::Isometry3d::Identity());
    for (int k = 0; k < 300; ++k) {
      const Eigen::Vector3d p = box.T_parent_shape * random_point(rng, 1.0);
      EXPECT_NEAR(shape_signed_distance(as_mesh, p), shape_signed_distance(box, p), 1e-9);
    }
  }
}

TEST(GeometrySdf, MeshOfCylinderApproachesCylinderSdf) {
  // A 512-gon prism lies between the cylinder and a cylinder r/cos(pi/512) apart.
  std::mt19937_64 rng(5);
  const CollisionShape cyl = make(Cylinder{0.5, 0.8}, random_pose(rng));
  const CollisionShape mesh =
      make(MeshShape{std::make_shared<TriangleMesh>(shape_to_mesh(cyl, 512))}, Eigen::Isometry3d::Identity());
  const double tol = 0.5 * (1.0 - std::cos(M_PI / 512)) + 1e-12;
  for (int k = 0; k < 300; ++k) {
    const Eigen::Vector3d p = cyl.T_parent_shape * random_point(rng, 0.9);
    EXPECT_NEAR(shape_signed_distance(mesh, p), shape_signed_distance(cyl, p), tol);
  }
}

TEST(GeometryWinding, NonConvexLPrismInsideOutside) {
  std::mt19937_64 rng(6);
  const Eigen::Isometry3d T = random_pose(rng);
  const CollisionShape s = make(MeshShape{test::l_prism()}, T);
  int inside = 0, notch = 0;
  std::uniform_real_distribution<double> u(-0.5, 2.5);
  for (int k = 0; k < 3000; ++k) {
    const Eigen::Vector3d p(u(rng), u(rng), u(rng) * 0.6);
    const double d_out = test::l_prism_outside_distance(p);
    const bool in = test::l_prism_contains(p);
    inside += in;
    notch += (p.x() > 1.0 && p.y() > 1.0 && p.x() < 2.0 && p.y() < 2.0 && p.z() > 0 && p.z() < 1);
    EXPECT_EQ(shape_contains(s, T * p), in) << p.transpose();
    const double sd = shape_signed_distance(s, T * p);
    if (in) {
      EXPECT_LE(sd, 0.0);
    } else {
      EXPECT_NEAR(sd, d_out, 1e-12);
    }
  }
  EXPECT_GT(inside, 200);
  EXPECT_GT(notch, 50);  // points in the concave notch are outside though inside the hull
}

TEST(GeometryWinding, OpenMeshIsUnsignedAndContainsOnlyItsSurface) {
  auto mesh = test::l_prism();
  mesh->triangles.pop_back();  // remove one side triangle: no longer closed
  mesh->closed = false;
  const CollisionShape s = make(MeshShape{mesh}, Eigen::Isometry3d::Identity());
  EXPECT_NEAR(shape_signed_distance(s, {0.5, 0.5, 0.5}), 0.5, 1e-12);  // unsigned inside
  EXPECT_FALSE(shape_contains(s, {0.5, 0.5, 0.5}));
  EXPECT_TRUE(shape_contains(s, {0.5, 0.5, 1.0}));  // on the top face
}

TEST(GeometryBounds, BoundsEncloseShapeAndAreTight) {
  std::mt19937_64 rng(7);
  for (int type = 0; type < 5; ++type) {
    for (int trial = 0; trial < 20; ++trial) {
      const CollisionShape s = test::random_shape(rng, type);
      const Eigen::Isometry3d T_frame = random_pose(rng);
      const Eigen::AlignedBox3d b = shape_bounds(s, T_frame);
      // Reference: bounds of a fine triangulation (placed in the frame), whose vertices lie on
      // the surface; for the cylinder the true bounds can exceed them by r(1 - cos(pi/n)).
      const TriangleMesh m = shape_to_mesh(s, 720);
      Eigen::AlignedBox3d ref;
      for (const auto& v : m.vertices_m) ref.extend(T_frame * v);
      const double slack = type == 1 ? 1e-4 : (type == 2 ? 1e-5 : 1e-12);
      EXPECT_TRUE((b.min().array() <= ref.min().array() + 1e-12).all()) << s.name;
      EXPECT_TRUE((b.max().array() >= ref.max().array() - 1e-12).all()) << s.name;
      EXPECT_LE((b.min() - ref.min()).cwiseAbs().maxCoeff(), slack) << s.name;
      EXPECT_LE((b.max() - ref.max()).cwiseAbs().maxCoeff(), slack) << s.name;
    }
  }
}

TEST(GeometryBounds, SphereBoundsExact) {
  const CollisionShape s = make(Sphere{0.3}, Eigen::Isometry3d(Eigen::Translation3d(1, 2, 3)));
  const Eigen::AlignedBox3d b = shape_bounds(s);
  EXPECT_TRUE(b.min().isApprox(Eigen::Vector3d(0.7, 1.7, 2.7)));
  EXPECT_TRUE(b.max().isApprox(Eigen::Vector3d(1.3, 2.3, 3.3)));
}

TEST(GeometryMaxDistance, MatchesFarthestSurfacePoint) {
  std::mt19937_64 rng(8);
  for (int type = 0; type < 5; ++type) {
    for (int trial = 0; trial < 20; ++trial) {
      const CollisionShape s = test::random_shape(rng, type);
      const Eigen::Vector3d c = random_point(rng, 2.0);
      const TriangleMesh m = shape_to_mesh(s, 720);
      double ref = 0.0;
      for (const auto& v : m.vertices_m) ref = std::max(ref, (v - c).norm());
      const double got = shape_max_distance(s, c);
      EXPECT_GE(got, ref - 1e-12) << s.name;  // never an underestimate
      EXPECT_LE(got, ref + (type == 1 || type == 2 ? 1e-4 : 1e-12)) << s.name;
    }
  }
}

TEST(GeometryClosestPoint, AgreesWithDenseBarycentricSearch) {
  std::mt19937_64 rng(9);
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Vector3d a = random_point(rng, 1), b = random_point(rng, 1), c = random_point(rng, 1);
    const Eigen::Vector3d p = random_point(rng, 2);
    const Eigen::Vector3d q = closest_point_on_triangle(p, a, b, c);
    // q lies on the triangle: non-negative barycentric coordinates summing to one.
    Eigen::Matrix<double, 3, 2> E;
    E << b - a, c - a;
    const Eigen::Vector2d uv = E.colPivHouseholderQr().solve(q - a);
    EXPECT_GE(uv.x(), -1e-9);
    EXPECT_GE(uv.y(), -1e-9);
    EXPECT_LE(uv.sum(), 1.0 + 1e-9);
    EXPECT_LT((a + E * uv - q).norm(), 1e-9);
    // No point of a dense barycentric grid is closer.
    const int n = 60;
    double best = 1e300;
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j)
        best = std::min(best, (a + (b - a) * (double(i) / n) + (c - a) * (double(j) / n) - p).norm());
    EXPECT_LE((q - p).norm(), best + 1e-12);
  }
}

TEST(GeometryClosestPoint, DegenerateTriangles) {
  const Eigen::Vector3d a(0, 0, 0), b(1, 0, 0), c(2, 0, 0);  // collinear
  EXPECT_TRUE(closest_point_on_triangle({0.5, 1, 0}, a, b, c).isApprox(Eigen::Vector3d(0.5, 0, 0)));
  EXPECT_TRUE(closest_point_on_triangle({3, 1, 0}, a, b, c).isApprox(Eigen::Vector3d(2, 0, 0)));
  EXPECT_TRUE(closest_point_on_triangle({3, 1, 0}, a, a, a).isApprox(a));
}

}  // namespace
}  // namespace porter
