#pragma once
// Parameters of the back-end solve (paper §VI-C). The problem it extends is the mid-end's, with
// the mid-end's settings (they travel in midend::MidendSolution); the collision term's own
// parameters (s_thr, weight, KC-SVSDF sample counts...) belong to the SafetyTerm
// (svsdf_safety_term.hpp and the baselines). Plain data; every field has the default the planner
// uses (config/planner/backend.yaml repeats them).

#include "porter/midend/midend_settings.hpp"

namespace porter::backend {

struct BackendSettings {
  // --- Solver (liblbfgs, as the mid-end) -------------------------------------------------------
  int max_iterations = 200;               ///< >= 1
  /// Stop when (f_{k-past} - f_k) / f_k < relative_cost_tolerance. > 0.
  double relative_cost_tolerance = 1e-5;
  int relative_cost_past = 3;             ///< >= 1
  int memory_size = 16;                   ///< [3, 64]
  /// >= 1. A line search still without a step after 8 trials (the step halved down to ~1/256 of
  /// the first, backtracking) ends the round: the next round starts from the same iterate with
  /// fresh safety-term decisions and a probed first step, which costs less than 32 more trials
  /// (bench-ablation, kc_svsdf, 20 seeds: median back-end 39/56/30/45 ms at h_b 1.1/1.0/0.9/0.8
  /// with 8, 47/72/27/41 ms with 40; same success rates).
  int max_line_search = 8;
  /// Backtracking: More-Thuente (the mid-end's choice) often fails its first line search here,
  /// where a unit of the safety gradient also moves stiff mid-end terms (wheel limits at gear
  /// switches); backtracking takes the short step instead.
  midend::LineSearch line_search = midend::LineSearch::kBacktrackingWolfe;
  /// L-BFGS's first step moves the decision vector by 1 in norm along -g; the solver works on
  /// y = x / variable_scale, so that first step moves x by variable_scale instead (the mid-end's
  /// warm start is near a minimum of the smooth terms; a unit step sweeps the trajectory through
  /// the obstacles and makes the first line search expensive). Later steps are quasi-Newton and
  /// unaffected. With probe_first_step, the upper bound of each round's probed scale. > 0.
  double variable_scale = 0.05;
  /// Before each L-BFGS round, probe the cost's curvature c along -g with one extra evaluation and
  /// make the first trial step the Newton step along -g, |g| / c (at most variable_scale). Why:
  /// inside an obstacle the safety penalty is stiff (bridge h_b 1.0 seed 20 at the warm start: c
  /// 5e8 along -g, Newton step 2e-5 against variable_scale 0.05), and the backtracking line search
  /// spent 12 halvings (~60 ms) finding it, again after every weight escalation.
  bool probe_first_step = true;
  /// Skip J_s at a line-search trial whose mid-end terms alone already exceed the current
  /// iterate's cost: the trial fails the sufficient-decrease test whatever J_s adds (J_s >= 0), so
  /// the iterates are the same as without the skip. Why: a unit trial step can sweep the
  /// trajectory across the map, where J_s costs 100x more (bridge h_b 1.1 seed 20: one such
  /// evaluation took 574 ms). Backtracking line searches only (More-Thuente interpolates the
  /// trial costs, so the skip is off there).
  bool skip_safety_above_current = true;
  // --- Until the re-check passes (Porter's choice; the paper runs the optimizer to convergence) --
  // The cubic penalty settles where it balances the smooth terms, which can leave a link just
  // inside the re-check's inflation after L-BFGS has converged. With an acceptance test passed to
  // solve():
  /// the acceptance test (the kernel trajectory check) runs on every this many accepted iterates (~1-3 ms each) and the
  /// solve stops at the first one that passes (its smoothness is then the mid-end's plus what the
  /// escape needed); 0: only after each round. >= 0.
  int recheck_every_iterations = 2;
  /// When L-BFGS stops (converged, stalled, iteration cap) before the budget while the re-check
  /// still fails, the safety weight is multiplied by this and L-BFGS restarts from its last
  /// iterate, at most max_weight_escalations times. >= 1.
  double weight_escalation_factor = 4.0;
  int max_weight_escalations = 4;  ///< >= 0
  // --- Piece windows (piece_window.hpp; with an acceptance test only) ---------------------------
  /// > 0: each piece of the warm start is checked on its own by the acceptance test, and only the
  /// runs of rejected pieces, grown by this many pieces on each side, are optimized (one window
  /// problem after the other, every other piece held exactly; the window's rounds and
  /// escalations as above, its re-checks on the window alone). A window whose rounds end without
  /// passing grows by this many pieces on each side, then twice as many, and so on up to its
  /// gear segment; a window that cannot grow any more hands the spliced trajectory to the whole
  /// problem. Why: J_s's cost is the candidate points near the pieces evaluated, and a trajectory
  /// whose collisions are a few places along it need not pay for the rest. Why 1: the window's
  /// end states are held, so a rejected piece at the end of a window could not move its end; one
  /// piece on each side is the least room that lets a detour leave and rejoin the path. 0: the
  /// whole problem from the start (the paper's back-end). >= 0.
  int window_grow_pieces = 1;
  /// When the windows cover more than this fraction of the pieces, the whole problem is solved
  /// instead: windows that large save little J_s and take away the freedom of the rest. (0, 1].
  double window_max_fraction = 0.5;
  /// Weight of the window problem's pull on the base's jerk at a cut towards the held side's,
  /// per (m/s^3)^2 (piece_window.hpp "Cuts"). >= 0; 0: the jerk may jump at a cut. Why 100: on
  /// the six runs (forest seeds 1, 5, 11, 12, 16, tunnel seed 14) whose wheel accelerations were
  /// 7-27 % over their limit at a cut without it, 100 left none over at a cut (4 of 6 succeeded
  /// against 1 of 6), 1e4 none either but held the windows so stiffly that 3 of 6 ran out of
  /// budget. A jump of 0.1 m/s^3 then costs 1, about a nearly free window's J_s, so the pull
  /// matters where the jump is large and gives way to J_s where the escape needs it.
  double window_cut_jerk_weight = 100.0;
};

}  // namespace porter::backend
