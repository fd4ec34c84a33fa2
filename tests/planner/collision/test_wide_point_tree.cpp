// The eight-wide sphere trees and the eight-lane lookups the kernel queries are built from
// (wide_point_tree.hpp, simd8.hpp): every vector lookup against its scalar counterpart. This
// file is compiled for the baseline ISA, so the lane helpers run here in their baseline form;
// the checkers' exactness tests (test_checker_reference.cpp) run the dispatched versions.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <tuple>

#include "collision_test_utils.hpp"
#include "porter/planner/collision/link_distance.hpp"
#include "porter/planner/collision/map_kernel.hpp"
#include "porter/planner/collision/pose4f.hpp"
#include "porter/planner/collision/wide_point_tree.hpp"

namespace porter::planner {
namespace {

using Key = std::tuple<float, float, float>;

std::vector<Key> sorted_keys(const std::vector<Eigen::Vector3f>& pts) {
  std::vector<Key> k;
  for (const auto& p : pts) k.emplace_back(p.x(), p.y(), p.z());
  std::sort(k.begin(), k.end());
  return k;
}

/// Every point below node slot (node, i) or in a block, for containment checks.
void collect(const WidePointTreePool& pool, std::int32_t ref, std::vector<Eigen::Vector3f>& out, int depth,
             int* max_depth) {
  *max_depth = std::max(*max_depth, depth);
  if (ref < 0) {
    const PointBlock& b = pool.blocks()[~ref];
    for (int i = 0; i < 8; ++i) out.emplace_back(b.x[i], b.y[i], b.z[i]);
    return;
  }
  const WideNode& n = pool.nodes()[ref];
  for (int i = 0; i < 8; ++i)
    if ((n.used >> i) & 1u) collect(pool, n.child[i], out, depth + 1, max_depth);
}

TEST(WidePointTree, SpheresContainTheirSubtreesAndEveryPointIsKeptOnce) {
  std::mt19937_64 rng(11);
  WidePointTreePool pool;
  for (int n : {1, 7, 8, 9, 63, 64, 65, 513, 5000}) {
    const auto pts = test::random_cloud(n, rng);
    const int t = pool.add_tree(pts);
    ASSERT_EQ(pool.tree_size(t), pts.size());
    EXPECT_EQ(sorted_keys(pool.points(t)), sorted_keys(pts)) << n;
    const WideTreeRoot& root = pool.root(t);
    std::vector<Eigen::Vector3f> below;
    int depth = 0;
    collect(pool, root.ref, below, 0, &depth);
    // The walk reaches exactly the points (spare block lanes repeat one of them).
    std::vector<Key> reached = sorted_keys(below), given = sorted_keys(pts);
    reached.erase(std::unique(reached.begin(), reached.end()), reached.end());
    given.erase(std::unique(given.begin(), given.end()), given.end());
    EXPECT_EQ(reached, given) << n;
    for (const auto& p : below) EXPECT_LE((p - Eigen::Vector3f(root.cx, root.cy, root.cz)).norm(), root.radius_m);
    // Eight children per node at most, so ceil(log8(n / 8)) levels of nodes.
    EXPECT_LE(depth, static_cast<int>(std::ceil(std::log(std::max(1.0, n / 8.0)) / std::log(8.0))) + 1) << n;
    // Every child sphere holds its subtree.
    for (std::size_t k = 0; k < pool.num_nodes(); ++k) {
      const WideNode& node = pool.nodes()[k];
      for (int i = 0; i < 8; ++i) {
        if (!((node.used >> i) & 1u)) continue;
        std::vector<Eigen::Vector3f> sub;
        int d = 0;
        collect(pool, node.child[i], sub, 0, &d);
        for (const auto& p : sub)
          ASSERT_LE((p - Eigen::Vector3f(node.cx[i], node.cy[i], node.cz[i])).norm(), node.r[i]);
      }
    }
  }
  WidePointTreePool empty;
  const int e = empty.add_tree({});
  EXPECT_EQ(empty.tree_size(e), 0u);
  EXPECT_TRUE(empty.points(e).empty());
  EXPECT_FALSE(wide_tree_any(
      empty, e, [](const WideNode&) { return 0xffu; }, [](const PointBlock&) { return true; }));
}

TEST(WidePointTree, PrunedWalkFindsAPointInABallExactlyWhenOneIsThere) {
  std::mt19937_64 rng(5);
  WidePointTreePool pool;
  const auto pts = test::random_cloud(3000, rng);
  const int t = pool.add_tree(pts);
  int hits = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const Eigen::Vector3f c(static_cast<float>(test::uniform(rng, -1.2, 1.2)),
                            static_cast<float>(test::uniform(rng, -0.4, 0.5)),
                            static_cast<float>(test::uniform(rng, -0.2, 2.2)));
    const float r = static_cast<float>(test::uniform(rng, 0.01, 0.08));
    bool brute = false;
    for (const auto& p : pts) brute = brute || (p - c).norm() <= r;
    const bool walk = wide_tree_any(
        pool, t,
        [&](const WideNode& n) {
          std::uint32_t open = 0;
          for (int i = 0; i < 8; ++i)
            if ((Eigen::Vector3f(n.cx[i], n.cy[i], n.cz[i]) - c).norm() <= n.r[i] + r) open |= 1u << i;
          return open;
        },
        [&](const PointBlock& b) {
          for (int i = 0; i < 8; ++i)
            if ((Eigen::Vector3f(b.x[i], b.y[i], b.z[i]) - c).norm() <= r) return true;
          return false;
        });
    EXPECT_EQ(walk, brute) << trial;
    hits += brute;
  }
  EXPECT_GT(hits, 20);   // both answers exercised
  EXPECT_LT(hits, 280);
}

TEST(Simd8, LaneMaskAndTruncationMatchScalar) {
  const v8i m{-1, 0, 0, -1, 0, 0, 0, -1};
  EXPECT_EQ(lane_mask(m), 0x89u);
  const v8f x{-1.5f, -0.5f, 0.f, 0.5f, 1.5f, 2.99f, 1e6f, -7.f};
  const v8i t = v8_trunc(x);
  for (int i = 0; i < 8; ++i) EXPECT_EQ(t[i], static_cast<int>(x[i]));
}

TEST(Simd8, Transpose8x4TurnsRowsIntoColumns) {
  v4f rows[8];
  for (int i = 0; i < 8; ++i)
    rows[i] = v4f{static_cast<float>(10 * i), static_cast<float>(10 * i + 1), static_cast<float>(10 * i + 2),
                  static_cast<float>(10 * i + 3)};
  v8f x, y, z, w;
  transpose8x4(rows, &x, &y, &z, &w);
  for (int i = 0; i < 8; ++i) {
    EXPECT_EQ(x[i], 10.f * i);
    EXPECT_EQ(y[i], 10.f * i + 1.f);
    EXPECT_EQ(z[i], 10.f * i + 2.f);
    EXPECT_EQ(w[i], 10.f * i + 3.f);
  }
}

TEST(Simd8, SplatPoseLanesApplyThePose4fToEveryLaneEvenInPlace) {
  std::mt19937_64 rng(4);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.3, -0.5, 0.8).normalized()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(0.4, -1.2, 2.5);
  const Pose4f P(T);
  const PoseLanes P8 = PoseLanes::splat(P);
  alignas(32) float x[8], y[8], z[8];
  for (int i = 0; i < 8; ++i) {
    x[i] = static_cast<float>(test::uniform(rng, -2.0, 2.0));
    y[i] = static_cast<float>(test::uniform(rng, -2.0, 2.0));
    z[i] = static_cast<float>(test::uniform(rng, -2.0, 2.0));
  }
  v8f ox, oy, oz;
  P8.apply(v8f_load(x), v8f_load(y), v8f_load(z), &ox, &oy, &oz);
  v8f ix = v8f_load(x), iy = v8f_load(y), iz = v8f_load(z);
  P8.apply(ix, iy, iz, &ix, &iy, &iz);  // outputs aliasing the inputs
  for (int i = 0; i < 8; ++i) {
    const v4f r = P.apply(x[i], y[i], z[i]);
    const Eigen::Vector3d e = T * Eigen::Vector3d(x[i], y[i], z[i]);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(r[k], e[k], 1e-5);
    EXPECT_NEAR(ox[i], r[0], 1e-5);
    EXPECT_NEAR(oy[i], r[1], 1e-5);
    EXPECT_NEAR(oz[i], r[2], 1e-5);
    EXPECT_EQ(ix[i], ox[i]);
    EXPECT_EQ(iy[i], oy[i]);
    EXPECT_EQ(iz[i], oz[i]);
  }
}

