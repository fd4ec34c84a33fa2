// Reeds–Shepp wrapper: exact end poses, sampling spacing, cusps, curvature.

#include <random>

#include <gtest/gtest.h>

#include "porter/frontend/reeds_shepp.hpp"
#include "porter/planner/angle.hpp"

namespace porter::frontend {
namespace {

TEST(ReedsShepp, DriveArcStraightAndCircle) {
  const BasePose p0{1.0, 2.0, 0.3};
  const BasePose straight = drive_arc(p0, 0.0, 2.0);
  EXPECT_NEAR(straight.x_m, 1.0 + 2.0 * std::cos(0.3), 1e-12);
  EXPECT_NEAR(straight.y_m, 2.0 + 2.0 * std::sin(0.3), 1e-12);
  EXPECT_NEAR(straight.yaw_rad, 0.3, 1e-12);
  // A full left circle of radius 0.5 returns to the start.
  const BasePose circle = drive_arc(p0, 2.0, 2.0 * M_PI * 0.5);
  EXPECT_NEAR(circle.x_m, p0.x_m, 1e-9);
  EXPECT_NEAR(circle.y_m, p0.y_m, 1e-9);
  // Reverse on a left arc: heading decreases, the base moves backwards.
  const BasePose rev = drive_arc({0, 0, 0}, 1.0, -0.1);
  EXPECT_LT(rev.x_m, 0.0);
  EXPECT_NEAR(rev.yaw_rad, -0.1, 1e-12);
}

TEST(ReedsShepp, ShortestReachesTheGoalExactly) {
  ReedsShepp rs(0.4);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-3.0, 3.0), a(-M_PI, M_PI);
  for (int k = 0; k < 200; ++k) {
    const BasePose from{u(rng), u(rng), a(rng)}, to{u(rng), u(rng), a(rng)};
    const RsPath path = rs.shortest(from, to);
    ASSERT_TRUE(std::isfinite(path.length_m));
    EXPECT_GE(path.length_m + 1e-9, std::hypot(to.x_m - from.x_m, to.y_m - from.y_m));
    const BasePose end = rs_pose_at(from, path, path.length_m);
    EXPECT_NEAR(end.x_m, to.x_m, 1e-6);
    EXPECT_NEAR(end.y_m, to.y_m, 1e-6);
    EXPECT_NEAR(planner::wrap_angle_rad(end.yaw_rad - to.yaw_rad), 0.0, 1e-6);
    EXPECT_NEAR(rs.distance(from, to), path.length_m, 1e-12);
    EXPECT_NEAR(rs.distance(to, from), path.length_m, 1e-9);  // Reeds–Shepp length is symmetric
  }
}

TEST(ReedsShepp, SamplesAreCloseIncludeCuspsAndRespectTheRadius) {
  ReedsShepp rs(0.4);
  // Parallel parking: needs a direction change.
  const BasePose from{0, 0, 0}, to{0, 0.6, 0};
  const RsPath path = rs.shortest(from, to);
  ASSERT_GE(path.cusps(), 1);
  std::vector<BaseSample> samples;
  sample_rs_path(from, path, 0.1, &samples);
  ASSERT_GE(samples.size(), 3u);
  EXPECT_NEAR(samples.back().pose.y_m, 0.6, 1e-6);
  int changes = 0;
  for (std::size_t i = 1; i < samples.size(); ++i) {
    const auto& a = samples[i - 1].pose;
    const auto& b = samples[i].pose;
    const double chord = std::hypot(b.x_m - a.x_m, b.y_m - a.y_m);
    EXPECT_LE(chord, 0.1 + 1e-9);
    EXPECT_GT(chord, 0.0);
    const double dyaw = std::abs(planner::wrap_angle_rad(b.yaw_rad - a.yaw_rad));
    EXPECT_LE(dyaw, 2.0 * std::asin(std::min(1.0, chord / 0.8)) + 1e-9);
    if (i > 1 && samples[i].eta != samples[i - 1].eta) ++changes;
  }
  EXPECT_EQ(changes, path.cusps());
}

TEST(ReedsShepp, ZeroLengthPath) {
  ReedsShepp rs(0.4);
  const BasePose p{1, 1, 1};
  const RsPath path = rs.shortest(p, p);
  EXPECT_NEAR(path.length_m, 0.0, 1e-12);
  std::vector<BaseSample> s;
  sample_rs_path(p, path, 0.1, &s);
  EXPECT_EQ(s.size(), 1u);
}

}  // namespace
}  // namespace porter::frontend
