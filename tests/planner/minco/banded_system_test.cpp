// BandedSystem (fast kernel) against Eigen's dense LU (slow reference).
#include "porter/minco/banded_system.hpp"

#include <random>
#include <string>

#include <Eigen/Dense>
#include <gtest/gtest.h>

namespace porter::minco {
namespace {

struct Case {
  int n, lower, upper, cols;
};

class BandedSystemTest : public ::testing::TestWithParam<Case> {};

TEST_P(BandedSystemTest, SolveAndAdjointMatchDenseLu) {
  const Case c = GetParam();
  std::mt19937 rng(1234 + c.n * 7 + c.lower);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  BandedSystem band(c.n, c.lower, c.upper);
  Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(c.n, c.n);
  for (int i = 0; i < c.n; ++i) {
    for (int j = std::max(0, i - c.lower); j <= std::min(c.n - 1, i + c.upper); ++j) {
      // Diagonal dominance keeps the unpivoted factorization well conditioned.
      const double v = (i == j) ? 4.0 + c.lower + c.upper + u(rng) : u(rng);
      band(i, j) = v;
      dense(i, j) = v;
    }
  }
  ASSERT_TRUE(band.factorize_lu());
  using RowMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const RowMat b = RowMat::Random(c.n, c.cols);

  RowMat x = b;
  band.solve(x.data(), c.cols, c.cols);
  const Eigen::MatrixXd x_ref = dense.partialPivLu().solve(Eigen::MatrixXd(b));
  EXPECT_LT((Eigen::MatrixXd(x) - x_ref).cwiseAbs().maxCoeff(), 1e-12);

  RowMat y = b;
  band.solve_adjoint(y.data(), c.cols, c.cols);
  const Eigen::MatrixXd y_ref = dense.transpose().partialPivLu().solve(Eigen::MatrixXd(b));
  EXPECT_LT((Eigen::MatrixXd(y) - y_ref).cwiseAbs().maxCoeff(), 1e-12);
}

INSTANTIATE_TEST_SUITE_P(Shapes, BandedSystemTest,
                         ::testing::Values(Case{1, 0, 0, 1}, Case{5, 1, 1, 2}, Case{12, 6, 6, 8},
                                           Case{30, 6, 6, 8}, Case{17, 2, 5, 3},
                                           Case{20, 5, 0, 1}),
                         [](const ::testing::TestParamInfo<Case>& info) {
                           const Case& c = info.param;
                           return "n" + std::to_string(c.n) + "_l" + std::to_string(c.lower) + "_u" +
                                  std::to_string(c.upper) + "_c" + std::to_string(c.cols);
                         });

TEST(BandedSystem, ReportsZeroPivot) {
  BandedSystem band(3, 1, 1);
  band(0, 0) = 0.0;
  band(0, 1) = 1.0;
  band(1, 0) = 1.0;
  band(1, 1) = 1.0;
  band(2, 2) = 1.0;
  EXPECT_FALSE(band.factorize_lu());
}

TEST(BandedSystem, ResizeZeroesEntries) {
  BandedSystem band(4, 1, 2);
  band(1, 3) = 5.0;
  band.resize(4, 1, 2);
  EXPECT_EQ(band(1, 3), 0.0);
  EXPECT_EQ(band.size(), 4);
  EXPECT_EQ(band.lower(), 1);
  EXPECT_EQ(band.upper(), 2);
}

}  // namespace
}  // namespace porter::minco