// Eight different poses, one per lane: every operation agrees lane by lane with Pose4f's.
TEST(Simd8, PoseLanesAgreeWithPose4fLaneByLane) {
  std::mt19937_64 rng(6);
  auto random_pose = [&] {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    const Eigen::Vector3d axis(test::uniform(rng, -1, 1), test::uniform(rng, -1, 1), test::uniform(rng, -1, 1));
    T.linear() = Eigen::AngleAxisd(test::uniform(rng, -3, 3), axis.normalized()).toRotationMatrix();
    T.translation() = Eigen::Vector3d(test::uniform(rng, -2, 2), test::uniform(rng, -2, 2), test::uniform(rng, -2, 2));
    return Pose4f(T);
  };
  Pose4f A[8], B[8];
  PoseLanes a, b;
  alignas(32) float x[8], y[8], z[8], c[8], s[8];
  for (int i = 0; i < 8; ++i) {
    A[i] = random_pose();
    B[i] = random_pose();
    a.set_lane(i, A[i]);
    b.set_lane(i, B[i]);
    x[i] = static_cast<float>(test::uniform(rng, -2.0, 2.0));
    y[i] = static_cast<float>(test::uniform(rng, -2.0, 2.0));
    z[i] = static_cast<float>(test::uniform(rng, -2.0, 2.0));
    const double angle = test::uniform(rng, -3.0, 3.0);
    c[i] = static_cast<float>(std::cos(angle));
    s[i] = static_cast<float>(std::sin(angle));
  }
  PoseLanes ab, az;
  PoseLanes::compose(a, b, ab);
  PoseLanes::rotated_z(a, v8f_load(c), v8f_load(s), az);
  v8f px, py, pz, qx, qy, qz;
  a.apply(v8f_load(x), v8f_load(y), v8f_load(z), &px, &py, &pz);
  a.apply_inverse(px, py, pz, &qx, &qy, &qz);
  for (int i = 0; i < 8; ++i) {
    const Pose4f got_ab = ab.lane(i), want_ab = A[i] * B[i];
    const Pose4f got_az = az.lane(i), want_az = A[i].rotated_z(c[i], s[i]);
    EXPECT_LT((got_ab.isometry().matrix() - want_ab.isometry().matrix()).cwiseAbs().maxCoeff(), 1e-5) << i;
    EXPECT_LT((got_az.isometry().matrix() - want_az.isometry().matrix()).cwiseAbs().maxCoeff(), 1e-5) << i;
    EXPECT_EQ(a.lane(i).isometry().matrix(), A[i].isometry().matrix()) << i;  // set_lane / lane round trip
    const v4f p = A[i].apply(x[i], y[i], z[i]);
    EXPECT_NEAR(px[i], p[0], 1e-5);
    EXPECT_NEAR(py[i], p[1], 1e-5);
    EXPECT_NEAR(pz[i], p[2], 1e-5);
    EXPECT_NEAR(qx[i], x[i], 1e-5);  // the inverse undoes the pose
    EXPECT_NEAR(qy[i], y[i], 1e-5);
    EXPECT_NEAR(qz[i], z[i], 1e-5);
  }
}

