#pragma once
// The whole-body MINCO trajectory shared by the planner, the tracker and the simulator.
//
// A trajectory is a sequence of N >= 1 polynomial pieces over the flat output
// z = [p_x, p_y, q1..q6] (kTrajDim = 8; m, m, rad x6; p in the world frame W), paper eq.
// (traj_piece). Piece i lasts T_i > 0 seconds, carries a driving direction eta_i in {+1, -1}
// (+1 forward, -1 reverse) and coefficients c_i (6 x 8): row k multiplies tau^k, where tau in
// [0, T_i] is the time local to the piece. Pieces follow each other without gaps; piece i covers
// global times [Tbar_{i-1}, Tbar_i) (the last one includes its end), so at a knot the piece that
// starts there is evaluated.
//
// Time: every query takes t_s in [0, total_duration_s()]; a t_s outside is clamped to that
// interval (NaN is treated as 0). Derivatives at a knot are those of the piece that starts
// there (right limit), except at the very end, which uses the last piece (left limit).
//
// Base heading (paper §III): yaw = atan2(eta * dp_y/dt, eta * dp_x/dt), i.e. the base's x axis
// points along the velocity when driving forward and against it in reverse. Where the base is
// (numerically) at rest, |dp/dt| < kRestSpeed_mps, the heading is that of the direction u in
// which the base is about to move (the right limit of the motion direction):
//   - let p^(k) be the first derivative of p_xy of order k >= 2 with |p^(k)| >= kVanishing; near
//     the rest instant t0 the velocity is ~ p^(k) (t - t0)^(k-1) / (k-1)!, so u = +p^(k) for odd
//     k, and for even k u = +p^(k) unless the residual velocity shows that t is still before the
//     rest instant (v . p^(k) < 0), in which case u = -p^(k) (the direction it is still moving in);
//   - at the very end of the trajectory (t_s >= total) the left limit is used instead: the
//     direction the base came from, u = (-1)^(k-1) p^(k) when v = 0 (again corrected by the sign
//     of a residual v);
//   - if every derivative of p_xy vanishes at t (the piece does not move the base), the heading is
//     held: the left-limit heading at the end of the last piece before it that moves the base,
//     or start_yaw_rad when no earlier piece moves it.
// yaw_rad is reported in (-pi, pi].
//
// Base rates: v_b = |dp/dt| >= 0, signed speed eta v_b (along the base's x axis),
// omega_b = (xd ydd - yd xdd) / |pd|^2 (independent of eta), a_b = d v_b / dt = u . pdd,
// alpha_b = d omega_b / dt = (pd x pddd)/|pd|^2 - 2 (pd x pdd)(pd . pdd)/|pd|^4.
// At a rest instant these are replaced by their limits, which exist for polynomials: writing
// pd(t) = (t - t0)^(k-1) V(t), omega_b = (V x V')/|V|^2 exactly, so omega_b and alpha_b are the
// same formulas evaluated with V = p^(k)/(k-1)!, V' = p^(k+1)/k!, V'' = 2 p^(k+2)/(k+1)! (smooth
// through the rest instant). At a held heading the rates are 0 (speed_mps still reports |pd|,
// which is then below kRestSpeed_mps).
//
// Near a rest instant the quotients above cancel catastrophically in double precision (pd is a
// sum of O(1) terms that cancels to O(h^(k-1)), and alpha_b is the difference of two O(1/h)
// terms). So below kSlowSpeed_mps, when an end t0 of the piece is a rest instant, everything is
// evaluated from the exact re-expansion around it: with h = t - t0 != 0 and d_r = p^(r)(t0),
// pd = h^(k-1) W(h), W(h) = sum_{m >= k-1} d_{m+1} h^(m-k+1) / m! (the orders below k are
// rounding residuals at t0 and are dropped: the rest is taken as exact), omega_b = (W x W')/|W|^2,
// alpha_b = (W x W'')/|W|^2 - 2 (W x W')(W . W')/|W|^4, v_b = |h|^(k-1) |W|, a_b = d v_b/dt and the
// motion direction sgn(h)^(k-1) W / |W| (this also replaces speed_mps and signed_speed_mps by
// the re-expanded, more accurate value). Relative error ~1e-12 down to 10 us from rest.
//
// Thread-safety: a Trajectory is an immutable value; all const members are reentrant. No query
// allocates memory.
// Failure: Trajectory::create() validates runtime data (it arrives from the network or a file)
// and returns a TrajectoryResult with a reason instead of throwing. Queries cannot fail.

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "porter/core/types.hpp"

