#pragma once
// Parameters of the back-end solve (paper §VI-C). The collision term's own parameters (s_thr,
// weight, KC-SVSDF sample counts...) belong to the SafetyTerm (svsdf_safety_term.hpp and the
// baselines). Plain data; every field has the default the planner uses.

#include "porter/midend/midend_settings.hpp"

namespace porter::backend {

struct BackendSettings {
  /// The mid-end problem the back-end extends. Its transcription, weights, residual bounds and
  /// path-preparation fields must equal the mid-end's (the warm start is the mid-end's decision
  /// vector); its solver fields (max_iterations ... default_time_budget_s) are not used here.
  midend::MidendSettings problem;

  // --- Solver (liblbfgs, as the mid-end) -------------------------------------------------------
  int max_iterations = 200;               ///< >= 1
  /// Stop when (f_{k-past} - f_k) / f_k < relative_cost_tolerance. > 0.
  double relative_cost_tolerance = 1e-5;
  int relative_cost_past = 3;             ///< >= 1
  int memory_size = 16;                   ///< [3, 64]
  int max_line_search = 40;               ///< >= 1
  /// Backtracking: More-Thuente (the mid-end's choice) often fails its first line search here,
  /// where a unit of the safety gradient also moves stiff mid-end terms (wheel limits at gear
  /// switches); backtracking takes the short step instead.
  midend::LineSearch line_search = midend::LineSearch::kBacktrackingWolfe;
  /// L-BFGS's first step moves the decision vector by 1 in norm along -g; the solver works on
  /// y = x / variable_scale, so that first step moves x by variable_scale instead (the mid-end's
  /// warm start is near a minimum of the smooth terms; a unit step sweeps the trajectory through
  /// the obstacles and makes the first line search expensive). Later steps are quasi-Newton and
  /// unaffected. > 0.
  double variable_scale = 0.05;
  /// Budget when the caller passes a non-positive one, s (the paper's optimization budget). > 0.
  double default_time_budget_s = 0.3;
  /// Stop early once the collision term has been zero for this many consecutive iterations (the
  /// remaining iterations would only polish smoothness); 0 disables. >= 0.
  int stop_after_safe_iterations = 0;

  // --- Until the re-check passes (Porter's choice; the paper runs the optimizer to convergence) --
  // The cubic penalty settles where it balances the smooth terms, which can leave a link just
  // inside the re-check's inflation after L-BFGS has converged. With a checker passed to solve():
  /// the kernel trajectory check runs on every this many accepted iterates (~1-3 ms each) and the
  /// solve stops at the first one that passes (its smoothness is then the mid-end's plus what the
  /// escape needed); 0: only after each round. >= 0.
  int recheck_every_iterations = 2;
  /// When L-BFGS stops (converged, stalled, iteration cap) before the budget while the re-check
  /// still fails, the safety weight is multiplied by this and L-BFGS restarts from its last
  /// iterate, at most max_weight_escalations times. >= 1.
  double weight_escalation_factor = 4.0;
  int max_weight_escalations = 4;  ///< >= 0

  // --- Frozen decisions (SafetyTerm::refresh_decisions, svsdf_safety_term.hpp) ------------------
  /// The safety term's discrete decisions are taken again at the start of every L-BFGS round
  /// (weight escalations included). With this > 0, a round also ends after this many accepted
  /// iterates and the next one starts there with fresh decisions and the same weight (L-BFGS
  /// memory is lost); 0: only at rounds. Such restarts do not count as escalations. >= 0.
  int refresh_every_iterations = 0;
};

}  // namespace porter::backend