TEST(Simd8, MapKernelLaneLookupsMatchTheScalarOnes) {
  OccupancyGrid g({0.3, -0.2, 0.0}, 0.05, {40, 30, 20});
  std::mt19937_64 rng(9);
  for (int k = 0; k < 60; ++k)
    g.set(static_cast<int>(rng() % 40), static_cast<int>(rng() % 30), static_cast<int>(rng() % 20));
  MapKernel mk(MapKernelSettings{}, 6, 4);
  mk.set_map(g);
  const Eigen::Vector3i n = mk.padded_dims();
  int clear_nonzero = 0, clear_lanes = 0, arm_set = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    alignas(32) float x[8], y[8], z[8];
    for (int i = 0; i < 8; ++i) {
      // Points inside the padded array (the arm-bit precondition) and, for the clearance, also
      // around it (outside the grid's region reads 0).
      x[i] = static_cast<float>(test::uniform(rng, 1.0, n.x() - 1.0));
      y[i] = static_cast<float>(test::uniform(rng, 1.0, n.y() - 1.0));
      z[i] = static_cast<float>(test::uniform(rng, 1.0, n.z() - 1.0));
    }
    alignas(32) float need[8];
    for (int i = 0; i < 8; ++i) need[i] = static_cast<float>(test::uniform(rng, 0.0, 30.0));
    const v8f ux = v8f_load(x), uy = v8f_load(y), uz = v8f_load(z);
    // clear8() against its scalar reference, except within float rounding of a tie (the lane
    // test compares squares, the scalar one takes a square root).
    auto expect_clear8_matches = [&](std::uint32_t clear) {
      for (int i = 0; i < 8; ++i) {
        const float c = mk.clearance_units(x[i], y[i], z[i]);
        if (std::abs(c - need[i]) < 1e-3f) continue;
        ASSERT_EQ(((clear >> i) & 1u) != 0, need[i] < c) << x[i] << " " << y[i] << " " << z[i] << " need " << need[i];
        clear_nonzero += c > 0.f;
        clear_lanes += (clear >> i) & 1u;
      }
    };
    expect_clear8_matches(mk.clear8(ux, uy, uz, v8f_load(need)));
    const std::uint32_t bits = mk.arm_bits8(ux, uy, uz);
    for (int i = 0; i < 8; ++i) {
      ASSERT_EQ(((bits >> i) & 1u) != 0,
                mk.arm_bit(static_cast<int>(x[i]), static_cast<int>(y[i]), static_cast<int>(z[i])));
      arm_set += (bits >> i) & 1u;
    }
    for (int i = 0; i < 8; ++i) {
      x[i] = static_cast<float>(test::uniform(rng, -20.0, n.x() + 20.0));
      y[i] = static_cast<float>(test::uniform(rng, -20.0, n.y() + 20.0));
      z[i] = static_cast<float>(test::uniform(rng, -20.0, n.z() + 20.0));
    }
    expect_clear8_matches(mk.clear8(v8f_load(x), v8f_load(y), v8f_load(z), v8f_load(need)));
  }
  EXPECT_GT(clear_nonzero, 1000);
  EXPECT_GT(clear_lanes, 1000);
  EXPECT_GT(arm_set, 100);
  // A NaN coordinate or need is never clear.
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const v8f mid = v8f_splat(0.5f * static_cast<float>(n.x()));
  EXPECT_EQ(mk.clear8(v8f{nan, 10, 10, 10, 10, 10, 10, 10}, mid, mid, v8f{0, 0, nan, 0, 0, 0, 0, 0}) & 5u, 0u);
}