namespace porter {

struct BaseLimits;  // robot_model.hpp

/// Polynomial degree of every piece (2s - 1 with s = 3, minimum jerk).
inline constexpr int kTrajDegree = 5;
inline constexpr int kTrajNumCoeffs = kTrajDegree + 1;

/// Limits Trajectory::create() enforces on runtime data (a file, the network). Beyond them a
/// trajectory is nothing a robot follows, and sampling it could overflow to infinity:
/// - a piece lasts [kTrajMinPieceDuration_s, kTrajMaxPieceDuration_s] (1 us .. 1 h), the whole
///   trajectory at most kTrajMaxTotalDuration_s (24 h);
/// - every term of every piece stays within kTrajMaxReach over the piece: |c_k| T^k <=
///   kTrajMaxReach (m or rad), so positions stay within 6 * kTrajMaxReach and, with T >= 1 us,
///   every derivative stays finite;
/// - |start_yaw_rad| <= kTrajMaxReach.
inline constexpr double kTrajMinPieceDuration_s = 1e-6;
inline constexpr double kTrajMaxPieceDuration_s = 3600.0;
inline constexpr double kTrajMaxTotalDuration_s = 86400.0;
inline constexpr double kTrajMaxReach = 1e6;

/// Below this speed the base is treated as at rest: for the heading rule at an instant that is
/// not next to a rest end of its piece, and to recognise a piece end as a rest instant.
inline constexpr double kRestSpeed_mps = 1e-5;
/// Below this speed, within a piece that has a rest instant at one of its ends (|dp/dt| <
/// kRestSpeed_mps there), the base rates come from the expansion of dp/dt around that instant
/// (see the header comment); the direct quotients lose all precision there (e.g. alpha_b off by
/// 5 rad/s^2 at 1 ms from rest in double).
inline constexpr double kSlowSpeed_mps = 1e-2;
/// A derivative of p_xy of order >= 2 smaller than this (m/s^k) counts as vanishing.
inline constexpr double kVanishing = 1e-9;

/// Coefficients of one piece: row k multiplies tau^k, column d is z_d (units m/s^k or rad/s^k).
using PieceCoeffs = Eigen::Matrix<double, kTrajNumCoeffs, kTrajDim>;

struct TrajectoryPiece {
  double duration_s = 0.0;  ///< T_i > 0
  int eta = 1;              ///< +1 forward, -1 reverse
  PieceCoeffs coeffs = PieceCoeffs::Zero();
};

/// Planar motion of the base at one instant (see the header comment for the definitions).
struct BaseMotion {
  double yaw_rad = 0.0;           ///< heading of B's x axis in W, (-pi, pi]
  int eta = 1;                    ///< direction of the piece evaluated
  double speed_mps = 0.0;         ///< v_b = |dp/dt| >= 0
  double signed_speed_mps = 0.0;  ///< eta v_b: velocity along B's x axis
  double accel_mps2 = 0.0;        ///< a_b = d v_b / dt
  double yaw_rate_radps = 0.0;    ///< omega_b
  double yaw_accel_radps2 = 0.0;  ///< alpha_b
  bool held = false;              ///< true when the base does not move and the heading is held
};

/// Wheel angular speeds and accelerations of a differential drive, paper eq. (1).
struct WheelRates {
  double left_radps = 0.0;    ///< omega_l = (2 eta v_b - d_w omega_b) / (2 r_w)
  double right_radps = 0.0;   ///< omega_r = (2 eta v_b + d_w omega_b) / (2 r_w)
  double left_radps2 = 0.0;   ///< alpha_l = (2 eta a_b - d_w alpha_b) / (2 r_w)
  double right_radps2 = 0.0;  ///< alpha_r = (2 eta a_b + d_w alpha_b) / (2 r_w)
};

/// Everything the tracker needs at one instant.
struct TrajectoryState {
  double t_s = 0.0;                        ///< the (clamped) time evaluated
  int piece = 0;                           ///< index of the piece evaluated
  TrajVector z = TrajVector::Zero();       ///< [p_x, p_y, q1..q6]  m, rad
  TrajVector z_dot = TrajVector::Zero();   ///< m/s, rad/s
  TrajVector z_ddot = TrajVector::Zero();  ///< m/s^2, rad/s^2
  BaseMotion base;
  WheelRates wheels;
};

struct TrajectoryResult;

class Trajectory {
 public:
  /// Validates and builds a trajectory. Fails (with a reason naming the piece) when there are no
  /// pieces, a duration is not finite and > 0, an eta is not +1/-1, a coefficient is not finite,
  /// start_yaw_rad is not finite, or a limit above (kTrajMin/MaxPieceDuration_s,
  /// kTrajMaxTotalDuration_s, kTrajMaxReach) is exceeded.
  static TrajectoryResult create(std::vector<TrajectoryPiece> pieces, double start_yaw_rad);

