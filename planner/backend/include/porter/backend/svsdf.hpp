#pragma once
// The swept-volume SDF metric of one link along a trajectory (paper §VI-A):
//   g_j(p)  = min_{t in [a, b]} SDF_j(T_j(t)^-1 p)        (eq. g)
//   t*_j(p) = its argmin                                   (eq. tstar)
// with SDF_j the link's field (link_sdf.hpp) and T_j(t) its pose (swept_body.hpp).
//
// Search over [a, b]:
//   1. coarse scan of the SweptBody's cached samples in [a, b], pruned by lower bounds on the field
//      (minus its error bound): pieces are visited from the nearest swept world box and skipped
//      once that box is farther than the best value found + 2 max_step_j + 2 err; in a visited
//      piece p is mapped into the link frame at a sample and the distance to the link's own
//      bounding box prunes the same way; the remaining samples get a trilinear lookup. Between
//      samples the true distance changes by at most max_step_j (no link point moves more), so a
//      sample whose bound exceeds the pruning level by i max_step_j (+ the fields' error) also
//      bounds the next i samples, which are skipped unvisited. A first guess (SearchOptions::
//      hint_t_s, e.g. the previous evaluation's t*) is looked up first for a tight level from the
//      start. None of this changes the result: every sample that can hold a kept minimum (within
//      the pruning level) is looked up, in any order;
//   2. the scan's local minima are ranked and the best max_local_minima of them are kept (a point
//      can be approached several times: a turn, a back-and-forth of the arm), dropping those whose
//      sample value is more than one step of motion (+ 2 err) above the best;
//   3. each is refined in its sample bracket [t_{k-1}, t_{k+1}] by Illinois regula falsi on the
//      analytic derivative d/dt SDF_j(T_j(t)^-1 p) = -grad_p . (J_j(p) qdot) (the velocity of the
//      link point at p; continuous since the field is C^1), down to time_tolerance_s. Without a
//      sign change in the bracket (the trilinear ranking and the C^1 field disagree by a sample) it
//      walks on by samples; at the search's limit it keeps the limit (a boundary minimum).
// The base (link 0) is searched over the whole trajectory (full()); every other link only in the
// window [t0* - dt, t0* + dt] around the base's t0*(p) (windowed(), paper §VI-B last paragraph).
//
// Gradients at t* (envelope theorem: t* held fixed): grad_p = R_W_Lj grad SDF_j; with respect to
// the configuration d_config = -J_j(p)^T grad_p (J_j the point Jacobian of link j at p, kinematics.hpp
// — the paper's escape direction -J_j^T grad g); with respect to the flat output, `sensitivity`
// (trajectory_gradient.hpp). A t* on a window edge inside the trajectory is flagged: there the
// window's own motion (through t0*) is ignored by the gradient.
//
// Thread-safety: one evaluator per thread (workspace inside); the SDF and the SweptBody are shared
// read-only. No allocation after the first searches.

#include <cstdint>
#include <limits>
#include <vector>

#include <Eigen/Core>

#include "porter/backend/robot_sdf.hpp"
#include "porter/backend/swept_body.hpp"
#include "porter/backend/trajectory_gradient.hpp"

