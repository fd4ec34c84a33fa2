// The J_s fast paths against their slow references: the lean t* scan
// (SvsdfSettings::lean_scan: smaller look-up level, per-interval Lipschitz skip) returns exactly
// what the reference scan returns; the SDF prefilter level (SvsdfSafetySettings::sdf_prefilter)
// leaves J_s and its gradient unchanged; the swept body's per-interval motion bounds are bounds;
// the prefilter's candidate lists (SvsdfSafetySettings::prefilter_slack_m) leave J_s, its gradient
// and every count unchanged.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "backend_fixtures.hpp"
#include "porter/backend/svsdf.hpp"
#include "porter/backend/svsdf_safety_term.hpp"
#include "porter/backend/swept_body.hpp"

namespace porter::backend {
namespace {

using testing::point_near;

constexpr char kPayload[] = "t_bar";

TEST(SweptBodyMotionBound, BoundsTheMotionOfTheLinkBetweenSamples) {
  const RobotModel& model = testing::robot(kPayload);
  SweptBody body(model);
  body.reset(testing::random_trajectory(model, 5, testing::RandomTrajectoryOptions::with_pieces(4)));
  const int n = body.num_samples();
  for (int j = 0; j < kNumLinks; ++j) {
    const Eigen::AlignedBox3d& b = model.links[static_cast<std::size_t>(j)].bounds;
    if (b.isEmpty()) continue;
    for (int k = 1; k < n; ++k) {
      const double one = body.motion_bound_m(j, k - 1, k);
      EXPECT_GE(one, 0.0);
      EXPECT_LE(one, body.max_step_m(j) + 1e-12);
    }
    // Over spans: no corner of the link's box moves farther between two samples than the bound.
    for (int k = 0; k + 7 < n; k += 5) {
      const int to = k + 7;
      const InversePose& a = body.sample_pose(k, j);
      const InversePose& c = body.sample_pose(to, j);
      for (int corner = 0; corner < 8; ++corner) {
        // Points of the link's bounding sphere (the geometry the bound is for).
        const Eigen::Vector3d dir = Eigen::Vector3d(corner & 1 ? 1 : -1, corner & 2 ? 1 : -1, corner & 4 ? 1 : -1).normalized();
        const Link& link = model.links[static_cast<std::size_t>(j)];
        const Eigen::Vector3d p_L = link.bounding_center + link.bounding_radius_m * dir;
        const Eigen::Vector3d wa = a.R_L_W.transpose() * (p_L - a.t_L_W);
        const Eigen::Vector3d wc = c.R_L_W.transpose() * (p_L - c.t_L_W);
        EXPECT_LE((wa - wc).norm(), body.motion_bound_m(j, k, to) + 1e-9);
      }
    }
    // samples_within_motion against a linear walk.
    for (int k = 0; k < n; k += 3) {
      for (double budget : {0.0, 0.005, 0.03, 0.2, 5.0}) {
        const int last = std::min(n - 1, k + 40);
        int expected = 0;
        while (k + expected + 1 <= last && body.motion_bound_m(j, k, k + expected + 1) < budget) ++expected;
        EXPECT_EQ(body.samples_within_motion(j, k, last, budget), expected) << "link " << j << " k " << k;
      }
    }
  }
}

/// Every field of a search result the callers read. A far result (g only known to exceed the
/// cap: the scan stopped looking there) is an upper bound from whichever samples were looked up;
/// callers use it only as "beyond the cap", so only that is compared. A coarse-only result (the
/// base's: the window centre and band) is compared in full.
void expect_same(const SvsdfValue& a, const SvsdfValue& b, double cap, const std::string& what) {
  EXPECT_EQ(a.far, b.far) << what;
  if (a.far && b.far && std::isfinite(cap)) {
    EXPECT_GT(a.g, cap) << what;
    EXPECT_GT(b.g, cap) << what;
    return;
  }
  EXPECT_EQ(a.g, b.g) << what;
  EXPECT_EQ(a.t_star_s, b.t_star_s) << what;
  EXPECT_EQ(a.band_lo_s, b.band_lo_s) << what;
  EXPECT_EQ(a.band_hi_s, b.band_hi_s) << what;
  if (a.far) return;
  EXPECT_EQ(a.grad_p, b.grad_p) << what;
  EXPECT_EQ(a.d_config, b.d_config) << what;
  EXPECT_EQ(a.on_window_edge, b.on_window_edge) << what;
}

TEST(SvsdfLeanScan, ReturnsExactlyWhatTheReferenceScanReturns) {
  const RobotModel& model = testing::robot(kPayload);
  const RobotSdf& sdf = testing::robot_sdf(kPayload);
  std::mt19937 rng(3);
  std::int64_t lean_lookups = 0, reference_lookups = 0, compared = 0, near = 0;
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    SweptBody body(model);
    body.reset(testing::random_trajectory(model, seed, testing::RandomTrajectoryOptions::with_pieces(4)));
    SvsdfSettings lean_settings;
    SvsdfSettings reference_settings;
    reference_settings.lean_scan = false;
    SvsdfEvaluator lean(sdf, body, lean_settings), reference(sdf, body, reference_settings);
    for (int n = 0; n < 160; ++n) {
      const int link = n % kNumLinks;
      const Eigen::Vector3d p = point_near(body, link, rng, n % 2 ? 0.05 : 0.4);
      SearchOptions options;
      switch (n % 5) {
        case 0: break;                                      // plain
        case 1: options.skip_above = 0.12; break;           // the safety term's cap
        case 2: options.band = 0.02; break;                 // the base's tie band
        case 3: options.coarse_only = true; options.band = 0.02; options.prune_above_skip = false; break;
        default: options.skip_above = 0.05; options.hint_t_s = 0.3 * body.duration_s(); break;
      }
      const double lo = link == 0 ? 0.0 : 0.25 * body.duration_s();
      const double hi = link == 0 ? body.duration_s() : 0.9 * body.duration_s();
      SvsdfValue a, b;
      lean.search(link, p, lo, hi, a, options);
      reference.search(link, p, lo, hi, b, options);
      expect_same(a, b, options.skip_above, "seed " + std::to_string(seed) + " point " + std::to_string(n));
      ++compared;
      near += !a.far;
    }
    lean_lookups += lean.stats().samples_evaluated;
    reference_lookups += reference.stats().samples_evaluated;
  }
  EXPECT_GT(near, compared / 4);  // the refined path is exercised, not only the far one
  // The fast path is taken: fewer samples looked up.
  EXPECT_LT(lean_lookups, reference_lookups);
}

TEST(SvsdfSafetyTermSdfPrefilter, LeavesTheCostAndGradientUnchanged) {
  const RobotModel& model = testing::robot(kPayload);
  const RobotSdf& sdf = testing::robot_sdf(kPayload);
  const Trajectory traj = testing::random_trajectory(model, 21, testing::RandomTrajectoryOptions::with_pieces(3));
  SweptBody body(model);
  body.reset(traj);
  // Points at all distances from the swept volume: inside, within the margin, just beyond it.
  std::mt19937 rng(17);
  std::vector<ObstaclePoint> points;
  for (int n = 0; n < 600; ++n) {
    const double spread = n % 3 == 0 ? 0.03 : (n % 3 == 1 ? 0.15 : 0.35);
    points.push_back({point_near(body, n % kNumLinks, rng, spread), kAllLinks});
  }
  const Trajectory other = testing::perturbed(traj, 1, 0, 3, 0.02);
  for (bool filter : {true, false}) {
    SvsdfSafetySettings fast_settings;
    fast_settings.weight = 1.0;
    fast_settings.kc.kinematic_filter = filter;
    SvsdfSafetySettings reference_settings = fast_settings;
    reference_settings.sdf_prefilter = false;
    reference_settings.kc.svsdf.lean_scan = false;
    SvsdfSafetyTerm fast(model, sdf, fast_settings), reference(model, sdf, reference_settings);
    fast.set_points(points);
    reference.set_points(points);
    // A refresh point, then a replay on a nearby trajectory, then back.
    for (const Trajectory* t : {&traj, &other, &traj}) {
      TrajectoryGradient ga, gb;
      ga.reset(t->num_pieces());
      gb.reset(t->num_pieces());
      SafetyStats sa, sb;
      const double ca = fast.evaluate(*t, ga, &sa);
      const double cb = reference.evaluate(*t, gb, &sb);
      ASSERT_GT(sb.violations, 10);
      ASSERT_GT(sb.inside, 0);
      EXPECT_NEAR(ca, cb, 1e-10 * (1.0 + std::abs(cb)));
      EXPECT_EQ(sa.violations, sb.violations);
      EXPECT_EQ(sa.inside, sb.inside);
      // The SDF level prunes pairs the box levels let through.
      EXPECT_LT(sa.link_queries, sb.link_queries);
      for (int i = 0; i < t->num_pieces(); ++i) {
        const double scale = 1.0 + gb.coeffs(i).cwiseAbs().maxCoeff();
        EXPECT_LE((ga.coeffs(i) - gb.coeffs(i)).cwiseAbs().maxCoeff(), 1e-10 * scale) << "piece " << i;
        EXPECT_NEAR(ga.duration(i), gb.duration(i), 1e-10 * (1.0 + std::abs(gb.duration(i)))) << "piece " << i;
      }
    }
  }
}

TEST(SvsdfSafetyTermCandidateLists, LeaveTheCostGradientAndCountsUnchanged) {
  const RobotModel& model = testing::robot(kPayload);
  const RobotSdf& sdf = testing::robot_sdf(kPayload);
  const Trajectory traj = testing::random_trajectory(model, 31, testing::RandomTrajectoryOptions::with_pieces(4));
  SweptBody body(model);
  body.reset(traj);
  std::mt19937 rng(29);
  std::vector<ObstaclePoint> points;
  for (int n = 0; n < 900; ++n) {
    const double spread = n % 3 == 0 ? 0.03 : (n % 3 == 1 ? 0.15 : 0.4);
    points.push_back({point_near(body, n % kNumLinks, rng, spread), kAllLinks});
  }
  // Moves of a few millimetres (the lists are read), 8 cm of one piece's position (that piece's
  // pairs search the index again), a longer piece, and back.
  const Trajectory tiny = testing::perturbed(traj, 1, 0, 0, 0.003);
  const Trajectory tiny2 = testing::perturbed(tiny, 2, 0, 1, -0.004);
  const Trajectory moved = testing::perturbed(traj, 2, 0, 0, 0.08);
  const Trajectory longer = testing::perturbed(traj, 0, -1, 0, 0.3);
  SvsdfSafetySettings fast_settings;
  fast_settings.weight = 1.0;
  SvsdfSafetySettings reference_settings = fast_settings;
  reference_settings.prefilter_slack_m = 0.0;
  SvsdfSafetyTerm fast(model, sdf, fast_settings), reference(model, sdf, reference_settings);
  fast.set_points(points);
  reference.set_points(points);
  std::int64_t searched_before = 0;
  int step = 0;
  for (const Trajectory* t : {&traj, &tiny, &tiny2, &moved, &tiny, &longer, &traj}) {
    TrajectoryGradient ga, gb;
    ga.reset(t->num_pieces());
    gb.reset(t->num_pieces());
    SafetyStats sa, sb;
    const double ca = fast.evaluate(*t, ga, &sa);
    const double cb = reference.evaluate(*t, gb, &sb);
    ASSERT_GT(sb.violations, 10);
    EXPECT_EQ(sa.candidate_points, sb.candidate_points) << "step " << step;
    EXPECT_EQ(sa.link_queries, sb.link_queries) << "step " << step;
    EXPECT_EQ(sa.violations, sb.violations) << "step " << step;
    EXPECT_EQ(sa.inside, sb.inside) << "step " << step;
    EXPECT_NEAR(ca, cb, 1e-12 * (1.0 + std::abs(cb))) << "step " << step;
    for (int i = 0; i < t->num_pieces(); ++i) {
      const double scale = 1.0 + gb.coeffs(i).cwiseAbs().maxCoeff();
      EXPECT_LE((ga.coeffs(i) - gb.coeffs(i)).cwiseAbs().maxCoeff(), 1e-12 * scale) << "step " << step << " piece " << i;
      EXPECT_NEAR(ga.duration(i), gb.duration(i), 1e-12 * (1.0 + std::abs(gb.duration(i)))) << "step " << step;
    }
    const std::int64_t searched = fast.pairs_searched() - searched_before;
    searched_before = fast.pairs_searched();
    if (step == 1 || step == 2) {
      EXPECT_EQ(searched, 0) << "millimetre moves read the lists, step " << step;
    }
    if (step == 3) {
      EXPECT_GT(searched, 0) << "an 8 cm move searches the index again";
    }
    ++step;
  }
  EXPECT_GT(fast.pairs_reused(), fast.pairs_searched()) << "the fast path is taken";
  EXPECT_EQ(reference.pairs_reused(), 0);
}

}  // namespace
}  // namespace porter::backend
