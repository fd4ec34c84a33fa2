// Penalty functions and the trapezoid transcription helper.
#include "porter/minco/penalty.hpp"

#include <random>

#include <gtest/gtest.h>

#include "porter/minco/penalty_integral.hpp"

namespace porter::minco {
namespace {

TEST(Penalty, SmoothedL1ValuesAndContinuity) {
  const double mu = 0.1;
  double g = 0.0;
  EXPECT_EQ(smoothed_l1(-1.0, mu, &g), 0.0);
  EXPECT_EQ(g, 0.0);
  EXPECT_EQ(smoothed_l1(0.0, mu, &g), 0.0);
  EXPECT_NEAR(smoothed_l1(mu, mu, &g), 0.5 * mu, 1e-15);
  EXPECT_NEAR(g, 1.0, 1e-15);
  EXPECT_NEAR(smoothed_l1(mu + 1e-12, mu, &g), 0.5 * mu, 1e-11);
  EXPECT_NEAR(smoothed_l1(2.0, mu, &g), 2.0 - 0.5 * mu, 1e-15);
  // Monotone non-decreasing.
  double prev = 0.0;
  for (double x = -0.2; x < 0.5; x += 1e-3) {
    const double v = smoothed_l1(x, mu, &g);
    EXPECT_GE(v, prev - 1e-15);
    prev = v;
  }
}

TEST(Penalty, DerivativesMatchCentralDifference) {
  for (PenaltyKind kind : {PenaltyKind::kSmoothedL1, PenaltyKind::kCubic}) {
    PenaltyFunction p{kind, 0.05};
    for (double x : {-0.3, 0.001, 0.02, 0.049, 0.051, 0.3, 2.0}) {
      double g = 0.0, gp = 0.0, gm = 0.0;
      p.value(x, &g);
      const double h = 1e-7;
      const double fd = (p.value(x + h, &gp) - p.value(x - h, &gm)) / (2.0 * h);
      EXPECT_NEAR(g, fd, 1e-6 * std::max(1.0, std::abs(fd))) << to_string(kind) << " x=" << x;
    }
  }
}

// A synthetic integrand with known partials: G = a.p^2-ish mixture of all four derivatives.
struct TestIntegrand {
  Eigen::Vector2d wp{0.7, -0.3}, wv{0.2, 0.5}, wa{-0.4, 0.1}, wj{0.05, 0.3};
  double operator()(PenaltySample<2>& s) const {
    const double g = s.pos.dot(wp) * s.pos.dot(wp) + std::sin(s.vel.dot(wv)) + s.acc.dot(wa) +
                     0.5 * s.jerk.squaredNorm() * wj.sum();
    s.grad_pos = 2.0 * s.pos.dot(wp) * wp;
    s.grad_vel = std::cos(s.vel.dot(wv)) * wv;
    s.grad_acc = wa;
    s.grad_jerk = s.jerk * wj.sum();
    return g;
  }
};

double integral(const Eigen::Matrix<double, 6, 2>& c, double t, int kappa,
                Eigen::Matrix<double, 6, 2>* gc, double* gt) {
  Eigen::Matrix<double, 6, 2> gc_local = Eigen::Matrix<double, 6, 2>::Zero();
  double gt_local = 0.0;
  const double v = integrate_piece_penalty<2>(c, t, kappa, TestIntegrand{}, gc_local, gt_local);
  if (gc) *gc = gc_local;
  if (gt) *gt = gt_local;
  return v;
}

TEST(PenaltyIntegral, ValueIsTrapezoidSum) {
  Eigen::Matrix<double, 6, 2> c = Eigen::Matrix<double, 6, 2>::Random();
  const double t = 1.3;
  const int kappa = 8;
  double ref = 0.0;
  for (int j = 0; j <= kappa; ++j) {
    PenaltySample<2> s;
    const double tj = t * j / kappa;
    s.pos = c.transpose() * basis(tj, 0);
    s.vel = c.transpose() * basis(tj, 1);
    s.acc = c.transpose() * basis(tj, 2);
    s.jerk = c.transpose() * basis(tj, 3);
    ref += (j == 0 || j == kappa ? 0.5 : 1.0) * (t / kappa) * TestIntegrand{}(s);
  }
  EXPECT_NEAR(integral(c, t, kappa, nullptr, nullptr), ref, 1e-12 * std::abs(ref));
}

TEST(PenaltyIntegral, GradientsMatchCentralDifference) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 5; ++trial) {
    Eigen::Matrix<double, 6, 2> c;
    for (int i = 0; i < 12; ++i) c.data()[i] = u(rng);
    const double t = 0.5 + 0.5 * (u(rng) + 1.0);
    Eigen::Matrix<double, 6, 2> gc;
    double gt = 0.0;
    integral(c, t, 16, &gc, &gt);
    const double h = 1e-6;
    Eigen::Matrix<double, 6, 2> fd;
    for (int i = 0; i < 12; ++i) {
      Eigen::Matrix<double, 6, 2> cp = c, cm = c;
      cp.data()[i] += h;
      cm.data()[i] -= h;
      fd.data()[i] = (integral(cp, t, 16, nullptr, nullptr) - integral(cm, t, 16, nullptr, nullptr)) / (2 * h);
    }
    const double fdt = (integral(c, t + h, 16, nullptr, nullptr) - integral(c, t - h, 16, nullptr, nullptr)) / (2 * h);
    EXPECT_LT((gc - fd).norm() / fd.norm(), 1e-6);
    EXPECT_NEAR(gt, fdt, 1e-6 * std::max(1.0, std::abs(fdt)));
  }
}

}  // namespace
}  // namespace porter::minco
