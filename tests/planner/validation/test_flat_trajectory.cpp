// The validator's own polynomial evaluation: derivatives against finite differences, the base
// rates against finite differences of the heading, and the heading rule at rest.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "porter/validation/flat_trajectory.hpp"
#include "validation_fixture.hpp"

namespace porter::validation {
namespace {

PolyPiece random_piece(std::mt19937_64& rng, double T, int eta) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  PolyPiece p;
  p.duration_s = T;
  p.eta = eta;
  for (int k = 0; k < kPolyCoeffs; ++k)
    for (int d = 0; d < kFlatDim; ++d) p.coeffs(k, d) = u(rng) / std::pow(T, k);
  p.coeffs(1, 0) += 1.0;  // keep the base moving
  return p;
}

TEST(FlatTrajectory, DerivativesMatchFiniteDifferences) {
  std::mt19937_64 rng(7);
  const FlatTrajectory traj({random_piece(rng, 1.3, 1), random_piece(rng, 0.7, -1)}, 0.0);
  const double h = 1e-6;
  for (double t : {0.1, 0.55, 1.1, 1.5, 1.9}) {
    for (int order = 1; order <= 5; ++order) {
      const FlatVector fd = (traj.derivative(t + h, order - 1) - traj.derivative(t - h, order - 1)) / (2 * h);
      const FlatVector an = traj.derivative(t, order);
      for (int d = 0; d < kFlatDim; ++d)
        EXPECT_NEAR(an[d], fd[d], 1e-5 * (1.0 + std::abs(an[d]))) << "t " << t << " order " << order << " dim " << d;
    }
    EXPECT_TRUE(traj.derivative(t, 6).isZero());
  }
}

TEST(FlatTrajectory, PlanarRatesMatchFiniteDifferencesOfHeadingAndSpeed) {
  std::mt19937_64 rng(11);
  for (int eta : {1, -1}) {
    const FlatTrajectory traj({random_piece(rng, 2.0, eta)}, 0.0);
    const double h = 1e-6;
    for (double t : {0.2, 0.7, 1.3, 1.8}) {
      const PlanarRates r = traj.planar_rates(t);
      ASSERT_GT(r.speed_mps, 0.05);
      const double dyaw = std::remainder(traj.yaw_rad(t + h) - traj.yaw_rad(t - h), 2 * M_PI) / (2 * h);
      EXPECT_NEAR(r.omega_radps, dyaw, 1e-5 * (1 + std::abs(dyaw)));
      const double domega = (traj.planar_rates(t + h).omega_radps - traj.planar_rates(t - h).omega_radps) / (2 * h);
      EXPECT_NEAR(r.alpha_radps2, domega, 1e-4 * (1 + std::abs(domega)));
      const double dv = (traj.planar_rates(t + h).v_mps - traj.planar_rates(t - h).v_mps) / (2 * h);
      EXPECT_NEAR(r.a_mps2, dv, 1e-5 * (1 + std::abs(dv)));
      EXPECT_NEAR(std::abs(r.v_mps), r.speed_mps, 1e-15);
      EXPECT_EQ(r.v_mps > 0, eta > 0);
      // Heading points along the velocity forward, against it in reverse.
      const FlatVector v = traj.derivative(t, 1);
      EXPECT_NEAR(std::remainder(traj.yaw_rad(t) - std::atan2(eta * v[1], eta * v[0]), 2 * M_PI), 0.0, 1e-12);
    }
  }
}

TEST(FlatTrajectory, HeadingAtRestFollowsTheMotionAboutToHappenOrJustEnded) {
  using test::carry_arm;
  using test::flat;
  const PolyPiece fwd = test::ramp(flat(0, 0, carry_arm()), flat(1, 1, carry_arm()), 2.0, 1);
  const FlatTrajectory f({fwd}, 1.0);
  EXPECT_NEAR(f.yaw_rad(0.0), M_PI / 4, 1e-12);  // rest; the jerk points along (1, 1)
  EXPECT_NEAR(f.yaw_rad(2.0), M_PI / 4, 1e-12);  // arriving along (1, 1)
  EXPECT_NEAR(f.yaw_rad(1.0), M_PI / 4, 1e-12);
  const PolyPiece rev = test::ramp(flat(0, 0, carry_arm()), flat(1, 1, carry_arm()), 2.0, -1);
  const FlatTrajectory r({rev}, 0.0);
  EXPECT_NEAR(r.yaw_rad(0.0), -3 * M_PI / 4, 1e-12);
  EXPECT_NEAR(r.yaw_rad(2.0), -3 * M_PI / 4, 1e-12);
  // Arm-only pieces keep the heading: the start's before any motion, the last motion's after.
  Eigen::Matrix<double, 6, 1> q2 = carry_arm();
  q2[0] = 0.5;
  const PolyPiece arm_first = test::ramp(flat(0, 0, carry_arm()), flat(0, 0, q2), 1.0);
  const PolyPiece drive = test::ramp(flat(0, 0, q2), flat(-1, 0, q2), 1.0);
  const PolyPiece arm_last = test::ramp(flat(-1, 0, q2), flat(-1, 0, carry_arm()), 1.0);
  const FlatTrajectory held({arm_first, drive, arm_last}, 0.3);
  EXPECT_NEAR(held.yaw_rad(0.5), 0.3, 1e-12);
  EXPECT_NEAR(std::abs(held.yaw_rad(1.5)), M_PI, 1e-12);
  EXPECT_NEAR(std::abs(held.yaw_rad(2.5)), M_PI, 1e-12);
  EXPECT_NEAR(std::abs(held.yaw_rad(3.0)), M_PI, 1e-12);
}

TEST(FlatTrajectory, LocatesPiecesAndClampsTime) {
  using test::carry_arm;
  using test::flat;
  const FlatTrajectory t({test::ramp(flat(0, 0, carry_arm()), flat(1, 0, carry_arm()), 1.0),
                          test::ramp(flat(1, 0, carry_arm()), flat(3, 0, carry_arm()), 2.0)},
                         0.0);
  double tau = -1;
  EXPECT_DOUBLE_EQ(t.duration_s(), 3.0);
  EXPECT_EQ(t.locate(1.0, &tau), 1);  // a knot belongs to the piece starting there
  EXPECT_DOUBLE_EQ(tau, 0.0);
  EXPECT_EQ(t.locate(3.0, &tau), 1);
  EXPECT_DOUBLE_EQ(tau, 2.0);
  EXPECT_EQ(t.locate(-5.0, &tau), 0);
  EXPECT_EQ(t.locate(std::nan(""), &tau), 0);
  EXPECT_NEAR(t.derivative(99.0, 0)[0], 3.0, 1e-12);
  EXPECT_NEAR(t.derivative(0.5, 0)[0], 0.5, 1e-12);
}

}  // namespace
}  // namespace porter::validation
