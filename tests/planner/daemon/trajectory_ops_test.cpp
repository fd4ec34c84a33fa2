// trajectory_tail and braking_trajectory: the tail is the same motion re-timed; a brake starts
// exactly in the executed state, ends at rest on the path, within its deceleration bounds.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "porter/planner_daemon/trajectory_ops.hpp"

namespace porter::planner_daemon {
namespace {

/// Three pieces of random quintics (continuity is not needed to compare a tail with its source).
Trajectory random_trajectory(std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<TrajectoryPiece> pieces;
  for (int i = 0; i < 3; ++i) {
    TrajectoryPiece p;
    p.duration_s = 0.5 + 0.5 * (u(rng) + 1.0);
    p.eta = i == 1 ? -1 : 1;
    for (int k = 0; k < kTrajNumCoeffs; ++k)
      for (int d = 0; d < kTrajDim; ++d) p.coeffs(k, d) = u(rng) / (1.0 + k);
    pieces.push_back(p);
  }
  return *Trajectory::create(pieces, 0.3).trajectory;
}

/// A straight drive along x at constant speed v with the arm moving at constant rate w.
Trajectory straight(double v, double w, double duration_s) {
  TrajectoryPiece p;
  p.duration_s = duration_s;
  p.coeffs(1, 0) = v;
  for (int d = 2; d < kTrajDim; ++d) p.coeffs(1, d) = w;
  return *Trajectory::create({p}, 0.0).trajectory;
}

TEST(TrajectoryTail, SameMotionFromTheCut) {
  for (std::uint32_t seed = 1; seed <= 5; ++seed) {
    const Trajectory t = random_trajectory(seed);
    for (double t0 : {0.0, 0.2, t.piece_start_time_s(1), t.piece_start_time_s(1) + 0.1, t.total_duration_s() - 0.05}) {
      const Trajectory tail = trajectory_tail(t, t0);
      EXPECT_NEAR(tail.total_duration_s(), t.total_duration_s() - t0, 1e-9);
      for (double s = 0.0; s <= tail.total_duration_s(); s += 0.01) {
        for (int order = 0; order <= 3; ++order) {
          EXPECT_LT((tail.derivative(s, order) - t.derivative(t0 + s, order)).norm(), 1e-8)
              << "seed " << seed << " t0 " << t0 << " s " << s << " order " << order;
        }
      }
      double tau = 0.0;
      EXPECT_EQ(tail.piece(0).eta, t.piece(t.locate(t0 + 1e-7, &tau)).eta);
    }
  }
}

TEST(TrajectoryTail, AtTheEndIsOneStationaryPiece) {
  const Trajectory t = random_trajectory(7);
  const Trajectory tail = trajectory_tail(t, t.total_duration_s() + 1.0);
  ASSERT_EQ(tail.num_pieces(), 1);
  EXPECT_LT((tail.position(0.0) - t.position(t.total_duration_s())).norm(), 1e-12);
  EXPECT_LT(tail.velocity(0.0).norm(), 1e-12);
}

TEST(BrakingTrajectory, StartsInTheExecutedStateAndEndsAtRest) {
  const BrakingLimits limits{1.0, 2.0, 0.2};
  for (std::uint32_t seed = 1; seed <= 5; ++seed) {
    const Trajectory t = random_trajectory(seed);
    const double th = 0.4 * t.total_duration_s();
    const Trajectory b = braking_trajectory(t, th, limits);
    for (int order = 0; order <= 2; ++order) EXPECT_LT((b.derivative(0.0, order) - t.derivative(th, order)).norm(), 1e-9);
    const double T = b.total_duration_s();
    EXPECT_LT(b.velocity(T).norm(), 1e-9);
    EXPECT_LT(b.acceleration(T).norm(), 1e-9);
    // The mean deceleration over the brake is within the limits.
    EXPECT_LE(t.velocity(th).head<2>().norm() / T, limits.base_decel_mps2 + 1e-12);
    for (int d = 2; d < kTrajDim; ++d) EXPECT_LE(std::abs(t.velocity(th)[d]) / T, limits.joint_decel_radps2 + 1e-12);
    EXPECT_GE(T, limits.min_duration_s);
    // It comes to rest where the trajectory is half the brake later.
    EXPECT_LT((b.position(T) - t.position(std::min(th + 0.5 * T, t.total_duration_s()))).norm(), 1e-9);
  }
}

TEST(BrakingTrajectory, FromConstantSpeedTheSpeedFallsMonotonicallyAlongThePath) {
  const Trajectory t = straight(0.8, 0.2, 10.0);
  const BrakingLimits limits{1.0, 1.0, 0.2};
  const Trajectory b = braking_trajectory(t, 2.0, limits);
  EXPECT_NEAR(b.total_duration_s(), 1.6, 1e-12);  // 2 v / a
  double previous = 1e9;
  for (double s = 0.0; s <= b.total_duration_s(); s += 0.01) {
    const TrajVector v = b.velocity(s);
    EXPECT_GE(v[0], -1e-12);  // never backwards
    EXPECT_LE(v[0], previous + 1e-12);
    EXPECT_NEAR(b.position(s)[1], 0.0, 1e-12);  // stays on the line
    EXPECT_LE(std::abs(b.acceleration(s)[0]), 1.5 * 1.0 + 1e-9);  // peak 1.5 x the mean
    previous = v[0];
  }
  EXPECT_NEAR(b.position(b.total_duration_s())[0], 1.6 + 0.8 * 0.8, 1e-9);  // x(2) + v T / 2
}

TEST(BrakingTrajectory, AxesAtRestStayWhereTheyAre) {
  const Trajectory t = straight(0.0, 0.0, 5.0);
  const Trajectory b = braking_trajectory(t, 1.0, BrakingLimits{1.0, 1.0, 0.3});
  EXPECT_NEAR(b.total_duration_s(), 0.3, 1e-12);
  for (double s = 0.0; s <= 0.3; s += 0.01) EXPECT_LT((b.position(s) - t.position(1.0)).norm(), 1e-12);
}

}  // namespace
}  // namespace porter::planner_daemon
