#pragma once
// Degree-5 polynomial pieces (MINCO s = 3): the time basis beta(t) = [1, t, ..., t^5]^T and its
// derivatives, and evaluation of a piece given its 6 x Dim coefficient block (row k multiplies
// t^k, the layout of porter::Trajectory and of MincoS3::coefficients()).
//
// Pure functions, thread-safe, no allocation.

#include <Eigen/Core>

namespace porter::minco {

inline constexpr int kPieceCoeffs = 6;  ///< 2s for s = 3
inline constexpr int kMaxDerivative = 5;

using Basis = Eigen::Matrix<double, kPieceCoeffs, 1>;

/// d^order/dt^order of beta(t), order in [0, 5]; zero for higher orders.
inline Basis basis(double t, int order) {
  Basis b = Basis::Zero();
  const double t2 = t * t, t3 = t2 * t, t4 = t3 * t, t5 = t4 * t;
  switch (order) {
    case 0: b << 1.0, t, t2, t3, t4, t5; break;
    case 1: b << 0.0, 1.0, 2.0 * t, 3.0 * t2, 4.0 * t3, 5.0 * t4; break;
    case 2: b << 0.0, 0.0, 2.0, 6.0 * t, 12.0 * t2, 20.0 * t3; break;
    case 3: b << 0.0, 0.0, 0.0, 6.0, 24.0 * t, 60.0 * t2; break;
    case 4: b << 0.0, 0.0, 0.0, 0.0, 24.0, 120.0 * t; break;
    case 5: b << 0.0, 0.0, 0.0, 0.0, 0.0, 120.0; break;
    default: break;
  }
  return b;
}

/// All derivatives 0..4 at once, as columns (cheaper than five basis() calls).
inline Eigen::Matrix<double, kPieceCoeffs, 5> basis_all(double t) {
  const double t2 = t * t, t3 = t2 * t, t4 = t3 * t, t5 = t4 * t;
  Eigen::Matrix<double, kPieceCoeffs, 5> b;
  b << 1.0, 0.0, 0.0, 0.0, 0.0,
       t, 1.0, 0.0, 0.0, 0.0,
       t2, 2.0 * t, 2.0, 0.0, 0.0,
       t3, 3.0 * t2, 6.0 * t, 6.0, 0.0,
       t4, 4.0 * t3, 12.0 * t2, 24.0 * t, 24.0,
       t5, 5.0 * t4, 20.0 * t3, 60.0 * t2, 120.0 * t;
  return b;
}

/// The order-th derivative of a piece at local time t. `coeffs` is 6 x Dim (any storage order).
template <class Derived>
Eigen::Matrix<double, Derived::ColsAtCompileTime, 1> evaluate_piece(
    const Eigen::MatrixBase<Derived>& coeffs, double t, int order) {
  return coeffs.transpose() * basis(t, order);
}

}  // namespace porter::minco