namespace porter::backend {

struct SvsdfSettings {
  /// Local minima of the coarse scan that are refined. >= 1.
  int max_local_minima = 3;
  /// Refinement stops when the bracket is shorter than this, s. > 0. Near a smooth minimum the
  /// value's error is quadratic in it (~1e-10 m) and the envelope gradient's linear (~1e-5 rel).
  double time_tolerance_s = 1e-5;
  /// Cap on derivative evaluations per refined minimum. >= 1.
  int max_refine_iterations = 40;
  /// Half-width dt of the window searched for links 1..7 around the base's t0*, s. > 0. It must
  /// cover the delay between the base and a link passing the same point: a payload reaching
  /// ~1 m ahead of the base at the ~0.25 m/s the mid-end gives a pass through the bridge needs ~4 s
  /// (2 s missed the payload's pass under the deck on bridge seeds: J_s ~0 with the payload 5 cm
  /// from the deck). The scan's Lipschitz skip keeps the wider window cheap.
  double window_half_width_s = 4.0;
  /// t0* as a set: the base's distance to p is often flat over a stretch (a face parallel to the
  /// motion) or equal at two passes (a manoeuvre), and a single argmin would then jump along the
  /// stretch or between the passes, dragging the windows of links 1..7 with it. The window is
  /// [first - dt, last + dt] over the base's scan samples within this band of its minimum
  /// (just t0* +- dt when the minimum is sharp and unique), m. >= 0; 0 = the literal single window.
  double base_tie_band_m = 0.02;
  /// Lean scan (the default): a search looks up only the samples within reach = max_step + 2 err
  /// of the coarse minimum (or within the tie band, when wider) instead of 2 max_step + 2 err, and
  /// its Lipschitz skip sums the per-interval motion bounds instead of the uniform max_step. Both
  /// leave every result unchanged (a kept minimum lies within reach, and a sample outside the
  /// level compares above every kept minimum as its neighbour), only fewer samples are visited;
  /// false is the reference the tests compare against. Profile scans (the ball search's) are
  /// always the reference ones, so that the ball search's sample order does not change.
  bool lean_scan = true;
  /// Accumulate the wall time spent in searches into SvsdfStats::search_time_s (benchmarks; two
  /// clock reads per search).
  bool collect_timing = false;
};

/// Per-sample lower bounds of SDF_j(T_j(t_k)^-1 p) over a searched interval: the trilinear value
/// where the scan looked the field up, the bounding-box bound where it pruned. The KC-SVSDF ball
/// search reuses the query point's profile to skip, for a sample y within r of p, every instant at
/// which the link is farther than the best value found + ~r from p (1-Lipschitz field).
struct ScanProfile {
  int k_lo = 0;                 ///< first sample index
  std::vector<double> lower;    ///< one per sample from k_lo
  std::vector<int> order;       ///< indices into `lower` by increasing bound (filled on first use)
};

/// One SVSDF value with its argmin time and gradients.
struct SvsdfValue {
  double g = std::numeric_limits<double>::infinity();  ///< eq. g, m
  double t_star_s = 0.0;                               ///< eq. tstar
  Eigen::Vector3d grad_p = Eigen::Vector3d::Zero();    ///< dg/dp, world
  DofVector d_config = DofVector::Zero();              ///< dg/d[x, y, yaw, q1..q6] at t*
  PointSensitivity sensitivity;                        ///< dg/dz, dg/dzdot at t*
  bool on_window_edge = false;
  /// The coarse scan alone showed g > skip_above (SearchOptions), or only the scan was asked for
  /// (coarse_only): g holds the scan's minimum (when the scan pruned every sample, the level that
  /// proved g > skip_above), t* its sample time; no refinement, gradients zero.
  bool far = false;
  /// First and last scan-sample times whose value is within SearchOptions::band of g (t* included).
  double band_lo_s = 0.0;
  double band_hi_s = 0.0;
};

struct SearchOptions {
  /// Receives p's scan profile (ScanProfile) when non-null.
  ScanProfile* profile = nullptr;
  /// Skip the refinement when the scan proves g > skip_above: its minimum exceeds skip_above by
  /// more than the most the refined minimum can be below it (one step of motion + twice the
  /// field's error bound). Callers that only use g below a margin pass the margin.
  double skip_above = std::numeric_limits<double>::infinity();
  /// With a finite skip_above, the scan also leaves out samples that cannot bring its minimum
  /// below skip_above + one step (+ 2 err): a far result then only bounds g from below and its t*
  /// is not the scan's argmin (when the value is needed after all, the scan is redone without
  /// this). Callers that use a far result's t* (the base's, which centres the windows) pass false.
  bool prune_above_skip = true;
  /// Fill SvsdfValue::band_lo_s / band_hi_s with this band (m); negative: t* for both.
  double band = -1.0;
  /// Only the scan: t* is its best sample, g its value, band_lo/hi over the samples within `band`
  /// (which are the only ones looked up besides the pruning's); no refinement (SvsdfValue::far).
  bool coarse_only = false;
  /// A first guess of t*, s (NaN: none). Only speeds the scan up; the result does not depend on it.
  double hint_t_s = std::numeric_limits<double>::quiet_NaN();
};

/// Work counters (the benchmark reports them).
struct SvsdfStats {
  std::int64_t searches = 0;
  std::int64_t samples_in_range = 0;   ///< cached samples in the searched intervals
  std::int64_t samples_visited = 0;    ///< of those, reached by the scan (pose applied)
  std::int64_t samples_evaluated = 0;  ///< of those, not pruned (one SDF lookup each)
  std::int64_t exact_evaluations = 0;  ///< trajectory + FK + SDF + Jacobian (refinement)
  std::int64_t skipped = 0;            ///< searches that stopped after the scan (far)
  double search_time_s = 0.0;          ///< with SvsdfSettings::collect_timing
  void add(const SvsdfStats& o) {
    searches += o.searches;
    samples_in_range += o.samples_in_range;
    samples_visited += o.samples_visited;
    samples_evaluated += o.samples_evaluated;
    exact_evaluations += o.exact_evaluations;
    skipped += o.skipped;
    search_time_s += o.search_time_s;
  }
};

class SvsdfEvaluator {
 public:
  /// The SDF and the body must outlive the evaluator; the body must be valid() when searching.
  SvsdfEvaluator(const RobotSdf& sdf, const SweptBody& body, const SvsdfSettings& settings);

