// Per-link SDF grids: exact node values, the trilinear error bound against analytic distances on
// primitives, gradients against finite differences, the sign on the non-convex payloads, and the
// robot's fields built on two threads equal to the serial build.

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "backend_fixtures.hpp"
#include "porter/backend/link_sdf.hpp"
#include "porter/core/geometry.hpp"

namespace porter::backend {
namespace {

CollisionShape make_shape(ShapeGeometry g, const Eigen::Isometry3d& T) {
  CollisionShape s;
  s.geometry = std::move(g);
  s.T_parent_shape = T;
  return s;
}

// Independent analytic signed distances (not geometry.cpp's).
double box_sdf(const Eigen::Vector3d& p, const Eigen::Vector3d& half) {
  const Eigen::Vector3d q = p.cwiseAbs() - half;
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}
double cylinder_sdf(const Eigen::Vector3d& p, double r, double half_len) {
  const Eigen::Vector2d d(Eigen::Vector2d(p.x(), p.y()).norm() - r, std::abs(p.z()) - half_len);
  return d.cwiseMax(0.0).norm() + std::min(d.maxCoeff(), 0.0);
}

Eigen::Vector3d random_point(std::mt19937& rng, const Eigen::AlignedBox3d& box) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  return box.min() + box.sizes().cwiseProduct(Eigen::Vector3d(u(rng), u(rng), u(rng)));
}

TEST(LinkSdf, PrimitivesWithinTheTrilinearBound) {
  Eigen::Isometry3d T_box = Eigen::Isometry3d::Identity();
  T_box.translation() << 0.1, -0.05, 0.02;
  Eigen::Isometry3d T_cyl = Eigen::Isometry3d::Identity();
  T_cyl.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix();
  T_cyl.translation() << -0.2, 0.1, 0.0;
  const Box box{Eigen::Vector3d(0.3, 0.12, 0.08)};
  const Cylinder cyl{0.05, 0.2};
  const std::vector<CollisionShape> shapes = {make_shape(box, T_box), make_shape(cyl, T_cyl),
                                              make_shape(Sphere{0.06}, Eigen::Isometry3d(Eigen::Translation3d(0.0, 0.15, 0.1)))};
  const LinkSdf sdf = LinkSdf::build(shapes, SdfGridSettings{});
  ASSERT_FALSE(sdf.empty());
  EXPECT_GE(sdf.resolution_m(), SdfGridSettings{}.min_resolution_m);
  EXPECT_LE(sdf.resolution_m(), SdfGridSettings{}.max_resolution_m);

  auto analytic = [&](const Eigen::Vector3d& p) {
    const double db = box_sdf(T_box.inverse() * p, 0.5 * box.size_m);
    const double dc = cylinder_sdf(T_cyl.inverse() * p, cyl.radius_m, 0.5 * cyl.length_m);
    const double ds = (p - Eigen::Vector3d(0.0, 0.15, 0.1)).norm() - 0.06;
    return std::min({db, dc, ds});
  };
  // Nodes are exact.
  const SdfGrid& fine = sdf.fine();
  for (int k = 0; k < fine.dims().z(); k += 7)
    for (int j = 0; j < fine.dims().y(); j += 5)
      for (int i = 0; i < fine.dims().x(); i += 3)
        ASSERT_NEAR(fine.value(i, j, k), analytic(fine.node_position(i, j, k)), 2e-6);
  // Anywhere in the fine grid: within sqrt(3)/2 h.
  std::mt19937 rng(7);
  double worst = 0.0;
  for (int n = 0; n < 20000; ++n) {
    const Eigen::Vector3d p = random_point(rng, fine.smooth_bounds());
    worst = std::max(worst, std::abs(sdf.distance(p) - analytic(p)));
    worst = std::max(worst, std::abs(sdf.distance_fast(p) - analytic(p)));
  }
  EXPECT_LE(worst, fine.error_bound_m());
  // The coarse grid and the extrapolation beyond it: within the coarse bound, and never below the
  // true distance by more than that bound (extrapolation is an upper bound).
  for (int n = 0; n < 5000; ++n) {
    const Eigen::Vector3d p = random_point(rng, sdf.coarse().smooth_bounds());
    EXPECT_NEAR(sdf.distance(p), analytic(p), sdf.coarse().error_bound_m());
  }
  for (int n = 0; n < 200; ++n) {
    const Eigen::Vector3d p = 4.0 * random_point(rng, sdf.coarse().bounds());
    if (sdf.coarse().contains(p)) continue;
    EXPECT_GE(sdf.distance(p), analytic(p) - sdf.coarse().error_bound_m());
    EXPECT_GE(sdf.distance(p), SdfGridSettings{}.coarse_padding_m - 1e-9);
  }
}

TEST(LinkSdf, GradientMatchesFiniteDifferencesAcrossBothGrids) {
  const std::vector<CollisionShape> shapes = {
      make_shape(Box{Eigen::Vector3d(0.2, 0.1, 0.3)}, Eigen::Isometry3d::Identity()),
      make_shape(Sphere{0.08}, Eigen::Isometry3d(Eigen::Translation3d(0.1, 0.1, 0.2)))};
  const LinkSdf sdf = LinkSdf::build(shapes, SdfGridSettings{});
  std::mt19937 rng(3);
  const double h = 1e-6;
  auto fd_gradient = [&](const Eigen::Vector3d& p) {
    Eigen::Vector3d fd;
    for (int a = 0; a < 3; ++a) {
      Eigen::Vector3d dp = Eigen::Vector3d::Zero();
      dp[a] = h;
      fd[a] = (sdf.distance(p + dp) - sdf.distance(p - dp)) / (2 * h);
    }
    return fd;
  };
  // The field is C^1 in the whole coarse grid, the band where the fine grid blends into the
  // coarse one included: the gradient matches everywhere.
  Eigen::AlignedBox3d band = sdf.fine().smooth_bounds();
  band.min().array() -= 0.05;
  band.max().array() += 0.05;
  for (const Eigen::AlignedBox3d& box : {sdf.fine().smooth_bounds(), sdf.coarse().smooth_bounds(), band}) {
    for (int n = 0; n < 1000; ++n) {
      const Eigen::Vector3d p = random_point(rng, box);
      if ((sdf.coarse().smooth_bounds().max() - p).minCoeff() < 2 * h ||
          (p - sdf.coarse().smooth_bounds().min()).minCoeff() < 2 * h) {
        continue;  // the coarse grid's own edge (extrapolation beyond) is only C^0
      }
      Eigen::Vector3d g;
      sdf.distance(p, &g);
      EXPECT_LT((fd_gradient(p) - g).norm(), 1e-6) << p.transpose();
    }
  }
  // Beyond the coarse grid: the derivative of d(q) + |p - q|.
  for (int n = 0; n < 100; ++n) {
    const Eigen::Vector3d p = sdf.coarse().bounds().max() + Eigen::Vector3d(0.3, -0.7, 0.2) * (1 + 0.01 * n);
    Eigen::Vector3d g;
    sdf.distance(p, &g);
    EXPECT_LT((fd_gradient(p) - g).norm(), 1e-6);
  }
}

TEST(SdfGrid, TrilinearGradientMatchesFiniteDifferencesInsideCells) {
  const std::vector<CollisionShape> shapes = {
      make_shape(Sphere{0.1}, Eigen::Isometry3d::Identity())};
  const LinkSdf sdf = LinkSdf::build(shapes, SdfGridSettings{});
  const SdfGrid& grid = sdf.fine();
  std::mt19937 rng(4);
  const double h = 1e-7;
  for (int n = 0; n < 500; ++n) {
    const Eigen::Vector3d p = random_point(rng, grid.smooth_bounds());
    Eigen::Vector3d g;
    const double v = grid.trilinear(p, &g);
    EXPECT_NEAR(v, sdf.distance_fast(p), 1e-12);
    EXPECT_NEAR(v, p.norm() - 0.1, grid.error_bound_m());
    for (int a = 0; a < 3; ++a) {
      Eigen::Vector3d dp = Eigen::Vector3d::Zero();
      dp[a] = h;
      const double u = (p[a] - grid.origin()[a]) / grid.resolution_m();
      if (std::abs(u - std::round(u)) * grid.resolution_m() < 2 * h) continue;  // cell face
      EXPECT_NEAR((grid.trilinear(p + dp, nullptr) - grid.trilinear(p - dp, nullptr)) / (2 * h), g[a], 1e-5);
    }
  }
}

TEST(LinkSdf, EmptyBodyIsFar) {
  const LinkSdf sdf = LinkSdf::build({}, SdfGridSettings{});
  EXPECT_TRUE(sdf.empty());
  Eigen::Vector3d g;
  EXPECT_EQ(sdf.distance(Eigen::Vector3d::Zero(), &g), LinkSdf::kNoGeometryDistance_m);
  EXPECT_TRUE(g.isZero());
}

TEST(LinkSdf, ResolutionFollowsBodySize) {
  const SdfGridSettings s;
  const double small = choose_sdf_resolution(Eigen::AlignedBox3d(Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(0.01)), [] { SdfGridSettings t; t.fine_padding_m = 0.15; return t; }());
  const double mid = choose_sdf_resolution(Eigen::AlignedBox3d(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.6, 0.4, 0.3)), s);
  const double large = choose_sdf_resolution(Eigen::AlignedBox3d(Eigen::Vector3d::Zero(), Eigen::Vector3d(3.0, 3.0, 2.0)), s);
  EXPECT_EQ(small, s.min_resolution_m);
  EXPECT_GT(mid, small);
  EXPECT_LT(mid, large);
  EXPECT_EQ(large, s.max_resolution_m);
}

