// Piece windows (piece_window.hpp) on the mid-end's synthetic paths: which pieces a window holds,
// and the window's problem against the whole problem's cost (the held pieces' terms are constants).
// The same on a real warm start, with J_s and the kernel check: warm_start_gradient_test.cpp.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "porter/backend/piece_window.hpp"
#include "porter/midend/midend.hpp"
#include "porter/midend/midend_problem.hpp"
#include "porter/midend/reference_path.hpp"
#include "synthetic_paths.hpp"

namespace porter::backend {
namespace {

/// A reference with segments of the given piece counts (still where `still` says); only the
/// piece counts and the still flags matter to the window arithmetic.
midend::ReferencePath counts(const std::vector<int>& pieces, const std::vector<bool>& still = {}) {
  midend::ReferencePath r;
  for (std::size_t s = 0; s < pieces.size(); ++s) {
    midend::ReferenceSegment seg;
    seg.base_still = s < still.size() && still[s];
    seg.durations_s.assign(static_cast<std::size_t>(pieces[s]), 1.0);
    r.segments.push_back(seg);
  }
  return r;
}

std::vector<bool> flags(int n, const std::vector<int>& set) {
  std::vector<bool> f(static_cast<std::size_t>(n), false);
  for (int i : set) f[static_cast<std::size_t>(i)] = true;
  return f;
}

TEST(PieceWindows, RunsOfFlaggedPiecesGrowMergeAndStayInTheirSegment) {
  const midend::ReferencePath one = counts({20});
  // Two runs, grown by one piece each side.
  EXPECT_EQ(windows_around(flags(20, {3, 4, 12}), one, 1),
            (std::vector<PieceWindow>{{2, 6}, {11, 14}}));
  // Grown by two they touch (6 .. 10 and 10 .. 15): merged.
  EXPECT_EQ(windows_around(flags(20, {3, 4, 12}), one, 3), (std::vector<PieceWindow>{{0, 8}, {9, 16}}));
  EXPECT_EQ(windows_around(flags(20, {5, 9}), one, 2), (std::vector<PieceWindow>{{3, 12}}));
  // Clipped at the trajectory's ends.
  EXPECT_EQ(windows_around(flags(20, {0, 19}), one, 1), (std::vector<PieceWindow>{{0, 2}, {18, 20}}));
  EXPECT_TRUE(windows_around(flags(20, {}), one, 1).empty());
  // Segments 0 .. 4, 5 .. 11, 12 .. 14: a run across a gear switch is cut there, each part grown
  // within its own segment only.
  const midend::ReferencePath three = counts({5, 7, 3});
  EXPECT_EQ(windows_around(flags(15, {4, 5}), three, 1), (std::vector<PieceWindow>{{3, 5}, {5, 7}}));
  EXPECT_EQ(windows_around(flags(15, {13}), three, 4), (std::vector<PieceWindow>{{12, 15}}));
  // A flagged piece on a still segment: no window (the whole problem).
  const midend::ReferencePath with_still = counts({8, 2}, {false, true});
  EXPECT_TRUE(windows_around(flags(10, {2, 9}), with_still, 1).empty());
  EXPECT_EQ(windows_around(flags(10, {7}), with_still, 1), (std::vector<PieceWindow>{{6, 8}}));
  // Growing stops at the segment.
  EXPECT_EQ(grow_window({6, 8}, three, 1), (PieceWindow{5, 9}));
  EXPECT_EQ(grow_window({5, 12}, three, 3), (PieceWindow{5, 12}));
}

/// The decision vector and trajectory of a whole mid-end solve on `path`.
struct Solved {
  midend::MidendSolution solution;
  Trajectory trajectory;
};
Solved solve(const planner::WholeBodyPath& path) {
  const midend::MidEnd mid(midend::testing::scout_mini_piper_model());
  const midend::MidendResult r = mid.solve(path, planner::Deadline(30.0));
  if (!r.trajectory || !r.solution) throw std::runtime_error("the mid-end did not solve the synthetic path");
  return {*r.solution, *r.trajectory};
}

/// The first piece and the piece count of the reference's longest moving segment.
PieceWindow longest_moving_segment(const midend::ReferencePath& r) {
  PieceWindow best;
  int first = 0;
  for (const midend::ReferenceSegment& seg : r.segments) {
    if (!seg.base_still && seg.num_pieces() > best.size()) best = {first, first + seg.num_pieces()};
    first += seg.num_pieces();
  }
  return best;
}

/// Sum of the window problems' costs over `parts` of `s`'s trajectory (with the cut-jerk pull,
/// which is zero there: the whole trajectory is C^4 at every cut).
double window_cost_sum(const Solved& s, const std::vector<PieceWindow>& parts) {
  double sum = 0.0;
  for (const PieceWindow& w : parts) {
    const std::optional<midend::ReferencePath> ref = window_reference(s.solution.reference, s.trajectory, w, 100.0);
    if (!ref) throw std::runtime_error("no window reference");
    midend::MidendProblem part(*ref, midend::MidendLimits::from_robot(midend::testing::scout_mini_piper_model()),
                               s.solution.settings);
    const std::optional<Trajectory> cut = cut_window(s.trajectory, w);
    Eigen::VectorXd xw;
    if (!cut || !part.decision_from_trajectory(*cut, xw)) throw std::runtime_error("the cut does not map back");
    sum += part.evaluate(xw, nullptr, nullptr);
  }
  return sum;
}

TEST(PieceWindows, WindowCostsOfAPartitionSumToTheWholeProblemsCost) {
  // Every mid-end term is a sum over pieces (energy, time, sampled penalties) or sits at a rest
  // boundary of the plan (heading, rest rates), so windows that partition a segment's pieces cost
  // exactly what the whole does: the terms of the pieces a window holds are constants of its problem.
  {
    // One moving segment (a straight without arm motion at its ends): the windows partition the
    // whole trajectory, and their costs sum to the whole problem's.
    const Solved s = solve(midend::testing::straight_line(14));
    midend::MidendProblem whole(s.solution.reference, midend::MidendLimits::from_robot(midend::testing::scout_mini_piper_model()),
                                s.solution.settings);
    ASSERT_EQ(whole.num_segments(), 1) << "a path of one moving segment";
    Eigen::VectorXd x;
    ASSERT_TRUE(whole.decision_from_trajectory(s.trajectory, x));
    const double f_whole = whole.evaluate(x, nullptr, nullptr);
    const int n = whole.num_pieces();
    ASSERT_GE(n, 6);
    EXPECT_NEAR(window_cost_sum(s, {{0, n / 3}, {n / 3, n / 3 + 1}, {n / 3 + 1, n}}), f_whole, 1e-9 * std::abs(f_whole));
    EXPECT_NEAR(window_cost_sum(s, {{0, n - 2}, {n - 2, n}}), f_whole, 1e-9 * std::abs(f_whole));
  }
  // Turns, arm motions, still ends and gear switches: any two partitions of a moving segment
  // cost the same (a cut neither adds nor drops a term).
  for (const planner::WholeBodyPath& path : {midend::testing::forward_with_turn(), midend::testing::forest_slalom(60)}) {
    const Solved s = solve(path);
    const PieceWindow m = longest_moving_segment(s.solution.reference);
    ASSERT_GE(m.size(), 6);
    const double a = window_cost_sum(s, {m});
    const int c1 = m.first + m.size() / 3, c2 = m.first + (2 * m.size()) / 3;
    EXPECT_NEAR(window_cost_sum(s, {{m.first, c1}, {c1, m.last}}), a, 1e-9 * std::abs(a));
    EXPECT_NEAR(window_cost_sum(s, {{m.first, c1}, {c1, c2}, {c2, m.last}}), a, 1e-9 * std::abs(a));
    EXPECT_NEAR(window_cost_sum(s, {{m.first, m.first + 1}, {m.first + 1, m.last - 1}, {m.last - 1, m.last}}), a,
                1e-9 * std::abs(a));
  }
}

TEST(PieceWindows, AWindowsSolutionSplicedBackHoldsEveryOtherPieceAndJoinsC2) {
  const Solved s = solve(midend::testing::forest_slalom(60));
  const int n = s.trajectory.num_pieces();
  const PieceWindow m = longest_moving_segment(s.solution.reference);
  ASSERT_GE(m.size(), 8);
  const PieceWindow w{m.first + 2, m.first + 6};
  const std::optional<midend::ReferencePath> ref = window_reference(s.solution.reference, s.trajectory, w);
  ASSERT_TRUE(ref);
  midend::MidendProblem part(*ref, midend::MidendLimits::from_robot(midend::testing::scout_mini_piper_model()),
                             s.solution.settings);
  const std::optional<Trajectory> cut = cut_window(s.trajectory, w);
  ASSERT_TRUE(cut);
  Eigen::VectorXd xw;
  ASSERT_TRUE(part.decision_from_trajectory(*cut, xw));
  // Move every variable of the window: waypoints by centimetres, times by a few per cent.
  std::mt19937 rng(7);
  std::normal_distribution<double> N(0.0, 0.03);
  for (int k = 0; k < xw.size(); ++k) xw[k] += N(rng);
  const std::vector<TrajectoryPiece> moved = part.pieces(xw.data());
  ASSERT_EQ(static_cast<int>(moved.size()), w.size());
  TrajectoryResult tw = Trajectory::create(moved, part.start_yaw_rad());
  ASSERT_TRUE(tw.ok()) << tw.error;
  const std::optional<Trajectory> spliced = splice(s.trajectory, w, *tw.trajectory);
  ASSERT_TRUE(spliced);
  ASSERT_EQ(spliced->num_pieces(), n);
  for (int i = 0; i < n; ++i) {
    if (i >= w.first && i < w.last) continue;
    EXPECT_EQ(spliced->piece(i).coeffs, s.trajectory.piece(i).coeffs) << "held piece " << i;
    EXPECT_EQ(spliced->piece(i).duration_s, s.trajectory.piece(i).duration_s) << "held piece " << i;
  }
  EXPECT_NE(spliced->piece(w.first).coeffs, s.trajectory.piece(w.first).coeffs) << "the window moved";
  // Position, velocity and acceleration agree across both cuts.
  for (const int cut_at : {w.first, w.last}) {
    const TrajectoryPiece& before = spliced->piece(cut_at - 1);
    const TrajectoryPiece& after = spliced->piece(cut_at);
    for (int order = 0; order <= 2; ++order) {
      const TrajVector a = piece_derivative(before.coeffs, before.duration_s, order);
      const TrajVector b = piece_derivative(after.coeffs, 0.0, order);
      EXPECT_LT((a - b).norm(), 1e-9 * (1.0 + a.norm())) << "cut before piece " << cut_at << ", order " << order;
    }
  }
  // A window grown over these cuts holds a trajectory MINCO cannot express (C^2, not C^4, at the
  // old cuts): the exact map back fails, the inexact one gives the quintics through the same
  // waypoints and times, with the new cuts' states.
  const PieceWindow grown{w.first - 1, w.last + 1};
  const std::optional<midend::ReferencePath> gref = window_reference(s.solution.reference, *spliced, grown);
  ASSERT_TRUE(gref);
  midend::MidendProblem gpart(*gref, midend::MidendLimits::from_robot(midend::testing::scout_mini_piper_model()),
                              s.solution.settings);
  const std::optional<Trajectory> gcut = cut_window(*spliced, grown);
  ASSERT_TRUE(gcut);
  Eigen::VectorXd xg;
  EXPECT_FALSE(gpart.decision_from_trajectory(*gcut, xg));
  ASSERT_TRUE(gpart.decision_from_trajectory(*gcut, xg, false));
  const std::vector<TrajectoryPiece> smooth = gpart.pieces(xg.data());
  ASSERT_EQ(static_cast<int>(smooth.size()), grown.size());
  for (int i = 0; i < grown.size(); ++i) {
    const TrajectoryPiece& a = smooth[static_cast<std::size_t>(i)];
    const TrajectoryPiece& b = gcut->piece(i);
    EXPECT_NEAR(a.duration_s, b.duration_s, 1e-9 * b.duration_s) << "piece " << i;
    EXPECT_LT((piece_derivative(a.coeffs, 0.0, 0) - piece_derivative(b.coeffs, 0.0, 0)).norm(), 1e-9) << "piece " << i;
  }
  for (int order = 0; order <= 2; ++order) {
    const TrajectoryPiece& a = smooth.back();
    const TrajectoryPiece& b = gcut->piece(grown.size() - 1);
    EXPECT_LT((piece_derivative(a.coeffs, a.duration_s, order) - piece_derivative(b.coeffs, b.duration_s, order)).norm(),
              1e-9 * (1.0 + piece_derivative(b.coeffs, b.duration_s, order).norm()))
        << "end state, order " << order;
  }
  // The heading is continuous there too (the base moves along the same velocity).
  for (const int cut_at : {w.first, w.last}) {
    const double t = spliced->piece_start_time_s(cut_at);
    EXPECT_NEAR(std::remainder(spliced->yaw_rad(t - 1e-7) - spliced->yaw_rad(t + 1e-7), 2.0 * M_PI), 0.0, 1e-5);
  }
}

TEST(PieceWindows, CutJerkPullIsZeroOnTheHeldTrajectoryAndGrowsWithTheJump) {
  const Solved s = solve(midend::testing::forest_slalom(60));
  const PieceWindow m = longest_moving_segment(s.solution.reference);
  ASSERT_GE(m.size(), 8);
  const PieceWindow w{m.first + 2, m.first + 6};
  const midend::MidendLimits limits = midend::MidendLimits::from_robot(midend::testing::scout_mini_piper_model());
  const std::optional<midend::ReferencePath> with = window_reference(s.solution.reference, s.trajectory, w, 100.0);
  const std::optional<midend::ReferencePath> without = window_reference(s.solution.reference, s.trajectory, w, 0.0);
  ASSERT_TRUE(with && without);
  ASSERT_TRUE(with->cut_start_base_jerk && with->cut_end_base_jerk);
  midend::MidendProblem a(*with, limits, s.solution.settings), b(*without, limits, s.solution.settings);
  Eigen::VectorXd x;
  ASSERT_TRUE(a.decision_from_trajectory(*cut_window(s.trajectory, w), x));
  midend::CostBreakdown ca, cb;
  a.evaluate(x, nullptr, &ca);
  b.evaluate(x, nullptr, &cb);
  EXPECT_LT(ca.cut_jerk, 1e-12 * (1.0 + ca.total())) << "the held trajectory is C^4 at the cuts";
  EXPECT_EQ(cb.cut_jerk, 0.0);
  // Moving the window's first interior waypoint sideways changes the jerk at the first cut: the
  // pull is 100 |j - j_held|^2 there, the rest of the cost as without it.
  Eigen::VectorXd moved = x;
  moved[1] += 0.05;
  a.evaluate(moved, nullptr, &ca);
  b.evaluate(moved, nullptr, &cb);
  const std::vector<TrajectoryPiece> p = a.pieces(moved.data());
  const Eigen::Vector2d j0 = piece_derivative(p.front().coeffs, 0.0, 3).head<2>();
  const Eigen::Vector2d j1 = piece_derivative(p.back().coeffs, p.back().duration_s, 3).head<2>();
  const double expected = 100.0 * ((j0 - *with->cut_start_base_jerk).squaredNorm() + (j1 - *with->cut_end_base_jerk).squaredNorm());
  EXPECT_GT(expected, 1e-3);
  EXPECT_NEAR(ca.cut_jerk, expected, 1e-9 * expected);
  EXPECT_NEAR(ca.total() - ca.cut_jerk, cb.total(), 1e-9 * cb.total());
}

TEST(PieceWindows, WindowProblemGradientMatchesCentralDifferences) {
  // The window's cut states enter as constants: the analytic gradient of the window's problem
  // (its interior waypoints, times and time scale; the cut-jerk pull included) against central
  // differences.
  const Solved s = solve(midend::testing::forest_slalom(60));
  const PieceWindow m = longest_moving_segment(s.solution.reference);
  ASSERT_GE(m.size(), 8);
  const PieceWindow w{m.first + 2, m.first + 7};
  const std::optional<midend::ReferencePath> ref = window_reference(s.solution.reference, s.trajectory, w, 100.0);
  ASSERT_TRUE(ref);
  midend::MidendProblem part(*ref, midend::MidendLimits::from_robot(midend::testing::scout_mini_piper_model()),
                             s.solution.settings);
  Eigen::VectorXd x;
  ASSERT_TRUE(part.decision_from_trajectory(*cut_window(s.trajectory, w), x));
  std::mt19937 rng(11);
  std::normal_distribution<double> N(0.0, 0.02);
  for (int k = 0; k < x.size(); ++k) x[k] += N(rng);  // off the optimum: every term pulls
  Eigen::VectorXd g(x.size());
  midend::CostBreakdown parts;
  const double f = part.evaluate(x, &g, &parts);
  ASSERT_TRUE(std::isfinite(f));
  ASSERT_GT(parts.cut_jerk, 0.0) << "the pull is active";
  const double h = 1e-6;
  for (int k = 0; k < x.size(); ++k) {
    Eigen::VectorXd xp = x, xm = x;
    xp[k] += h;
    xm[k] -= h;
    const double fd = (part.evaluate(xp, nullptr, nullptr) - part.evaluate(xm, nullptr, nullptr)) / (2.0 * h);
    EXPECT_NEAR(g[k], fd, 1e-4 * (1.0 + std::abs(fd))) << "variable " << k << " of " << x.size();
  }
}

}  // namespace
}  // namespace porter::backend
