#pragma once
// MINCO for s = 3 (minimum jerk, degree-5 pieces, C^4 at interior waypoints) over a Dim-vector
// flat output z (Wang et al., "Geometrically constrained trajectory optimization for
// multicopters", T-RO 2022; GCOPTER's MINCO_S3NU).
//
// Given head and tail states (position, velocity, acceleration), N-1 interior waypoints Q and N
// positive durations T, the coefficients C (6N x Dim, row 6i+k multiplies t^k on piece i,
// local time t in [0, T_i]) solve the banded system M(T) C = b(head, Q, tail). Row layout:
//   rows 0..2            : z(0), z'(0), z''(0) of piece 0 = head
//   rows 6i+3 .. 6i+8    : junction i (between pieces i and i+1, i = 0..N-2):
//                          jerk and snap continuity, z_i(T_i) = q_i, then z, z', z'' continuity
//   rows 6N-3 .. 6N-1    : z(T), z'(T), z''(T) of piece N-1 = tail
// M is banded with 6 sub- and 6 super-diagonals; factorization and solves are O(N).
//
// Gradients: any cost K(C, T) given as partials dK/dC (C treated as free) and dK/dT is
// propagated to Q, T, head and tail by one adjoint solve G = M^-T dK/dC (propagate_gradient).
//
// Not thread-safe (internal buffers); one instance per thread. generate() allocates only when
// the number of pieces grows.

#include <Eigen/Core>

#include "porter/minco/banded_system.hpp"
#include "porter/minco/polynomial.hpp"

namespace porter::minco {

template <int Dim>
class MincoS3 {
 public:
  static_assert(Dim >= 1, "MINCO needs at least one output dimension");
  static constexpr int kStorage = Dim == 1 ? Eigen::ColMajor : Eigen::RowMajor;

  using Vector = Eigen::Matrix<double, Dim, 1>;
  /// Columns: position, velocity, acceleration.
  using BoundaryState = Eigen::Matrix<double, Dim, 3>;
  /// Interior waypoints as columns (Dim x (N-1)).
  using Waypoints = Eigen::Matrix<double, Dim, Eigen::Dynamic>;
  /// 6N x Dim; row 6i+k is the t^k coefficient of piece i.
  using Coefficients = Eigen::Matrix<double, Eigen::Dynamic, Dim, kStorage>;
  using PieceCoefficients = Eigen::Matrix<double, kPieceCoeffs, Dim, kStorage>;

  /// Builds and solves the system. waypoints must be Dim x (N-1) and durations N x 1 with
  /// every entry > 0 and finite; N >= 1. Returns false (coefficients unspecified) when the
  /// inputs are inconsistent or the factorization meets a zero/non-finite pivot.
  bool generate(const BoundaryState& head, const BoundaryState& tail, const Waypoints& waypoints,
                const Eigen::VectorXd& durations_s);

  int num_pieces() const { return num_pieces_; }
  const Eigen::VectorXd& durations() const { return durations_; }
  const Coefficients& coefficients() const { return coeffs_; }
  /// Coefficient block of piece i (6 x Dim).
  using PieceBlock = Eigen::Block<const Coefficients, kPieceCoeffs, Dim, kStorage == Eigen::RowMajor>;
  PieceBlock piece(int i) const {
    return coeffs_.template middleRows<kPieceCoeffs>(kPieceCoeffs * i);
  }
  double total_duration() const { return durations_.sum(); }

  /// Control effort sum_i int_0^T_i z'''(t)^T diag(weights) z'''(t) dt (closed form).
  double energy(const Vector& weights) const;
  /// Adds the partials of energy() w.r.t. C (C held free) and T to grad_c (6N x Dim) and
  /// grad_t (N); both must already have the right size.
  void add_energy_gradient(const Vector& weights, Coefficients& grad_c,
                           Eigen::VectorXd& grad_t) const;

  /// Propagates partials (dK/dC with C held free, dK/dT) through the MINCO map to the
  /// parameters: writes grad_q (Dim x (N-1)), grad_t (N, total derivative including the
  /// partial), grad_head and grad_tail (Dim x 3: d/d position, velocity, acceleration).
  /// Must follow a successful generate(); partial_c may alias nothing else.
  void propagate_gradient(const Coefficients& partial_c, const Eigen::VectorXd& partial_t,
                          Waypoints& grad_q, Eigen::VectorXd& grad_t, BoundaryState& grad_head,
                          BoundaryState& grad_tail);

 private:
  int num_pieces_ = 0;
  Eigen::VectorXd durations_;
  BandedSystem system_;
  Coefficients coeffs_;
  Coefficients adjoint_;
};

extern template class MincoS3<1>;
extern template class MincoS3<2>;
extern template class MincoS3<8>;

}  // namespace porter::minco