TEST(Simd8, DistanceGridClearOf8MatchesClearOf) {
  CollisionShape box;
  box.geometry = Box{Eigen::Vector3d(0.3, 0.1, 0.2)};
  box.T_parent_shape.translation() = Eigen::Vector3d(0.05, -0.02, 0.1);
  CollisionShape cyl;
  cyl.geometry = Cylinder{0.04, 0.3};
  cyl.T_parent_shape.translation() = Eigen::Vector3d(-0.1, 0.05, 0.3);
  const DistanceGrid grid({box, cyl}, 0.01, 0.05);
  std::mt19937_64 rng(4);
  int clear = 0, total = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    alignas(32) float x[8], y[8], z[8], d[8];
    for (int i = 0; i < 8; ++i) {
      x[i] = static_cast<float>(test::uniform(rng, -0.5, 0.5));
      y[i] = static_cast<float>(test::uniform(rng, -0.4, 0.4));
      z[i] = static_cast<float>(test::uniform(rng, -0.3, 0.7));
      d[i] = static_cast<float>(test::uniform(rng, -0.02, 0.3));
    }
    const std::uint32_t m = grid.clear_of8(v8f_load(x), v8f_load(y), v8f_load(z), v8f_load(d));
    for (int i = 0; i < 8; ++i) {
      const bool scalar = grid.clear_of(Eigen::Vector3f(x[i], y[i], z[i]), d[i]);
      ASSERT_EQ(((m >> i) & 1u) != 0, scalar) << x[i] << " " << y[i] << " " << z[i] << " d " << d[i];
      clear += scalar;
      ++total;
    }
  }
  EXPECT_GT(clear, total / 10);  // both answers exercised, inside and outside the grid's box
  EXPECT_LT(clear, total - total / 10);
}

