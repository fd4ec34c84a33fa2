// MincoS3 (fast banded path) against a dense reference, constraint checks, the closed-form
// energy against quadrature, and every gradient against central finite differences.
#include "porter/minco/minco_s3.hpp"

#include <random>

#include <Eigen/Dense>
#include <gtest/gtest.h>

namespace porter::minco {
namespace {

using M8 = MincoS3<8>;

struct Problem {
  M8::BoundaryState head, tail;
  M8::Waypoints q;
  Eigen::VectorXd t;
};

Problem random_problem(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Problem p;
  p.head = M8::BoundaryState::NullaryExpr([&]() { return u(rng); });
  p.tail = M8::BoundaryState::NullaryExpr([&]() { return u(rng); });
  p.q = M8::Waypoints::NullaryExpr(8, n - 1, [&]() { return 2.0 * u(rng); });
  p.t = Eigen::VectorXd::NullaryExpr(n, [&]() { return 0.6 + 0.5 * (u(rng) + 1.0); });
  return p;
}

// Slow reference: every condition written as "sum_k basis^(order)(t)_k c_k = value", assembled
// densely and solved with full-pivot LU.
Eigen::MatrixXd dense_reference(const Problem& p) {
  const int n = static_cast<int>(p.t.size());
  const int rows = 6 * n;
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(rows, rows);
  Eigen::MatrixXd b = Eigen::MatrixXd::Zero(rows, 8);
  int r = 0;
  for (int k = 0; k < 3; ++k, ++r) {
    a.block(r, 0, 1, 6) = basis(0.0, k).transpose();
    b.row(r) = p.head.col(k).transpose();
  }
  for (int i = 0; i + 1 < n; ++i) {
    a.block(r, 6 * i, 1, 6) = basis(p.t[i], 0).transpose();
    b.row(r++) = p.q.col(i).transpose();
    for (int k = 0; k <= 4; ++k, ++r) {
      a.block(r, 6 * i, 1, 6) = basis(p.t[i], k).transpose();
      a.block(r, 6 * (i + 1), 1, 6) = -basis(0.0, k).transpose();
    }
  }
  for (int k = 0; k < 3; ++k, ++r) {
    a.block(r, 6 * (n - 1), 1, 6) = basis(p.t[n - 1], k).transpose();
    b.row(r) = p.tail.col(k).transpose();
  }
  return a.fullPivLu().solve(b);
}

TEST(MincoS3, MatchesDenseReference) {
  for (int n : {1, 2, 5, 23}) {
    const Problem p = random_problem(n, 10 + n);
    M8 m;
    ASSERT_TRUE(m.generate(p.head, p.tail, p.q, p.t));
    const Eigen::MatrixXd ref = dense_reference(p);
    EXPECT_LT((Eigen::MatrixXd(m.coefficients()) - ref).cwiseAbs().maxCoeff(),
              1e-9 * std::max(1.0, ref.cwiseAbs().maxCoeff()))
        << "n=" << n;
  }
}

TEST(MincoS3, SatisfiesBoundaryWaypointsAndC4Continuity) {
  const Problem p = random_problem(9, 3);
  M8 m;
  ASSERT_TRUE(m.generate(p.head, p.tail, p.q, p.t));
  for (int k = 0; k < 3; ++k) {
    EXPECT_LT((evaluate_piece(m.piece(0), 0.0, k) - p.head.col(k)).norm(), 1e-10);
    EXPECT_LT((evaluate_piece(m.piece(8), p.t[8], k) - p.tail.col(k)).norm(), 1e-9);
  }
  for (int i = 0; i < 8; ++i) {
    EXPECT_LT((evaluate_piece(m.piece(i), p.t[i], 0) - p.q.col(i)).norm(), 1e-9);
    for (int k = 0; k <= 4; ++k) {
      const auto left = evaluate_piece(m.piece(i), p.t[i], k);
      const auto right = evaluate_piece(m.piece(i + 1), 0.0, k);
      EXPECT_LT((left - right).norm(), 1e-8 * std::max(1.0, left.norm())) << "i=" << i << " k=" << k;
    }
  }
  EXPECT_NEAR(m.total_duration(), p.t.sum(), 1e-12);
}

TEST(MincoS3, RejectsBadInput) {
  Problem p = random_problem(3, 5);
  M8 m;
  Eigen::VectorXd t = p.t;
  t[1] = 0.0;
  EXPECT_FALSE(m.generate(p.head, p.tail, p.q, t));
  t[1] = std::nan("");
  EXPECT_FALSE(m.generate(p.head, p.tail, p.q, t));
  EXPECT_FALSE(m.generate(p.head, p.tail, M8::Waypoints(8, 1), p.t));
}

TEST(MincoS3, EnergyMatchesQuadrature) {
  const Problem p = random_problem(4, 21);
  M8 m;
  ASSERT_TRUE(m.generate(p.head, p.tail, p.q, p.t));
  M8::Vector w;
  w << 1.0, 2.0, 0.5, 0.1, 3.0, 1.0, 1.5, 0.7;
  // 5-point Gauss-Legendre is exact for the degree-4 integrand jerk^2.
  const double xg[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831, 0.9061798459386640};
  const double wg[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889, 0.4786286704993665, 0.2369268850561891};
  double ref = 0.0;
  for (int i = 0; i < 4; ++i) {
    for (int g = 0; g < 5; ++g) {
      const double t = 0.5 * p.t[i] * (xg[g] + 1.0);
      const M8::Vector j = evaluate_piece(m.piece(i), t, 3);
      ref += 0.5 * p.t[i] * wg[g] * j.dot(w.cwiseProduct(j));
    }
  }
  EXPECT_NEAR(m.energy(w), ref, 1e-10 * ref);
}

// A generic cost of the coefficients and durations (nonlinear in both) to test propagation.
double generic_cost(const M8& m, M8::Coefficients* gc, Eigen::VectorXd* gt) {
  const auto& c = m.coefficients();
  const Eigen::VectorXd& t = m.durations();
  double f = 0.0;
  if (gc) gc->setZero(c.rows(), 8);
  if (gt) gt->setZero(t.size());
  for (int r = 0; r < c.rows(); ++r) {
    for (int d = 0; d < 8; ++d) {
      const double wgt = 0.1 * ((r * 7 + d * 3) % 11) - 0.5;
      f += wgt * c(r, d) + 0.05 * c(r, d) * c(r, d);
      if (gc) (*gc)(r, d) = wgt + 0.1 * c(r, d);
    }
  }
  for (int i = 0; i < t.size(); ++i) {
    f += std::sin(t[i]) * (i + 1);
    if (gt) (*gt)[i] = std::cos(t[i]) * (i + 1);
  }
  return f;
}

double total_cost(const Problem& p, const M8::Vector& w, bool with_energy) {
  M8 m;
  EXPECT_TRUE(m.generate(p.head, p.tail, p.q, p.t));
  return generic_cost(m, nullptr, nullptr) + (with_energy ? m.energy(w) : 0.0);
}

void check_gradients(bool with_energy) {
  for (int n : {1, 3, 8}) {
    const Problem p = random_problem(n, 40 + n);
    M8::Vector w;
    w << 1.0, 1.0, 0.3, 0.3, 0.3, 2.0, 0.3, 0.3;
    M8 m;
    ASSERT_TRUE(m.generate(p.head, p.tail, p.q, p.t));
    M8::Coefficients gc;
    Eigen::VectorXd gt;
    generic_cost(m, &gc, &gt);
    if (with_energy) m.add_energy_gradient(w, gc, gt);
    M8::Waypoints gq;
    Eigen::VectorXd gt_total;
    M8::BoundaryState gh, gtail;
    m.propagate_gradient(gc, gt, gq, gt_total, gh, gtail);

    // Flatten parameters: q, t, head, tail.
    std::vector<double*> params;
    std::vector<double> analytic;
    Problem pp = p;
    for (int i = 0; i < pp.q.size(); ++i) { params.push_back(pp.q.data() + i); analytic.push_back(gq.data()[i]); }
    for (int i = 0; i < pp.t.size(); ++i) { params.push_back(pp.t.data() + i); analytic.push_back(gt_total[i]); }
    for (int i = 0; i < 24; ++i) { params.push_back(pp.head.data() + i); analytic.push_back(gh.data()[i]); }
    for (int i = 0; i < 24; ++i) { params.push_back(pp.tail.data() + i); analytic.push_back(gtail.data()[i]); }
    Eigen::VectorXd a(analytic.size()), fd(analytic.size());
    for (std::size_t k = 0; k < params.size(); ++k) {
      const double x0 = *params[k];
      const double h = 1e-6 * std::max(1.0, std::abs(x0));
      *params[k] = x0 + h;
      const double fp = total_cost(pp, w, with_energy);
      *params[k] = x0 - h;
      const double fm = total_cost(pp, w, with_energy);
      *params[k] = x0;
      fd[k] = (fp - fm) / (2.0 * h);
      a[k] = analytic[k];
    }
    EXPECT_LT((a - fd).norm() / fd.norm(), 1e-5) << "n=" << n << " energy=" << with_energy;
  }
}

TEST(MincoS3, PropagatedGradientMatchesFiniteDifference) { check_gradients(false); }
TEST(MincoS3, EnergyGradientMatchesFiniteDifference) { check_gradients(true); }

TEST(MincoS3, EnergyPartialGradientMatchesFiniteDifference) {
  // Partial w.r.t. coefficients (held free) and durations, before propagation.
  const Problem p = random_problem(3, 77);
  M8::Vector w = M8::Vector::Constant(1.3);
  M8 m;
  ASSERT_TRUE(m.generate(p.head, p.tail, p.q, p.t));
  M8::Coefficients gc = M8::Coefficients::Zero(18, 8);
  Eigen::VectorXd gt = Eigen::VectorXd::Zero(3);
  m.add_energy_gradient(w, gc, gt);
  // Energy of free coefficients: replicate the closed form on a single piece.
  auto piece_energy = [&](const Eigen::Matrix<double, 6, 8>& c, double t) {
    double e = 0.0;
    const double xg[3] = {-0.7745966692414834, 0.0, 0.7745966692414834};
    const double wg[3] = {0.5555555555555556, 0.8888888888888888, 0.5555555555555556};
    for (int g = 0; g < 3; ++g) {  // exact for degree 4 in t
      const double tt = 0.5 * t * (xg[g] + 1.0);
      const M8::Vector j = c.transpose() * basis(tt, 3);
      e += 0.5 * t * wg[g] * j.dot(w.cwiseProduct(j));
    }
    return e;
  };
  for (int i = 0; i < 3; ++i) {
    Eigen::Matrix<double, 6, 8> c = m.piece(i);
    for (int r = 3; r < 6; ++r) {
      for (int d = 0; d < 8; ++d) {
        Eigen::Matrix<double, 6, 8> cp = c, cm = c;
        cp(r, d) += 1e-6;
        cm(r, d) -= 1e-6;
        const double fd = (piece_energy(cp, p.t[i]) - piece_energy(cm, p.t[i])) / 2e-6;
        EXPECT_NEAR(gc(6 * i + r, d), fd, 1e-5 * std::max(1.0, std::abs(fd)));
      }
    }
    const double fdt = (piece_energy(c, p.t[i] + 1e-6) - piece_energy(c, p.t[i] - 1e-6)) / 2e-6;
    EXPECT_NEAR(gt[i], fdt, 1e-5 * std::max(1.0, std::abs(fdt)));
  }
}

TEST(MincoS3, OtherDimensionsWork) {
  MincoS3<1> m1;
  MincoS3<1>::BoundaryState h = MincoS3<1>::BoundaryState::Zero(), t = MincoS3<1>::BoundaryState::Zero();
  t(0, 0) = 1.0;
  MincoS3<1>::Waypoints q(1, 1);
  q(0, 0) = 0.5;
  Eigen::VectorXd d(2);
  d << 1.0, 1.0;
  ASSERT_TRUE(m1.generate(h, t, q, d));
  // Symmetric rest-to-rest through the midpoint: position at the junction is 0.5.
  EXPECT_NEAR(evaluate_piece(m1.piece(0), 1.0, 0)[0], 0.5, 1e-12);
}

}  // namespace
}  // namespace porter::minco
