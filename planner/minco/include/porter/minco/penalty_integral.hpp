#pragma once
// Constraint transcription of a time integral over one polynomial piece (GCOPTER's
// attachPenaltyFunctional): with kappa intervals, samples t_j = (j / kappa) T for j = 0..kappa,
// trapezoid weights w_j (1/2 at both ends, 1 elsewhere) and step h = T / kappa,
//
//   I = sum_j w_j h G(z(t_j), z'(t_j), z''(t_j), z'''(t_j)).
//
// The integrand G is supplied by the caller together with its partials; this helper turns them
// into partials w.r.t. the piece's coefficients (C held free) and its duration:
//
//   dI/dc   += w_j h sum_k beta^(k)(t_j) (dG/dz^(k))^T
//   dI/dT   += w_j [ G / kappa + h (j / kappa) sum_k (dG/dz^(k)) . z^(k+1)(t_j) ]
//
// Header-only template; no allocation; thread-safe if the integrand is.

#include <Eigen/Core>

#include "porter/minco/polynomial.hpp"

namespace porter::minco {

/// Derivatives of z at one sample and the integrand's partials w.r.t. them.
template <int Dim>
struct PenaltySample {
  using Vector = Eigen::Matrix<double, Dim, 1>;
  int index = 0;         ///< j in [0, kappa]
  int kappa = 1;         ///< number of intervals
  double t_s = 0.0;      ///< local time in the piece
  Vector pos, vel, acc, jerk;          ///< z, z', z'', z''' at t_s
  Vector grad_pos, grad_vel, grad_acc, grad_jerk;  ///< dG/dz^(k): the integrand writes these
};

/// Integrates one piece. `integrand(sample)` returns G and writes the four partials (it must
/// write all four; zero what does not apply). Returns I and adds its partials to grad_c (a 6 x Dim
/// block) and grad_t.
template <int Dim, class CoeffBlock, class GradBlock, class Integrand>
double integrate_piece_penalty(const CoeffBlock& coeffs, double duration_s, int kappa,
                               Integrand&& integrand, GradBlock&& grad_c, double& grad_t) {
  using Deriv = Eigen::Matrix<double, Dim, 5>;
  const Eigen::Matrix<double, kPieceCoeffs, Dim> c = coeffs;  // fixed size: unrolled products
  Eigen::Matrix<double, kPieceCoeffs, Dim> gc = Eigen::Matrix<double, kPieceCoeffs, Dim>::Zero();
  Eigen::Matrix<double, Dim, 4> g;
  PenaltySample<Dim> s;
  s.kappa = kappa;
  const double h = duration_s / kappa;
  double total = 0.0;
  double gt = 0.0;
  for (int j = 0; j <= kappa; ++j) {
    const double frac = static_cast<double>(j) / kappa;
    const double t = frac * duration_s;
    const Eigen::Matrix<double, kPieceCoeffs, 5> b = basis_all(t);
    Deriv d;
    d.noalias() = c.transpose().lazyProduct(b);
    s.index = j;
    s.t_s = t;
    s.pos = d.col(0);
    s.vel = d.col(1);
    s.acc = d.col(2);
    s.jerk = d.col(3);
    const double value = integrand(s);
    g.col(0) = s.grad_pos;
    g.col(1) = s.grad_vel;
    g.col(2) = s.grad_acc;
    g.col(3) = s.grad_jerk;
    if (value == 0.0 && (g.array() == 0.0).all()) continue;
    const double w = (j == 0 || j == kappa) ? 0.5 : 1.0;
    const double wh = w * h;
    total += wh * value;
    gc.noalias() += (wh * b.template leftCols<4>()).lazyProduct(g.transpose());
    gt += w * (value / kappa + h * frac *
                                   (g.col(0).dot(d.col(1)) + g.col(1).dot(d.col(2)) +
                                    g.col(2).dot(d.col(3)) + g.col(3).dot(d.col(4))));
  }
  grad_c += gc;
  grad_t += gt;
  return total;
}

}  // namespace porter::minco