  const SvsdfSettings& settings() const { return settings_; }
  const SweptBody& body() const { return *body_; }

  /// g_j over the whole trajectory (the base's full search; usable for any link).
  void full(int link, const Eigen::Vector3d& p_W, SvsdfValue& out);
  /// g_j over [t_center - dt, t_center + dt] clipped to the trajectory.
  void windowed(int link, const Eigen::Vector3d& p_W, double t_center_s, SvsdfValue& out);
  /// g_j over [t_lo, t_hi] (clipped to the trajectory; t_lo <= t_hi).
  void search(int link, const Eigen::Vector3d& p_W, double t_lo_s, double t_hi_s, SvsdfValue& out);
  /// Only the coarse scan's minimum over [t_lo, t_hi] (no refinement, no gradient): an upper bound
  /// on g_j within one sample step of motion. Cheap; used to rank ball-search samples.
  double coarse_minimum(int link, const Eigen::Vector3d& p_W, double t_lo_s, double t_hi_s);

  /// search() with options; a requested profile is left empty when the interval holds no sample.
  void search(int link, const Eigen::Vector3d& p_W, double t_lo_s, double t_hi_s, SvsdfValue& out,
              const SearchOptions& options);
  /// Coarse minimum at y over the samples of `profile` (computed at a point p with |y - p| <= radius)
  /// that can hold it; the sample index of the minimum to *argmin_k. Same accuracy as
  /// coarse_minimum over the profile's interval. Stops as soon as the running minimum falls below
  /// `abort_below` (returning that running minimum): a caller maximizing over several y needs no
  /// more once a y cannot win.
  double coarse_minimum_near(int link, const Eigen::Vector3d& y_W, ScanProfile& profile,
                             double radius_m, double abort_below, int* argmin_k);

  /// g_j over [t_lo, t_hi] refined from cached sample k only (no scan): for a point whose coarse
  /// minimum is known to be at sample k (coarse_minimum_near's argmin).
  void refine_sample(int link, const Eigen::Vector3d& p_W, int k, double t_lo_s, double t_hi_s, SvsdfValue& out);

  /// SDF_j(T_j(t)^-1 p) at exactly t_s, with d/dt to *dsdt (when non-null). Leaves the state at t_s
  /// in state().
  double evaluate_at(int link, const Eigen::Vector3d& p_W, double t_s, double* dsdt);
  const BodyState& state() const { return state_; }

  SvsdfStats& stats() { return stats_; }
  const SvsdfStats& stats() const { return stats_; }

 private:
  struct Candidate {
    double t = 0.0;
    double f = 0.0;
    bool stationary = false;  ///< found by bracketing a sign change of the time derivative
    bool in_interior = false; ///< not stationary, yet strictly inside the search (see refine())
  };
  /// Looks up the samples of [k_lo, k_hi] that can hold the minimum (values_, touched_), sample
  /// hint_k first when in range; returns the smallest value (inf if all pruned). dense_lower:
  /// also fill lower_ with a bound for every sample (a ScanProfile).
  /// Samples whose bound exceeds min(best + margin, level_cap) are not looked up; margin is
  /// 2 max_step + 2 err unless margin_override >= 0. uniform_skip: the Lipschitz skip steps by
  /// max_step (the reference) rather than by the per-interval motion bounds.
  double scan(int link, const Eigen::Vector3d& p, int k_lo, int k_hi, int hint_k, bool dense_lower,
              double level_cap, double margin_override, bool uniform_skip);
  /// Resets the entries of values_ the last scan set (values_ spans every sample of the body).
  void clear_scan();
  /// Minimizes around the sample t_k, starting with the bracket [a, b], within the search [lo, hi].
  Candidate refine(int link, const Eigen::Vector3d& p, double a, double t_k, double b, double lo, double hi);
  Candidate bracket_minimum(int link, const Eigen::Vector3d& p, double a, double t_k, double b, double lo,
                            double hi);
  void finish(int link, const Eigen::Vector3d& p, const Candidate& best, double t_lo, double t_hi,
              SvsdfValue& out);

  const RobotSdf* sdf_;
  const SweptBody* body_;
  SvsdfSettings settings_;
  BodyState state_;
  BodyState kept_;         ///< state of the best exact evaluation of the current search
  double kept_f_ = std::numeric_limits<double>::infinity();
  struct PieceRange {
    double lower = 0.0;  ///< bound on the field over the piece's samples
    int first = 0, last = 0;  ///< sample indices in the scanned range
  };
  std::vector<PieceRange> piece_order_;
  std::vector<double> values_;   ///< per body sample: the last scan's lookups, else inf
  std::vector<int> touched_;     ///< samples the last scan looked up
  std::vector<double> lower_;    ///< per sample of the scanned range, with a profile only
  std::vector<int> minima_;
  SvsdfStats stats_;
};

}  // namespace porter::backend
