// Reference path preparation: joins, coincident nodes, zero-length segments, densification,
// durations, and malformed input.
#include "porter/midend/reference_path.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "synthetic_paths.hpp"

namespace porter::midend {
namespace {

MidendLimits limits() { return MidendLimits::from_robot(testing::scout_mini_piper_model()); }

planner::PathNode node(double x, double y, double yaw, double t, double q0 = 0.0) {
  planner::PathNode n;
  n.config.base = {x, y, yaw};
  n.config.q_rad = testing::carry_pose();
  n.config.q_rad[0] = q0;
  n.time_s = t;
  return n;
}

TEST(ReferencePath, EmptyAndMalformed) {
  MidendSettings s;
  EXPECT_EQ(build_reference_path({}, limits(), s).outcome, ReferenceOutcome::kEmpty);
  planner::WholeBodyPath p;
  p.segments.push_back({1, {}});
  EXPECT_EQ(build_reference_path(p, limits(), s).outcome, ReferenceOutcome::kEmpty);
  p.segments = {{2, {node(0, 0, 0, 0), node(1, 0, 0, 1)}}};
  ReferenceBuild b = build_reference_path(p, limits(), s);
  EXPECT_EQ(b.outcome, ReferenceOutcome::kMalformed);
  EXPECT_NE(b.message.find("eta"), std::string::npos);
  p.segments = {{1, {node(0, 0, 0, 0), node(std::nan(""), 0, 0, 1)}}};
  b = build_reference_path(p, limits(), s);
  EXPECT_EQ(b.outcome, ReferenceOutcome::kMalformed);
  EXPECT_NE(b.message.find("node 1"), std::string::npos);
}

TEST(ReferencePath, AllCoincidentIsNoMotion) {
  MidendSettings s;
  planner::WholeBodyPath p;
  p.segments = {{1, {node(1, 2, 0.3, 0), node(1, 2, 0.3, 1)}}, {-1, {node(1, 2, 0.3, 1), node(1, 2, 0.3, 2)}}};
  const ReferenceBuild b = build_reference_path(p, limits(), s);
  EXPECT_EQ(b.outcome, ReferenceOutcome::kNoMotion);
  EXPECT_DOUBLE_EQ(b.single.base.x_m, 1.0);
}

TEST(ReferencePath, DropsCoincidentNodesAndKeepsTimesPositive) {
  MidendSettings s;
  planner::WholeBodyPath p;
  p.segments = {{1, {node(0, 0, 0, 0), node(0, 0, 0, 0), node(0.3, 0, 0, 0.5), node(0.3, 0, 0, 0.5),
                     node(0.6, 0, 0, 1.0)}}};
  const ReferenceBuild b = build_reference_path(p, limits(), s);
  ASSERT_EQ(b.outcome, ReferenceOutcome::kOk);
  ASSERT_EQ(b.path.segments.size(), 1u);
  EXPECT_EQ(b.path.segments[0].nodes.size(), 3u);
  for (double d : b.path.segments[0].durations_s) EXPECT_GT(d, 0.0);
}

TEST(ReferencePath, ZeroLengthSegmentIsMergedAway) {
  MidendSettings s;
  planner::WholeBodyPath p;
  // forward, a reverse "segment" that does not move the base (but moves the arm), forward.
  p.segments = {{1, {node(0, 0, 0, 0), node(0.4, 0, 0, 1)}},
                {-1, {node(0.4, 0, 0, 1), node(0.4, 0, 0, 2, 0.3)}},
                {1, {node(0.4, 0, 0, 2, 0.3), node(0.8, 0, 0, 3, 0.3)}}};
  const ReferenceBuild b = build_reference_path(p, limits(), s);
  ASSERT_EQ(b.outcome, ReferenceOutcome::kOk);
  ASSERT_EQ(b.path.segments.size(), 1u);  // no gear switch is left
  EXPECT_EQ(b.path.segments[0].eta, 1);
  EXPECT_EQ(b.path.segments[0].nodes.size(), 4u);  // the arm-only node is kept
  EXPECT_NEAR(b.path.segments[0].nodes[2].q_rad[0], 0.3, 1e-12);
}

TEST(ReferencePath, JoinsSegmentsThatDoNotShareTheirSwitchNode) {
  MidendSettings s;
  planner::WholeBodyPath p;
  p.segments = {{1, {node(0, 0, 0, 0), node(0.4, 0, 0, 1)}}, {-1, {node(0.2, 0, 0, 2), node(0.0, 0.1, 0, 3)}}};
  const ReferenceBuild b = build_reference_path(p, limits(), s);
  ASSERT_EQ(b.outcome, ReferenceOutcome::kOk);
  ASSERT_EQ(b.path.segments.size(), 2u);
  EXPECT_NEAR(b.path.segments[1].nodes.front().base.x_m, 0.4, 1e-12);
  EXPECT_EQ(b.path.segments[1].eta, -1);
}

TEST(ReferencePath, DensifiesLongEdges) {
  MidendSettings s;
  s.residual_base_bound_m = 0.2;
  planner::WholeBodyPath p;
  p.segments = {{1, {node(0, 0, 0, 0), node(3.0, 0, 0, 1)}}};
  const ReferenceBuild b = build_reference_path(p, limits(), s);
  ASSERT_EQ(b.outcome, ReferenceOutcome::kOk);
  const auto& nodes = b.path.segments[0].nodes;
  EXPECT_EQ(nodes.size(), 14u);  // ceil(3.0 / (1.2 * 0.2)) = 13 pieces
  for (std::size_t i = 1; i < nodes.size(); ++i) {
    EXPECT_NEAR(nodes[i].base.x_m - nodes[i - 1].base.x_m, 3.0 / 13, 1e-12);
  }
  // Initial durations follow the speed profile (rest to rest over 3 m at initial_speed_fraction
  // of the speed and acceleration limits), not the 1 s the front-end allotted.
  const double f = s.initial_speed_fraction;
  const double v = f * limits().max_base_speed_mps();
  const double a = f * limits().wheel_radius_m * limits().wheel_alpha_max_radps2;
  double total = 0.0;
  for (double d : b.path.segments[0].durations_s) total += d;
  EXPECT_GT(total, 3.0 / v);           // never faster than the top speed
  EXPECT_LT(total, 3.0 / v + v / a + 0.05);  // trapezoid: accelerate, cruise, brake

}

TEST(ReferencePath, SyntheticThreePointTurnHasThreeSegments) {
  MidendSettings s;
  const ReferenceBuild b = build_reference_path(testing::three_point_turn(), limits(), s);
  ASSERT_EQ(b.outcome, ReferenceOutcome::kOk);
  ASSERT_EQ(b.path.segments.size(), 3u);
  EXPECT_EQ(b.path.segments[0].eta, 1);
  EXPECT_EQ(b.path.segments[1].eta, -1);
  EXPECT_EQ(b.path.segments[2].eta, 1);
  for (std::size_t i = 0; i + 1 < b.path.segments.size(); ++i) {
    const auto& a = b.path.segments[i].nodes.back();
    const auto& c = b.path.segments[i + 1].nodes.front();
    EXPECT_EQ(a.base.x_m, c.base.x_m);
    EXPECT_EQ(a.base.y_m, c.base.y_m);
  }
}

}  // namespace
}  // namespace porter::midend