  /// first followed by second (second's t = 0 at first's end), with first's start_yaw_rad; a
  /// base that is stationary at the start of second holds first's last heading. Continuity at
  /// the junction is the caller's business (nothing is checked or adjusted).
  static Trajectory concatenate(const Trajectory& first, const Trajectory& second);

  int num_pieces() const { return static_cast<int>(pieces_.size()); }
  const std::vector<TrajectoryPiece>& pieces() const { return pieces_; }
  const TrajectoryPiece& piece(int i) const { return pieces_[static_cast<size_t>(i)]; }
  double start_yaw_rad() const { return start_yaw_rad_; }
  double total_duration_s() const { return start_times_s_.back(); }
  /// Global time at which piece i starts; piece_start_time_s(num_pieces()) is the total.
  double piece_start_time_s(int i) const { return start_times_s_[static_cast<size_t>(i)]; }

  /// Clamps t_s and finds its piece (binary search). Returns the piece index; *tau_s receives
  /// the time local to it, in [0, T_i].
  int locate(double t_s, double* tau_s) const;

  /// d^order z / dt^order at t_s (order >= 0; orders above 5 are zero; a negative order is
  /// treated as 0).
  TrajVector derivative(double t_s, int order) const;
  TrajVector position(double t_s) const { return derivative(t_s, 0); }
  TrajVector velocity(double t_s) const { return derivative(t_s, 1); }
  TrajVector acceleration(double t_s) const { return derivative(t_s, 2); }
  TrajVector jerk(double t_s) const { return derivative(t_s, 3); }
  TrajVector snap(double t_s) const { return derivative(t_s, 4); }

  double yaw_rad(double t_s) const { return base_motion(t_s).yaw_rad; }
  BaseMotion base_motion(double t_s) const;
  WheelRates wheel_rates(double t_s, double track_width_m, double wheel_radius_m) const;

  /// Full state at t_s; the wheel rates use d_w = track_width_m and r_w = wheel_radius_m.
  TrajectoryState sample(double t_s, double track_width_m, double wheel_radius_m) const;
  /// Same, with d_w and r_w from the robot's BaseLimits (include porter/core/robot_model.hpp).
  TrajectoryState sample(double t_s, const BaseLimits& base) const;

 private:
  Trajectory(std::vector<TrajectoryPiece> pieces, double start_yaw_rad);
  BaseMotion base_motion_at(int piece, double tau_s, bool at_end) const;

  std::vector<TrajectoryPiece> pieces_;
  std::vector<double> start_times_s_;  ///< size N + 1: 0, Tbar_1, ..., Tbar_N
  std::vector<double> held_yaw_rad_;   ///< heading held when piece i does not move the base
  double start_yaw_rad_ = 0.0;
};

/// Outcome of building a trajectory from runtime data: a trajectory, or why there is none.
struct TrajectoryResult {
  std::optional<Trajectory> trajectory;
  std::string error;  ///< empty on success; otherwise names the offending element and the reason
  bool ok() const { return trajectory.has_value(); }
};

/// d^order/dtau^order of one piece at local time tau_s (no clamping; order >= 0).
TrajVector piece_derivative(const PieceCoeffs& coeffs, double tau_s, int order);

/// Wheel rates of a differential drive from the base motion, paper eq. (1).
/// track_width_m = d_w, wheel_radius_m = r_w > 0.
WheelRates wheel_rates(const BaseMotion& base, double track_width_m, double wheel_radius_m);

/// The quintic that takes (p0, v0, a0) at tau = 0 to (p1, v1, a1) at tau = duration_s (> 0, finite;
/// otherwise the result is not finite). Consecutive pieces built from shared knot states are C2.
PieceCoeffs quintic_hermite(const TrajVector& p0, const TrajVector& v0, const TrajVector& a0,
                            const TrajVector& p1, const TrajVector& v1, const TrajVector& a1,
                            double duration_s);

}  // namespace porter
