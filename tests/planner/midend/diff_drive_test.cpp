// Diff-drive rates: gradients against central differences, values against porter::Trajectory's
// independent implementation (core), and the rest-state guard (no NaN).
#include "porter/midend/diff_drive.hpp"
#include "porter/planner/angle.hpp"

#include <random>

#include <gtest/gtest.h>

#include "porter/core/trajectory.hpp"

namespace porter::midend {
namespace {

double component(const BaseRates& r, int which) {
  switch (which) {
    case 0: return r.speed;
    case 1: return r.accel;
    case 2: return r.yaw_rate;
    default: return r.yaw_accel;
  }
}

TEST(DiffDrive, RateGradientsMatchCentralDifference) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::Matrix<double, 6, 1> x;
    for (int k = 0; k < 6; ++k) x[k] = u(rng);
    if (trial % 4 == 0) x.head<2>() *= 1e-3;  // near rest, inside the guard's range
    const double eps = 1e-3;
    auto eval = [&](const Eigen::Matrix<double, 6, 1>& y) {
      return base_rates(y.segment<2>(0), y.segment<2>(2), y.segment<2>(4), eps);
    };
    const BaseRates r = eval(x);
    for (int which = 0; which < 4; ++which) {
      Eigen::Matrix<double, 6, 1> ana = Eigen::Matrix<double, 6, 1>::Zero();
      switch (which) {
        case 0: ana.head<2>() = r.dspeed_dv; break;
        case 1: ana.head<2>() = r.daccel_dv; ana.segment<2>(2) = r.daccel_da; break;
        case 2: ana.head<2>() = r.dyaw_rate_dv; ana.segment<2>(2) = r.dyaw_rate_da; break;
        default:
          ana.head<2>() = r.dyaw_accel_dv;
          ana.segment<2>(2) = r.dyaw_accel_da;
          ana.segment<2>(4) = r.dyaw_accel_dj;
      }
      Eigen::Matrix<double, 6, 1> fd;
      for (int k = 0; k < 6; ++k) {
        const double h = 1e-7 * std::max(1e-3, std::abs(x[k]));
        Eigen::Matrix<double, 6, 1> xp = x, xm = x;
        xp[k] += h;
        xm[k] -= h;
        fd[k] = (component(eval(xp), which) - component(eval(xm), which)) / (2.0 * h);
      }
      EXPECT_LT((ana - fd).norm(), 1e-5 * std::max(1.0, fd.norm())) << "trial " << trial << " rate " << which;
    }
  }
}

TEST(DiffDrive, HeadingGradientMatchesCentralDifference) {
  for (int eta : {1, -1}) {
    const Eigen::Vector2d v(0.3, -0.7);
    Eigen::Vector2d g;
    heading_from_velocity(v, eta, &g);
    for (int k = 0; k < 2; ++k) {
      Eigen::Vector2d vp = v, vm = v, dummy;
      vp[k] += 1e-7;
      vm[k] -= 1e-7;
      const double fd = planner::angle_difference_rad(heading_from_velocity(vp, eta, &dummy),
                                         heading_from_velocity(vm, eta, &dummy)) / 2e-7;
      EXPECT_NEAR(g[k], fd, 1e-6);
    }
  }
}

TEST(DiffDrive, MatchesCoreTrajectoryAwayFromRest) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double track = 0.4165, radius = 0.0875;
  for (int trial = 0; trial < 10; ++trial) {
    TrajectoryPiece piece;
    piece.duration_s = 2.0;
    piece.eta = trial % 2 ? 1 : -1;
    for (int r = 0; r < 6; ++r) {
      for (int c = 0; c < 8; ++c) piece.coeffs(r, c) = u(rng) / (r + 1);
    }
    piece.coeffs(1, 0) = 1.0;  // keep moving
    const TrajectoryResult tr = Trajectory::create({piece}, 0.0);
    ASSERT_TRUE(tr.ok()) << tr.error;
    const double t = 0.3;
    const TrajectoryState st = tr.trajectory->sample(t, track, radius);
    const TrajVector v = piece_derivative(piece.coeffs, t, 1);
    const TrajVector a = piece_derivative(piece.coeffs, t, 2);
    const TrajVector j = piece_derivative(piece.coeffs, t, 3);
    ASSERT_GT(v.head<2>().norm(), 0.1);
    const BaseRates r = base_rates(v.head<2>(), a.head<2>(), j.head<2>(), 1e-9);
    EXPECT_NEAR(r.speed, st.base.speed_mps, 1e-9);
    EXPECT_NEAR(r.accel, st.base.accel_mps2, 1e-9);
    EXPECT_NEAR(r.yaw_rate, st.base.yaw_rate_radps, 1e-8);
    EXPECT_NEAR(r.yaw_accel, st.base.yaw_accel_radps2, 1e-7);
    Eigen::Vector2d dphi;
    EXPECT_NEAR(planner::angle_difference_rad(heading_from_velocity(v.head<2>(), piece.eta, &dphi), st.base.yaw_rad), 0.0, 1e-12);
    const double half = 0.5 * track;
    EXPECT_NEAR((piece.eta * r.speed - half * r.yaw_rate) / radius, st.wheels.left_radps, 1e-7);
    EXPECT_NEAR((piece.eta * r.accel + half * r.yaw_accel) / radius, st.wheels.right_radps2, 1e-6);
  }
}

TEST(DiffDrive, RestIsFinite) {
  const Eigen::Vector2d zero = Eigen::Vector2d::Zero();
  const BaseRates r = base_rates(zero, zero, Eigen::Vector2d(1.0, 2.0), 1e-3);
  for (double x : {r.speed, r.accel, r.yaw_rate, r.yaw_accel}) EXPECT_TRUE(std::isfinite(x));
  EXPECT_TRUE(r.dyaw_accel_dv.allFinite() && r.dyaw_accel_dj.allFinite() && r.daccel_dv.allFinite());
  EXPECT_EQ(r.yaw_rate, 0.0);
  Eigen::Vector2d g;
  EXPECT_EQ(heading_from_velocity(zero, -1, &g), std::atan2(-0.0, -0.0));
  EXPECT_TRUE(g.isZero());
}

TEST(DiffDrive, AngleDifferenceWraps) {
  EXPECT_NEAR(planner::angle_difference_rad(3.1, -3.1), 3.1 + 3.1 - 2 * M_PI, 1e-12);
  EXPECT_NEAR(planner::angle_difference_rad(-3.1, 3.1), 2 * M_PI - 6.2, 1e-12);
  EXPECT_NEAR(planner::angle_difference_rad(0.5, 0.2), 0.3, 1e-12);
}

}  // namespace
}  // namespace porter::midend
