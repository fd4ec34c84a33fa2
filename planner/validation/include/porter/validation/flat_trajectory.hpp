#pragma once
// Evaluation of a planned trajectory from its polynomial pieces, written for the validator
// independently of the planner's trajectory code.
//
// Flat output z(t) = [p_x, p_y, q1..q6] (m, m, rad; p in the world frame W). Piece i covers
// global times [S_i, S_i + T_i); the last piece includes its end. A time outside [0, total] is
// clamped. Derivatives at a knot are those of the piece starting there, at the very end those of
// the last piece.
//
// Base heading (README "Frames and units"): yaw = atan2(eta * dy/dt, eta * dx/dt), eta the
// piece's direction. Where the base is at rest (|dp/dt| below kRestSpeed_mps) the velocity is
// dominated by the first derivative p^(k), k >= 2, that does not vanish, v ~ p^(k) h^(k-1)/(k-1)!
// with h the time from the rest instant. The heading is taken as the direction the base is about
// to move in: +p^(k) (the sign of h^(k-1) for h > 0), or at the very end of the trajectory the
// direction it arrived from, (-1)^(k-1) p^(k). A base that does not move at all in the piece
// keeps the heading it had (start_yaw_rad before any motion).
//
// Base rates: signed speed along B's x axis v = eta |dp/dt| (m/s), yaw rate
// omega = (dx ddy - dy ddx) / |dp|^2 (rad/s), a = dv/dt and alpha = domega/dt; wheel rates of a
// differential drive with track d_w and wheel radius r_w: (v -+ d_w omega / 2) / r_w. These
// quotients are only evaluated where |dp/dt| >= a caller-given floor (see validator.hpp).
//
// Thread-safety: immutable after construction; const members are reentrant.

#include <vector>

#include <Eigen/Core>

#include "porter/validation/plan_file.hpp"

namespace porter::validation {

using FlatVector = Eigen::Matrix<double, kFlatDim, 1>;

/// Below this speed (m/s) the base counts as at rest for the heading rule.
inline constexpr double kRestSpeed_mps = 1e-6;

/// Planar motion of the base at one instant.
struct PlanarRates {
  double speed_mps = 0.0;         ///< |dp/dt|
  double v_mps = 0.0;             ///< eta |dp/dt|, along B's x axis
  double a_mps2 = 0.0;            ///< dv/dt
  double omega_radps = 0.0;       ///< yaw rate
  double alpha_radps2 = 0.0;      ///< yaw acceleration
};

class FlatTrajectory {
 public:
  /// pieces must be non-empty with durations > 0 (parse_plan_file guarantees it).
  FlatTrajectory(std::vector<PolyPiece> pieces, double start_yaw_rad);

  double duration_s() const { return starts_s_.back(); }
  int num_pieces() const { return static_cast<int>(pieces_.size()); }
  double piece_start_s(int i) const { return starts_s_[static_cast<size_t>(i)]; }
  const PolyPiece& piece(int i) const { return pieces_[static_cast<size_t>(i)]; }

  /// Piece containing t (clamped) and the local time in it.
  int locate(double t_s, double* tau_s) const;
  /// d^order z / dt^order (order 0..5; higher orders are zero).
  FlatVector derivative(double t_s, int order) const;
  /// Heading of B's x axis in W at t (rule in the header comment), in (-pi, pi].
  double yaw_rad(double t_s) const;
  /// Base rates at t from the derivatives up to the third (valid where speed_mps is not tiny).
  PlanarRates planar_rates(double t_s) const;

 private:
  double heading_at(int piece, double tau_s, bool at_end) const;

  std::vector<PolyPiece> pieces_;
  std::vector<double> starts_s_;      ///< size N + 1
  std::vector<double> held_yaw_rad_;  ///< heading held by piece i if it does not move the base
};

/// d^order/dtau^order of a polynomial piece at local time tau_s.
FlatVector poly_derivative(const PolyCoeffs& c, double tau_s, int order);

}  // namespace porter::validation
