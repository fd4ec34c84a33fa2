#pragma once
// Internal: the mid-end's last check of its own result (never a silently wrong trajectory). The optimizer enforces limits by penalties at samples, so a run that stops early
// or lands in a poor local minimum can return a trajectory that breaks them; this samples the
// final trajectory through porter::Trajectory (core's rates, not the optimizer's formulas) and
// reports the first gross violation.
// Pure; thread-safe.

#include <string>
#include <vector>

#include "porter/core/trajectory.hpp"
#include "porter/midend/midend_limits.hpp"

namespace porter::midend::detail {

/// Samples every step_s (and at the end): finite values, wheel |omega| and |alpha|, joint
/// |qd| and |qdd| at most (1 + tolerance) times their limits, joint positions at most
/// tolerance * range outside their bounds, and no base reversal inside a segment (the base
/// velocity turning by more than 90 degrees between samples above 1e-6 m/s, within pieces
/// that piece_segment maps to the same segment). Returns "" when the trajectory passes, else
/// a description of the first violation ("wheel acceleration 1.31 x limit at t = 51.20 s").
std::string verify_trajectory(const Trajectory& trajectory, const std::vector<int>& piece_segment,
                              const MidendLimits& limits, double tolerance, double step_s);

}  // namespace porter::midend::detail
