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


// Step 8: edges grouped into pieces. Invariants on a path with reversals and arm motion: knots
// cover the nodes in order, each piece respects the caps, the edge next to a gear switch is
// alone, interior node fractions are strictly increasing multiples of 2 / kappa inside (0, 1),
// and piece durations are the sums of the edge durations (the one-edge-per-piece build).
TEST(ReferencePath, GroupsEdgesIntoPiecesWithinTheCaps) {
  MidendSettings s;
  MidendSettings single = s;
  single.max_edges_per_piece = 1;
  const planner::WholeBodyPath path = testing::three_point_turn();
  const ReferenceBuild b = build_reference_path(path, limits(), s);
  const ReferenceBuild one = build_reference_path(path, limits(), single);
  ASSERT_EQ(b.outcome, ReferenceOutcome::kOk);
  ASSERT_EQ(one.outcome, ReferenceOutcome::kOk);
  ASSERT_EQ(b.path.segments.size(), one.path.segments.size());
  EXPECT_LT(b.path.num_pieces(), one.path.num_pieces());
  const int num_segments = static_cast<int>(b.path.segments.size());
  for (int si = 0; si < num_segments; ++si) {
    const ReferenceSegment& seg = b.path.segments[si];
    const ReferenceSegment& ref = one.path.segments[si];
    ASSERT_EQ(seg.nodes.size(), ref.nodes.size());
    ASSERT_EQ(ref.num_pieces() + 1, static_cast<int>(ref.nodes.size()));
    ASSERT_EQ(static_cast<int>(seg.knots.size()), seg.num_pieces() + 1);
    ASSERT_EQ(seg.intervals.size(), seg.durations_s.size());
    EXPECT_EQ(seg.knots.front(), 0);
    EXPECT_EQ(seg.knots.back(), static_cast<int>(seg.nodes.size()) - 1);
    for (int p = 0; p < seg.num_pieces(); ++p) {
      const int m = seg.edges_in_piece(p);
      ASSERT_GE(m, 1);
      EXPECT_LE(m, s.max_edges_per_piece);
      double length = 0.0, arm = 0.0, edge_sum = 0.0;
      for (int e = seg.knots[p]; e < seg.knots[p + 1]; ++e) {
        length += std::hypot(seg.nodes[e + 1].base.x_m - seg.nodes[e].base.x_m,
                             seg.nodes[e + 1].base.y_m - seg.nodes[e].base.y_m);
        arm += (seg.nodes[e + 1].q_rad - seg.nodes[e].q_rad).norm();
        edge_sum += ref.durations_s[e];
      }
      if (m > 1) {
        EXPECT_LE(length, s.piece_length_m + 1e-12);
        EXPECT_LE(arm, s.piece_arm_motion_rad + 1e-12);
      }
      EXPECT_NEAR(seg.durations_s[p], edge_sum, 1e-12);
      const int kappa = seg.intervals[p];
      EXPECT_EQ(kappa % 2, 0);
      EXPECT_GE(kappa, std::max(s.samples_per_piece, s.samples_per_edge * m));
      // At most max_sample_interval_s between samples (below the 128-interval cap).
      EXPECT_GE(kappa, std::min(static_cast<double>(ReferenceSegment::kMaxSamplesPerPiece),
                                seg.durations_s[p] / s.max_sample_interval_s - 1e-9));
      EXPECT_EQ(seg.fraction_in_piece(p, 0), 0.0);
      EXPECT_EQ(seg.fraction_in_piece(p, m), 1.0);
      for (int k = 1; k < m; ++k) {
        const double f = seg.fraction_in_piece(p, k);
        EXPECT_GT(f, seg.fraction_in_piece(p, k - 1));
        EXPECT_LT(f, 1.0);
        EXPECT_NEAR(f * kappa / 2.0, std::round(f * kappa / 2.0), 1e-12);
      }
    }
    if (si > 0) {
      EXPECT_EQ(seg.edges_in_piece(0), 1);
      // The gear factor multiplies the piece's own kappa (samples_per_piece, or the time-based
      // minimum when the piece is long).
      const int by_time = static_cast<int>(std::ceil(seg.durations_s.front() / s.max_sample_interval_s));
      const int base = std::max(s.samples_per_piece, by_time);
      EXPECT_EQ(seg.intervals.front(), std::min(base * s.gear_sample_factor + (base * s.gear_sample_factor) % 2,
                                                ReferenceSegment::kMaxSamplesPerPiece));
    }
    if (si + 1 < num_segments) {
      EXPECT_EQ(seg.edges_in_piece(seg.num_pieces() - 1), 1);
    }
  }
}

}  // namespace
}  // namespace porter::midend
