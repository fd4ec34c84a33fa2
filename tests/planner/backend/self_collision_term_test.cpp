// The back-end's self-collision penalty (self_collision_term.hpp):
//  - surface samples lie on the link's surface (nearly all) and cover it (every finer sample within h sqrt(3)
//    of one of them, the worst case of lattice node + projection);
//  - the integrand's d/dq and the trajectory gradient (coefficients and durations) against
//    central differences, where pairs are violated;
//  - relative thresholds: after prepare() the warm start costs nothing, no threshold rises above
//    the derived one, the pairs a low arm pose keeps close get a lower one, and folding the
//    arm further costs again.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

#include "backend_fixtures.hpp"
#include "porter/backend/self_collision_term.hpp"
#include "porter/planner/collision/kernel_collision_checker.hpp"

namespace porter::backend {
namespace {

constexpr char kPayload[] = "t_bar";

/// The shoulder down at its limit with the elbow half folded: link 3 a few centimetres over the
/// base (inside the derived thresholds, not in collision by the check).
JointVector low_pose() {
  JointVector q;
  q << 0.0, 0.05, -0.8, 0.0, 0.5, 0.0;
  return q;
}

/// Three pieces of a base driving straight at 0.3 m/s while the arm sways about low_pose().
Trajectory swaying_trajectory(double amplitude_rad) {
  std::vector<TrajectoryPiece> pieces;
  const double T = 1.0;
  auto knot = [&](int k, TrajVector* p, TrajVector* v, TrajVector* a) {
    p->setZero();
    v->setZero();
    a->setZero();
    (*p)[0] = 0.3 * T * k;
    (*v)[0] = 0.3;
    const JointVector q = low_pose();
    for (int m = 0; m < kNumArmJoints; ++m) {
      (*p)[2 + m] = q[m] + amplitude_rad * std::sin(1.3 * k + 0.7 * m);
      (*v)[2 + m] = 0.5 * amplitude_rad * std::cos(1.1 * k + 0.5 * m);
    }
  };
  for (int k = 0; k < 3; ++k) {
    TrajVector p0, v0, a0, p1, v1, a1;
    knot(k, &p0, &v0, &a0);
    knot(k + 1, &p1, &v1, &a1);
    TrajectoryPiece piece;
    piece.duration_s = T * (1.0 + 0.1 * k);
    piece.coeffs = quintic_hermite(p0, v0, a0, p1, v1, a1, piece.duration_s);
    pieces.push_back(piece);
  }
  TrajectoryResult r = Trajectory::create(std::move(pieces), 0.0);
  if (!r.ok()) throw std::runtime_error(r.error);
  return std::move(*r.trajectory);
}

struct TermCase {
  const RobotModel& model = testing::robot(kPayload);
  const RobotSdf& sdf = testing::robot_sdf(kPayload);
  planner::KernelCollisionChecker checker{model};
  std::vector<std::array<int, 2>> pairs = checker.self_collision().checked_pairs();  // as porter-plan
  SelfCollisionTerm make(bool relative) const {
    SelfCollisionTermSettings s;
    s.relative_to_warm_start = relative;
    return SelfCollisionTerm(model, sdf, pairs, checker.self_collision().inflation_bound_m(), s);
  }
};

TEST(SelfCollisionTerm, SurfaceSamplesLieOnTheSurfaceAndCoverIt) {
  const RobotSdf& sdf = testing::robot_sdf(kPayload);
  const double h = 0.015;
  for (const int link : {0, 3, 7}) {
    const std::vector<Eigen::Vector3f> coarse = surface_samples(sdf.link(link), h);
    ASSERT_GT(coarse.size(), 50u) << "link " << link;
    // Projected along the field's gradient: nearly all onto the zero level, every one within the
    // band it was taken from (a few stall where the gradient of the min over shapes vanishes).
    std::size_t on_surface = 0;
    for (const auto& p : coarse) {
      const double d = std::abs(sdf.link(link).distance(p.cast<double>()));
      ASSERT_LE(d, 0.5 * std::sqrt(3.0) * h) << "link " << link;
      on_surface += d < 1e-3;
    }
    EXPECT_GE(on_surface, 0.95 * static_cast<double>(coarse.size())) << "link " << link;
    const std::vector<Eigen::Vector3f> fine = surface_samples(sdf.link(link), 0.25 * h);
    double worst = 0.0;
    for (std::size_t i = 0; i < fine.size(); i += 7) {
      double nearest = INFINITY;
      for (const auto& q : coarse) nearest = std::min(nearest, static_cast<double>((fine[i] - q).norm()));
      worst = std::max(worst, nearest);
    }
    EXPECT_LE(worst, std::sqrt(3.0) * h) << "link " << link;
  }
}

TEST(SelfCollisionTerm, RejectsBadPairsAndSettings) {
  const TermCase c;
  EXPECT_THROW(SelfCollisionTerm(c.model, c.sdf, {{0, 0}}, 0.01), std::invalid_argument);
  EXPECT_THROW(SelfCollisionTerm(c.model, c.sdf, {{0, 8}}, 0.01), std::invalid_argument);
  EXPECT_THROW(SelfCollisionTerm(c.model, c.sdf, c.pairs, -1.0), std::invalid_argument);
  SelfCollisionTermSettings bad;
  bad.point_spacing_m = 0.0;
  EXPECT_THROW(SelfCollisionTerm(c.model, c.sdf, c.pairs, 0.01, bad), std::invalid_argument);
}

TEST(SelfCollisionTerm, ConfigurationGradientMatchesCentralDifferences) {
  const TermCase c;
  SelfCollisionTerm term = c.make(false);
  std::mt19937 rng(11);
  std::normal_distribution<double> N(0.0, 0.15);
  const JointVector carry = low_pose();
  int violated = 0;
  for (int trial = 0; trial < 12; ++trial) {
    JointVector q = carry;
    for (int m = 0; m < kNumArmJoints; ++m) q[m] += N(rng);
    Eigen::Matrix<double, kNumArmJoints, 1> g;
    SelfCollisionStats st;
    const double f = term.configuration_cost(q, &g, &st);
    if (f == 0.0) continue;
    ++violated;
    for (int m = 0; m < kNumArmJoints; ++m) {
      const double e = 1e-6;
      JointVector qp = q, qm = q;
      qp[m] += e;
      qm[m] -= e;
      const double fd = (term.configuration_cost(qp, nullptr) - term.configuration_cost(qm, nullptr)) / (2 * e);
      EXPECT_NEAR(g[m], fd, 1e-4 * (1.0 + std::abs(fd)) + 1e-3 * g.norm()) << "trial " << trial << " joint " << m;
    }
  }
  EXPECT_GE(violated, 6) << "the pose must put pairs inside the derived thresholds";
}

TEST(SelfCollisionTerm, TrajectoryGradientMatchesCentralDifferences) {
  const TermCase c;
  SelfCollisionTerm term = c.make(false);
  const Trajectory traj = swaying_trajectory(0.1);
  term.prepare(traj);
  TrajectoryGradient grad;
  grad.reset(traj.num_pieces());
  SelfCollisionStats st;
  const double f0 = term.evaluate(traj, grad, &st);
  ASSERT_GT(f0, 0.0) << "the fixture must violate some pair";
  ASSERT_GT(st.violations, 0);
  auto value = [&](const Trajectory& t) {
    TrajectoryGradient unused;
    unused.reset(t.num_pieces());
    return term.evaluate(t, unused);
  };
  for (int i = 0; i < traj.num_pieces(); ++i) {
    for (int col = 2; col < kTrajDim; ++col)  // joints; the base position never matters
      for (int row = 0; row < kTrajNumCoeffs; row += 2) {
        const double e = 1e-6;
        const double fd = (value(testing::perturbed(traj, i, row, col, e)) - value(testing::perturbed(traj, i, row, col, -e))) / (2 * e);
        EXPECT_NEAR(grad.coeffs(i)(row, col), fd, 1e-4 * (1.0 + std::abs(fd)) + 1e-6 * f0)
            << "piece " << i << " row " << row << " col " << col;
      }
    EXPECT_EQ(grad.coeffs(i).col(0).norm() + grad.coeffs(i).col(1).norm(), 0.0);
    const double e = 1e-6;
    const double fd = (value(testing::perturbed(traj, i, -1, 0, e)) - value(testing::perturbed(traj, i, -1, 0, -e))) / (2 * e);
    EXPECT_NEAR(grad.duration(i), fd, 1e-4 * (1.0 + std::abs(fd))) << "duration " << i;
  }
}

TEST(SelfCollisionTerm, RelativeThresholdsLeaveTheWarmStartFree) {
  const TermCase c;
  SelfCollisionTerm term = c.make(true);
  const Trajectory traj = swaying_trajectory(0.1);
  term.prepare(traj);
  TrajectoryGradient grad;
  grad.reset(traj.num_pieces());
  EXPECT_EQ(term.evaluate(traj, grad), 0.0);
  int lowered = 0;
  for (int k = 0; k < term.num_pairs(); ++k) {
    EXPECT_LE(term.active_threshold_m(k), term.threshold_m(k));
    EXPECT_GE(term.active_threshold_m(k), 0.0);
    lowered += term.active_threshold_m(k) < term.threshold_m(k);
  }
  EXPECT_GE(lowered, 1);
  // The arm folded further towards the base than the warm start ever was costs again.
  std::vector<TrajectoryPiece> pieces;
  for (int i = 0; i < traj.num_pieces(); ++i) {
    TrajectoryPiece p = traj.piece(i);
    p.coeffs(0, 2 + 2) -= 0.4;  // joint 3 folded further
    pieces.push_back(p);
  }
  TrajectoryResult folded = Trajectory::create(std::move(pieces), traj.start_yaw_rad());
  ASSERT_TRUE(folded.ok()) << folded.error;
  grad.reset(traj.num_pieces());
  EXPECT_GT(term.evaluate(*folded.trajectory, grad), 0.0);
}

}  // namespace
}  // namespace porter::backend
