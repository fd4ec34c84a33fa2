#pragma once
// Gradients of scalar costs with respect to the raw parameters of a porter::Trajectory: every
// piece's coefficient block c_i (6 x 8, C held free, i.e. before the MINCO map) and every duration
// T_i. The back-end hands these to the MINCO adjoint (minco_s3.hpp propagate_gradient).
//
// A quantity evaluated at one instant t of the trajectory (an SVSDF value at its t*) depends on the
// trajectory through z(t) and, via the heading rule, through one derivative z^(k)(t) of the base
// position: k = 1 while the base moves (yaw = atan2(eta ydot, eta xdot)), the first non-vanishing
// derivative k >= 2 at a rest instant (trajectory.hpp). With t held fixed in absolute time
// (envelope theorem, paper §VI / algorithms.md §1.4), piece i's local time tau = t - sum_{k<i} T_k
// shifts when an earlier duration changes:
//   d/dc_i  += beta(tau) dz^T + beta^(k)(tau) dh^T
//   d/dT_m  -= dz . zdot(t) + dh . z^(k+1)(t)            for every m < i,
// and T_i itself receives nothing. The shift is -d/dt of the quantity along the trajectory, which
// vanishes at an interior (stationary) minimum: such instants are flagged and get exactly zero
// (rather than the residual of the t* search). An instant anchored at the end of the trajectory
// (t* = T_total, a boundary minimum) moves with the end instead: d/dT_{N-1} += dz . zdot + dh . z^(k+1).
//
// Not thread-safe; one per thread (merge with add()). No allocation after reset() for a given size.

#include <vector>

#include "porter/core/trajectory.hpp"
#include "porter/core/types.hpp"

namespace porter::backend {

/// Partial derivatives of a quantity with respect to the flat output at one instant.
struct PointSensitivity {
  double t_s = 0.0;       ///< the instant, global time
  int piece = 0;          ///< piece containing it (Trajectory::locate)
  double tau_s = 0.0;     ///< local time in that piece
  bool at_end = false;    ///< anchored at the trajectory's end (see header)
  bool stationary = false;  ///< an interior minimum in time: the shift term is exactly zero
  TrajVector d_z = TrajVector::Zero();        ///< d/dz    [p_x, p_y, q1..q6]
  int heading_order = 1;                      ///< k: the derivative the heading is read from
  TrajVector d_heading = TrajVector::Zero();  ///< d/dz^(k) (through the heading rule)
};

class TrajectoryGradient {
 public:
  /// Zeroes the gradient for a trajectory of num_pieces pieces.
  void reset(int num_pieces);
  int num_pieces() const { return static_cast<int>(durations_.size()); }

  /// Adds weight * (the sensitivity pushed through the piece polynomials of `traj`).
  void add(const Trajectory& traj, const PointSensitivity& s, double weight);
  /// Adds weight * (beta(tau) d_z^T + beta^(order)(tau) d_zk^T) to piece's coefficients, for costs
  /// integrated over a piece (the caller handles the duration terms of its quadrature).
  void add_local(int piece, double tau_s, const TrajVector& d_z, int order, const TrajVector& d_zk,
                 double weight);
  /// Adds to d/dT_i directly.
  void add_duration(int piece, double value) { durations_[static_cast<std::size_t>(piece)] += value; }
  /// Adds another gradient of the same size (per-thread partial sums).
  void add(const TrajectoryGradient& other);

  /// d/dc_i and d/dT_i. Call after the last add().
  const PieceCoeffs& coeffs(int piece) const { return coeffs_[static_cast<std::size_t>(piece)]; }
  double duration(int piece) const;

 private:
  std::vector<PieceCoeffs> coeffs_;
  std::vector<double> durations_;
  /// Shifts still to be applied to every earlier piece (suffix sums, resolved in duration()).
  std::vector<double> shift_;
};

}  // namespace porter::backend
