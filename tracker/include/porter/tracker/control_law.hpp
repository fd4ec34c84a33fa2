#pragma once
// The base tracking law of porter-tracker: feed-forward (v_r, omega_r) from the trajectory plus
// Kanayama-style feedback on the pose error, then the wheel speed and acceleration limits of a
// differential drive. Pure functions of (reference, measured pose, gains, limits), so tests check
// them directly.
//
// Frames and signs. Poses are of the base frame B in the world W (BasePose: x_m, y_m, yaw_rad).
// The feedback error is the reference pose expressed in the measured B (Kanayama 1990):
//   e_x   =  cos(yaw) (x_r - x) + sin(yaw) (y_r - y)     along x_B, m
//   e_y   = -sin(yaw) (x_r - x) + cos(yaw) (y_r - y)     along y_B, m
//   e_yaw = wrap(yaw_r - yaw)                            rad, in (-pi, pi]
//
// Law (v_r signed: negative in reverse, eta = -1):
//   v     = v_r cos(e_yaw) + k_x e_x
//   omega = omega_r + v_r k_y e_y + (k_yaw |v_r| + k_yaw_rest) sin(e_yaw)
//
// Stability. With V = (e_x^2 + e_y^2)/2 + (1 - cos e_yaw)/k_y and the error dynamics of a unicycle
//   de_x = omega e_y - v + v_r cos e_yaw,  de_y = -omega e_x + v_r sin e_yaw,  de_yaw = omega_r - omega,
// the law gives dV/dt = -k_x e_x^2 - ((k_yaw |v_r| + k_yaw_rest)/k_y) sin^2 e_yaw <= 0 for any sign of
// v_r whenever k_x > 0, k_y > 0, k_yaw >= 0, k_yaw_rest >= 0 (Kanayama's original law has v_r
// k_yaw, which makes dV/dt positive in reverse; |v_r| keeps it negative for eta = -1). All three
// errors converge to 0 (|e_yaw| < pi) when the reference keeps moving (|v_r| bounded away from
// 0 and v_r, omega_r bounded with bounded derivatives, Barbalat's lemma): e_y is driven only
// through v_r, so a base at rest corrects e_x and e_yaw but not a pure cross-track offset.
// Linearised about a straight line at speed v_r, e_x decays at rate k_x and (e_y, e_yaw) obey
// s^2 + (k_yaw |v_r| + k_yaw_rest) s + k_y v_r^2 = 0: natural frequency |v_r| sqrt(k_y) (a spatial
// frequency of sqrt(k_y) rad per metre travelled) and damping (k_yaw + k_yaw_rest / |v_r|) /
// (2 sqrt(k_y)). k_yaw_rest is there for the heading at low speed; it over-damps (slows) the
// lateral convergence, so it is kept small and k_yaw chosen for damping 1 at cruise speed.
// The limits below only scale the command, so they keep its direction in wheel space; a command
// the limits cut is no longer the law's and the Lyapunov argument holds only while unsaturated.
//
// Limits. Wheel speeds omega_l,r = (v -/+ d_w omega / 2) / r_w. The speed limit scales (v, omega)
// together (keeping the curvature) so that max |omega_l,r| <= wheel_omega_max_radps; the
// acceleration limit then scales the change of the wheel speeds from the previous command so
// that each changes by at most wheel_alpha_max_radps2 * dt. A previous command within the speed
// limit and a target within it give a result within it (the box is convex).
//
// Thread-safety: pure functions, reentrant. Failure: none; non-finite inputs give a zero command
// (see limit_command) so a NaN never reaches a motor.

#include "porter/core/robot_model.hpp"
#include "porter/core/types.hpp"

namespace porter::tracker {

/// Wraps an angle to (-pi, pi], rad.
double wrap_angle(double angle_rad);

/// Reference of the base at one instant.
struct BaseReference {
  BasePose pose;               ///< T_W_B of the reference (x_m, y_m, yaw_rad)
  double v_mps = 0.0;          ///< signed speed along x_B (eta * |dp/dt|), m/s
  double omega_radps = 0.0;    ///< yaw rate, rad/s
};

/// Feedback gains (see the header comment for their meaning and the stability conditions).
struct TrackingGains {
  double k_x_1ps = 1.5;          ///< along-track gain, 1/s (> 0)
  double k_y_1pm2 = 4.0;         ///< cross-track gain, 1/m^2 (> 0)
  double k_yaw_1pm = 3.0;        ///< heading gain per metre travelled, 1/m (>= 0)
  double k_yaw_rest_1ps = 0.5;   ///< heading gain independent of speed, 1/s (>= 0)
};

/// A base velocity command (of B, expressed in B).
struct BaseCommand {
  double v_mps = 0.0;
  double omega_radps = 0.0;
};

/// Pose error of the reference relative to the measured pose, in the measured base frame.
struct PoseError {
  double x_m = 0.0;
  double y_m = 0.0;
  double yaw_rad = 0.0;
};

/// Reference minus measured, expressed in the measured B (the law's error).
PoseError error_in_measured_frame(const BasePose& reference, const BasePose& measured);
/// Reference minus measured, expressed in B at the reference (along / cross track, TRACKER_STATUS).
PoseError error_in_reference_frame(const BasePose& reference, const BasePose& measured);

/// The unlimited law.
BaseCommand tracking_law(const BaseReference& reference, const BasePose& measured,
                         const TrackingGains& gains);

struct LimitedCommand {
  BaseCommand command;
  bool speed_limited = false;   ///< the wheel speed limit scaled the command
  bool accel_limited = false;   ///< the wheel acceleration limit scaled the change
  bool non_finite = false;      ///< the desired command was not finite; zero was returned
};

/// Applies the wheel speed limit to `desired` and the wheel acceleration limit relative to
/// `previous` over dt_s (>= 0). Uses wheel_radius_m, track_width_m, wheel_omega_max_radps and
/// wheel_alpha_max_radps2 of `limits`. A non-finite desired command gives zero.
LimitedCommand limit_command(const BaseCommand& desired, const BaseCommand& previous, double dt_s,
                             const BaseLimits& limits);

/// Law plus limits in one call: the command for one control period.
struct BaseControl {
  BaseCommand unlimited;
  LimitedCommand limited;
  PoseError error;  ///< in the measured frame
};
BaseControl base_control(const BaseReference& reference, const BasePose& measured,
                         const BaseCommand& previous, double dt_s, const TrackingGains& gains,
                         const BaseLimits& limits);

}  // namespace porter::tracker
