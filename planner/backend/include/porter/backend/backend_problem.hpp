#pragma once
// The back-end optimization problem (paper §VI-C): the mid-end's problem (eq. midend_problem:
// MINCO over z per gear segment, energy, time, wheel and joint limits, pose residuals) plus the
// safety penalty J_s of a SafetyTerm, over the mid-end's decision vector.
//
// J_s is attached to a midend::MidendProblem as its extra cost (MidendProblem::set_extra_cost):
// the mid-end hands the SafetyTerm the trajectory a decision vector describes, takes back the
// partials with respect to every piece's coefficients and duration (TrajectoryGradient: t* held
// fixed, earlier durations shifted) and propagates them through its own MINCO adjoint, time map
// (T = exp(sigma) T(tau)) and gear-state mapping. Nothing here knows the decision-vector layout:
// the warm start is the mid-end's own decision vector (midend::MidendSolution).
//
// Cost split: BackendCost::midend is the mid-end's breakdown, whose `extra` is J_s (+ J_self with a
// SelfCollisionTerm, both times the safety scale); `safety` and `self_collision` repeat them
// unscaled, and total() counts them once.
//
// Not thread-safe (workspaces inside); one per solve. The SafetyTerm is used from evaluate() only.

#include <limits>
#include <optional>

#include <Eigen/Core>

#include "porter/backend/safety_term.hpp"
#include "porter/backend/self_collision_term.hpp"
#include "porter/core/trajectory.hpp"
#include "porter/midend/midend_limits.hpp"
#include "porter/midend/midend_problem.hpp"
#include "porter/midend/midend_settings.hpp"
#include "porter/midend/reference_path.hpp"

namespace porter::backend {

struct BackendCost {
  midend::CostBreakdown midend;  ///< the mid-end's terms; midend.extra = J_s
  double safety = 0.0;           ///< J_s (= midend.extra / safety scale; 0 when masked off)
  SafetyStats safety_stats;      ///< of the SafetyTerm evaluation behind `safety`
  /// J_self (self_collision_term.hpp; 0 without one), unscaled like `safety`.
  double self_collision = 0.0;
  SelfCollisionStats self_stats;
  /// J_s was not evaluated (evaluate()'s cutoff): safety = 0 and the cost is a lower bound only.
  bool safety_skipped = false;
  double total() const { return midend.total(); }
};

class BackendProblem {
 public:
  /// `reference` from midend::build_reference_path (kOk). `safety` must be prepare()d and outlive
  /// the problem; so must `self_collision` when given (prepare()d too), whose J_self is added to
  /// the extra cost next to J_s (and scaled with it).
  BackendProblem(midend::ReferencePath reference, const midend::MidendLimits& limits,
                 const midend::MidendSettings& settings, SafetyTerm& safety,
                 SelfCollisionTerm* self_collision = nullptr);
  BackendProblem(const BackendProblem&) = delete;  // the extra cost captures `this`
  BackendProblem& operator=(const BackendProblem&) = delete;

  int num_variables() const { return midend_.num_variables(); }
  int num_pieces() const { return midend_.num_pieces(); }
  int num_segments() const { return midend_.num_segments(); }
  /// The underlying problem (term masks for tests: kTermExtra alone is J_s).
  midend::MidendProblem& midend() { return midend_; }


  /// Cost and gradient (size num_variables(), when non-null); +infinity (gradient zeroed) when the
  /// mid-end problem is unusable at x or J_s is not finite. When the mid-end terms alone exceed
  /// `cutoff`, J_s is not evaluated (cost->safety_skipped): the result is then the mid-end terms
  /// alone, above the cutoff but below the true cost, with their gradient only.
  double evaluate(const double* x, double* grad, BackendCost* cost,
                  double cutoff = std::numeric_limits<double>::infinity());

  /// Multiplies J_s (and its gradient) by scale > 0 in evaluate() (the back-end's weight
  /// escalation); BackendCost::midend.extra (and total()) then hold the scaled value,
  /// BackendCost::safety the unscaled J_s. Default 1.
  void set_safety_scale(double scale) { safety_scale_ = scale; }
  double safety_scale() const { return safety_scale_; }

  /// The trajectory x describes (nullopt if x is unusable).
  std::optional<Trajectory> trajectory(const double* x);

 private:
  double safety_cost(const Trajectory& trajectory, midend::ExtraCostGradient* grad);

  midend::MidendProblem midend_;
  SafetyTerm* safety_;
  SelfCollisionTerm* self_ = nullptr;
  TrajectoryGradient tgrad_;
  SafetyStats stats_;
  SelfCollisionStats self_stats_;
  double last_js_ = 0.0;    ///< unscaled J_s of the last extra-cost call
  double last_self_ = 0.0;  ///< unscaled J_self of the last extra-cost call
  double safety_scale_ = 1.0;
};

}  // namespace porter::backend