class PayloadSdf : public ::testing::TestWithParam<std::string> {};

// Non-convex payloads (the T, the arc): node values equal the exact mesh distance (the pruned build
// is exact), and the sign agrees with winding-number containment everywhere the value is farther
// from zero than the interpolation bound.
TEST_P(PayloadSdf, SignAndValuesOnNonConvexMeshes) {
  const RobotModel& model = testing::robot(GetParam());
  const std::vector<CollisionShape>& shapes = model.links[kEndEffectorLink].shapes;
  const LinkSdf& sdf = testing::robot_sdf(GetParam()).link(kEndEffectorLink);
  auto exact = [&](const Eigen::Vector3d& p) {
    double d = std::numeric_limits<double>::infinity();
    for (const auto& s : shapes) d = std::min(d, shape_signed_distance(s, p));
    return d;
  };
  auto inside = [&](const Eigen::Vector3d& p) {
    for (const auto& s : shapes)
      if (shape_contains(s, p)) return true;
    return false;
  };
  const SdfGrid& fine = sdf.fine();
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> ix(0, fine.dims().x() - 1), iy(0, fine.dims().y() - 1),
      iz(0, fine.dims().z() - 1);
  for (int n = 0; n < 3000; ++n) {
    const int i = ix(rng), j = iy(rng), k = iz(rng);
    ASSERT_NEAR(fine.value(i, j, k), exact(fine.node_position(i, j, k)), 2e-6);
  }
  // Points on and near the payload, where the sign matters.
  int inside_count = 0, outside_near = 0;
  Eigen::AlignedBox3d near = sdf.body_bounds();
  for (int n = 0; n < 40000; ++n) {
    const Eigen::Vector3d p = random_point(rng, near);
    const double d = sdf.distance(p);
    if (std::abs(d) <= fine.error_bound_m()) continue;
    const bool in = inside(p);
    ASSERT_EQ(d < 0.0, in) << "p = " << p.transpose() << " d = " << d;
    inside_count += in;
    outside_near += !in;
  }
  EXPECT_GT(inside_count, 50);
  EXPECT_GT(outside_near, 1000);  // the bounding box of a T or an arc is mostly empty
}