// The box-union bound never exceeds the exact distance (with more shapes than boxes, so some
// are merged, and with a rotated shape whose box is looser than it), and far from the link it
// clears what the exact distance clears.
TEST(Simd8, BoxUnionBoundIsALowerBoundOfTheLinkDistance) {
  std::vector<CollisionShape> shapes;
  std::mt19937_64 rng(12);
  for (int k = 0; k < BoxUnionBound::kMaxBoxes + 3; ++k) {
    CollisionShape s;
    if (k % 2 == 0) {
      s.geometry = Box{Eigen::Vector3d(test::uniform(rng, 0.02, 0.3), test::uniform(rng, 0.02, 0.2), test::uniform(rng, 0.02, 0.1))};
    } else {
      s.geometry = Cylinder{test::uniform(rng, 0.01, 0.06), test::uniform(rng, 0.05, 0.3)};
    }
    s.T_parent_shape.translation() = Eigen::Vector3d(test::uniform(rng, -0.4, 0.4), test::uniform(rng, -0.3, 0.3), test::uniform(rng, 0.0, 0.6));
    s.T_parent_shape.linear() = Eigen::AngleAxisd(test::uniform(rng, -3.0, 3.0), Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    shapes.push_back(s);
  }
  const BoxUnionBound bound(shapes);
  const LinkDistance exact(shapes);
  EXPECT_EQ(bound.num_boxes(), BoxUnionBound::kMaxBoxes);
  int clear = 0, exact_clear_far = 0, clear_far = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    alignas(32) float x[8], y[8], z[8], d[8];
    for (int i = 0; i < 8; ++i) {
      x[i] = static_cast<float>(test::uniform(rng, -1.5, 1.5));
      y[i] = static_cast<float>(test::uniform(rng, -1.5, 1.5));
      z[i] = static_cast<float>(test::uniform(rng, -1.0, 1.8));
      d[i] = static_cast<float>(test::uniform(rng, 0.0, 0.8));
    }
    const std::uint32_t m = bound.clear_of8(v8f_load(x), v8f_load(y), v8f_load(z), v8f_load(d));
    for (int i = 0; i < 8; ++i) {
      const double e = exact.signed_distance(Eigen::Vector3d(x[i], y[i], z[i]));
      if ((m >> i) & 1u) {
        ASSERT_GT(e, d[i]) << x[i] << " " << y[i] << " " << z[i] << " d " << d[i];
        ++clear;
      }
      if (e > d[i] + 0.5) {  // far: the boxes are at most ~0.35 m looser than the shapes here
        ++exact_clear_far;
        clear_far += (m >> i) & 1u;
      }
    }
  }
  EXPECT_GT(clear, 2000);
  EXPECT_EQ(clear_far, exact_clear_far);
  // NaN points or distances are never clear; a negative distance neither.
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(bound.clear_of8(v8f{nan, 5, 5, 5, 5, 5, 5, 5}, v8f_splat(5.f), v8f_splat(5.f),
                            v8f{0.1f, nan, -1.f, 0.1f, 0.1f, 0.1f, 0.1f, 0.1f}) & 7u,
            0u);
}

}  // namespace
}  // namespace porter::planner
