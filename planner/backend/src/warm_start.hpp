#pragma once
// The warm start: a mid-end trajectory as the mid-end's decision vector. MidendProblem has no
// inverse of its trajectory map, so this is the one place in the back-end that reads the layout
// documented in midend_problem.hpp (per segment: interior waypoints, then tau with
// T = exp(sigma) T(tau); per gear switch [z, theta, qd, qdd]; last, sigma = 0 here).
// BackendProblem::decision_from_trajectory verifies the result with MidendProblem::pieces, so a
// layout change in the mid-end is reported as a mismatch, never optimized silently.
// A mid-end API "decision vector of a trajectory" would remove this file.

#include <Eigen/Core>

#include "porter/core/trajectory.hpp"
#include "porter/midend/reference_path.hpp"

namespace porter::backend::detail {

/// x (resized to num_variables) for `trajectory`; false when the piece count or a piece's eta does
/// not match `reference`, or when num_variables is not what the documented layout gives.
bool warm_start_decision(const midend::ReferencePath& reference, int num_variables,
                         const Trajectory& trajectory, Eigen::VectorXd& x);

}  // namespace porter::backend::detail
