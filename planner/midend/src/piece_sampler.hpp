#pragma once
// Internal: the fast penalty transcription of one piece (the hot loop of the mid-end cost).
//
// It integrates exactly the integrand of sample_penalty.hpp (wheel rates, joint limits, the
// non-singular speed and the pose residuals) with the trapezoid rule of
// minco::integrate_piece_penalty, and returns the same value and partials, in three passes:
//   1. evaluation: the 8 outputs' position, velocity and acceleration and the base's jerk at all
//      kappa + 1 samples, as rows over the samples (structure of arrays in a caller-owned
//      workspace, no allocation), with the reference's Horner expressions, so the loops run
//      over contiguous samples and the compiler vectorises them;
//   2. screening: per sample, the largest normalized violation over the terms, computed with
//      branch-free loops over the samples (wheel rates, joint limits and min speed per sample;
//      the residuals per run of samples that share their nearest node, whose values are then
//      loop constants); the base residual uses the exact path's atan2-free upper bound;
//   3. the exact per-sample code (unchanged: value, then partials only for violated terms,
//      added to the coefficient gradient only for the outputs they touch) on the samples the
//      screen could not prove feasible, typically 5-15 %. Samples exactly midway between two
//      nodes, and all samples of a piece whose coefficients are too large for the screen's
//      products to be exact enough, always take this path.
// Durations change at every evaluation of a solve (every tau and the global time scale move
// with each step), so nothing is cached across evaluations; powers of t are formed only for
// the samples of pass 3.
// The slow reference (SamplePenalty + integrate_piece_penalty) is kept and the two are compared
// in tests/planner/midend/piece_sampler_test.cpp (MidendProblem::set_reference_sampling).
//
// Pure apart from the output arguments; thread-safe.

#include <array>
#include <cstdint>

#include "porter/core/types.hpp"
#include "porter/midend/midend_limits.hpp"
#include "porter/midend/midend_result.hpp"
#include "porter/midend/midend_settings.hpp"
#include "porter/minco/penalty.hpp"

namespace porter::midend::detail {

/// Per-problem constants of the sampled terms (bounds inverted once).
struct SamplerConstants {
  SamplerConstants(const MidendLimits& limits, const MidendSettings& settings, std::uint32_t terms);

  minco::PenaltyFunction penalty;
  bool wheel_velocity = false, wheel_acceleration = false;
  bool joint_position = false, joint_velocity = false, joint_acceleration = false;
  bool residual_base = false, residual_arm = false, min_speed = false;
  double w_wheel_velocity = 0.0, w_wheel_acceleration = 0.0, w_joint_position = 0.0,
         w_joint_velocity = 0.0, w_joint_acceleration = 0.0, w_residual_base = 0.0,
         w_residual_arm = 0.0, w_min_speed = 0.0;
  double half_track_m = 0.0, inv_wheel_radius = 0.0;
  double inv_omega_max2 = 0.0, inv_alpha_max2 = 0.0;
  double speed_guard2 = 0.0;
  JointVector lower_rad, upper_rad, inv_qd_max2, inv_qdd_max2;
  double inv_rho_b2 = 0.0, rho_b2 = 0.0, inv_rho_m2 = 0.0, yaw_weight_m2 = 0.0, gate2 = 0.0;
};

/// What differs per piece.
struct PieceInputs {
  int eta = 1;
  int num_edges = 1;                           ///< reference edges spanned by the piece (m)
  const RobotConfiguration* nodes = nullptr;   ///< its m + 1 reference nodes, in order
  const std::array<double, 2>* dirs = nullptr; ///< (cos, sin) of each node's yaw
  const double* fractions = nullptr;           ///< each node's time fraction: 0 .. 1 (nearest_node.hpp)
  double min_speed_mps = 0.0;  ///< > 0: keep |v_xy| above it
  bool base_still = false;     ///< a still segment's piece: no base terms (the base is held)
};

/// Rows of sample_piece's workspace, each kappa + 1 doubles long.
inline constexpr int kWorkRows = 28;
/// Doubles of workspace sample_piece needs for pieces of up to max_kappa intervals.
int sampler_work_size(int max_kappa);

/// Integrates the sampled penalties over one piece with `kappa` trapezoid intervals. `coeffs`
/// and `grad_c` are 6 x 8 row-major (row k multiplies t^k); partials are added to grad_c and
/// *grad_t, per-term integrals to *breakdown (never null). `work` holds at least
/// sampler_work_size(kappa) doubles (overwritten). Returns the integral.
double sample_piece(const SamplerConstants& k, const PieceInputs& in, const double* coeffs,
                    double duration_s, int kappa, double* work, double* grad_c, double* grad_t,
                    CostBreakdown* breakdown);

}  // namespace porter::midend::detail