INSTANTIATE_TEST_SUITE_P(Payloads, PayloadSdf, ::testing::Values("t_bar", "arc"));

TEST(PayloadSdf, ConcaveRegionsAreOutside) {
  // Points in the payload frame P (config/payloads/generate_meshes.py): between the T's stem and
  // crossbar, and on the arc's inner (concave) side, are outside with the exact distance; points in
  // the middle of the tubes are inside.
  struct Probe {
    std::string payload;
    Eigen::Vector3d p_P;
    double expected;  // exact signed distance
  };
  const std::vector<Probe> probes = {
      {"t_bar", {0.3, 0.3, 0.0}, 0.24},       // crossbar face at x = 0.54
      {"t_bar", {0.3, 0.0, 0.0}, -0.03},      // stem centre line
      {"t_bar", {0.57, -0.4, 0.0}, -0.03},    // crossbar centre line
      {"arc", {0.2, 0.0, 0.0}, 0.27},         // inner face at r = 0.47
      {"arc", {0.5, 0.0, 0.0}, -0.03},        // centre line
  };
  for (const Probe& probe : probes) {
    const RobotModel& model = testing::robot(probe.payload);
    const LinkSdf& sdf = testing::robot_sdf(probe.payload).link(kEndEffectorLink);
    const CollisionShape& mesh = model.links[kEndEffectorLink].shapes.back();  // attached last
    ASSERT_TRUE(std::holds_alternative<MeshShape>(mesh.geometry));
    const Eigen::Vector3d p_L = mesh.T_parent_shape * probe.p_P;
    EXPECT_NEAR(shape_signed_distance(mesh, p_L), probe.expected, 2e-3) << probe.payload;
    EXPECT_NEAR(sdf.distance(p_L), probe.expected, 2e-3 + sdf.fine().error_bound_m()) << probe.payload;
  }
}

}  // namespace
}  // namespace porter::backend

namespace porter::backend {
namespace {

TEST(RobotSdf, ParallelBuildEqualsTheSerialOne) {
  const RobotModel& model = testing::robot("t_bar");
  const RobotSdf serial = RobotSdf::build(model, {}, 1);
  const RobotSdf parallel = RobotSdf::build(model, {}, 2);
  for (int j = 0; j < kNumLinks; ++j) {
    const LinkSdf& a = serial.link(j);
    const LinkSdf& b = parallel.link(j);
    ASSERT_EQ(a.empty(), b.empty()) << "link " << j;
    if (a.empty()) continue;
    EXPECT_EQ(a.fine().values(), b.fine().values()) << "link " << j;
    EXPECT_EQ(a.coarse().values(), b.coarse().values()) << "link " << j;
    EXPECT_EQ(a.resolution_m(), b.resolution_m()) << "link " << j;
  }
}

}  // namespace
}  // namespace porter::backend
