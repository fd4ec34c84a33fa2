#include "porter/minco/time_map.hpp"

#include <gtest/gtest.h>

namespace porter::minco {
namespace {

TEST(TimeMap, InverseRoundTrips) {
  for (double t : {1e-4, 0.01, 0.3, 0.999, 1.0, 1.001, 2.5, 40.0, 1e4}) {
    EXPECT_NEAR(duration_from_tau(tau_from_duration(t)), t, 1e-12 * std::max(1.0, t)) << t;
  }
  for (double tau : {-50.0, -3.0, -1e-3, 0.0, 1e-3, 2.0, 80.0}) {
    EXPECT_NEAR(tau_from_duration(duration_from_tau(tau)), tau, 1e-8 * std::max(1.0, std::abs(tau)));
  }
}

TEST(TimeMap, AlwaysPositive) {
  for (double tau = -1e3; tau <= 1e3; tau += 7.3) EXPECT_GT(duration_from_tau(tau), 0.0) << tau;
}

TEST(TimeMap, DerivativeMatchesCentralDifference) {
  for (double tau : {-20.0, -2.0, -0.5, -1e-2, 0.3, 1.0, 4.0, 30.0}) {
    const double h = 1e-6 * std::max(1.0, std::abs(tau));
    const double fd = (duration_from_tau(tau + h) - duration_from_tau(tau - h)) / (2.0 * h);
    EXPECT_NEAR(duration_derivative(tau), fd, 1e-6 * std::max(1.0, std::abs(fd))) << tau;
  }
}

TEST(TimeMap, IsC2AtZero) {
  EXPECT_DOUBLE_EQ(duration_from_tau(0.0), 1.0);
  const double h = 1e-4;
  EXPECT_NEAR(duration_derivative(h), duration_derivative(-h), 3e-4);
  const double d2_right = (duration_derivative(2 * h) - duration_derivative(h)) / h;
  const double d2_left = (duration_derivative(-h) - duration_derivative(-2 * h)) / h;
  EXPECT_NEAR(d2_right, 1.0, 1e-3);
  EXPECT_NEAR(d2_left, 1.0, 1e-3);
}

}  // namespace
}  // namespace porter::minco
