#pragma once
// The back-end optimization problem (paper §VI-C): the mid-end's problem (eq. midend_problem:
// MINCO over z per gear segment, energy, time, wheel and joint limits, pose residuals) plus the
// safety penalty J_s of a SafetyTerm, over the mid-end's decision vector.
//
// The mid-end's problem is reused as is (midend::MidendProblem). It has no hook for an extra cost
// yet, so J_s is attached here by a local adapter: the pieces a decision vector describes
// (MidendProblem::pieces) go to the SafetyTerm, whose gradient with respect to the raw pieces is
// pushed through a MINCO adjoint per segment (rebuilt from the pieces' boundary states, waypoints
// and durations, which reproduces the mid-end's coefficients) and mapped to the decision vector
// with the layout documented in midend_problem.hpp (waypoints, tau with T = T(tau), gear states
// [z, theta, qd, qdd] with base velocity eta v_ns [cos theta, sin theta] and base acceleration 0).
// With a mid-end hook "extra cost on (coefficients, durations) -> partials added before
// propagation" this adapter would shrink to a callback (see the issue-6 report).
//
// Not thread-safe (workspaces inside); one per solve.

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "porter/backend/safety_term.hpp"
#include "porter/core/trajectory.hpp"
#include "porter/midend/midend_limits.hpp"
#include "porter/midend/midend_problem.hpp"
#include "porter/midend/midend_settings.hpp"
#include "porter/midend/reference_path.hpp"
#include "porter/minco/minco_s3.hpp"

namespace porter::backend {

struct BackendCost {
  midend::CostBreakdown midend;  ///< the mid-end's terms
  double safety = 0.0;           ///< J_s
  SafetyStats safety_stats;
  double total() const { return midend.total() + safety; }
};

class BackendProblem {
 public:
  using Minco = minco::MincoS3<kTrajDim>;

  /// `reference` from midend::build_reference_path (kOk). `safety` must be prepare()d and outlive
  /// the problem.
  BackendProblem(midend::ReferencePath reference, const midend::MidendLimits& limits,
                 const midend::MidendSettings& settings, SafetyTerm& safety);

  int num_variables() const { return midend_.num_variables(); }
  int num_pieces() const { return midend_.num_pieces(); }
  int num_segments() const { return midend_.num_segments(); }
  midend::MidendProblem& midend() { return midend_; }

  /// The decision vector of a trajectory with this problem's structure (the mid-end's result for
  /// the same path and settings): false when the piece count or a piece's eta differs.
  bool decision_from_trajectory(const Trajectory& trajectory, Eigen::VectorXd& x) const;

  /// Cost and gradient (size num_variables(), when non-null); +infinity (gradient zeroed) when the
  /// mid-end problem is unusable at x.
  double evaluate(const double* x, double* grad, BackendCost* cost);

  /// The trajectory x describes (nullopt if x is unusable).
  std::optional<Trajectory> trajectory(const double* x);

 private:
  bool add_safety_gradient(const Trajectory& traj, const TrajectoryGradient& tgrad, const double* x,
                           double* grad);

  midend::ReferencePath reference_;
  midend::MidendLimits limits_;
  midend::MidendProblem midend_;
  SafetyTerm* safety_;
  std::vector<int> q_offset_, tau_offset_, gear_offset_, first_piece_;
  TrajectoryGradient tgrad_;
  Minco minco_;
  Minco::Coefficients partial_c_;
  Eigen::VectorXd partial_t_, grad_t_;
  Minco::Waypoints grad_q_;
};

}  // namespace porter::backend
