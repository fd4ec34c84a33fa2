#pragma once
// Kinematically-Coupled SVSDF (paper §VI-B, Algorithm 1) at one query point p (an obstacle point).
//
// Walking down the chain j = 0 (base), 1..6 (arm links), 7 (gripper + payload), with a joint-space
// accumulator G (9-D: [x, y, yaw] = the base's "joint 0", then q1..q6) reset per query:
//   g_j(p) from svsdf.hpp: the base over the whole trajectory (t0* = its argmin), every other link
//   in [t0* - dt, t0* + dt] (widened to cover every base time within base_tie_band_m of the
//   minimum, see svsdf.hpp: t0* is not unique when the base passes p twice or along a flat face);
//   outside (g_j > 0): D[j] = g_j, escape_j = -J_j^T grad g_j, G += escape_j;
//   inside: ball shrinking: r = r0; repeat: Y = ball_samples directions on the sphere of radius r
//     around p; KinematicFilter (j >= 2, eq. kc-svsdf-filter): keep y with
//     escape_y[i] . G[i] >= 0 for i in {j-2, j-1}, escape_y = J_j^T (p - y);
//     y* = argmax g_j over the survivors; if g_j(y*) < epsilon: D[j] = -r, escape_j = J_j^T (p - y*),
//     G += escape_j, stop; else r -= g_j(y*).
// `escape_j` only has entries on the joints that move link j, so G[0:j] += escape_j as in the paper.
//
// Choices where the paper is silent or inconsistent (see also the report of issue 6):
//  - Sign of the inside escape. Outside, -J^T grad g is the joint motion that moves the link away
//    from p (increases g). Inside, the nearest boundary is at y*, and the link frees p by moving
//    away from y*: J^T (p - y*). The paper writes J^T (y* - p), which points the other way (in 1-D:
//    a body on [0, 1] holding p = 0.2 has y* = 0 and must move by +0.2; J^T (y* - p) = -0.2). With
//    that sign, G would mix "move away" (outside) with "move towards" (inside) votes, so Porter uses
//    the escape sense for both; the filter compares like with like.
//  - Joint 0 is the planar base pose (3 columns): G[0] and escape[0] are 3-vectors and the filter
//    uses their dot product.
//  - J_j for the inside case is the point Jacobian of link j at p at t*_j(p) (the deepest instant).
//  - g_j at a ball sample y is searched in the same window around t0*(p) (also for the base), by the
//    coarse scan restricted to the instants where the link comes within ~r of p (svsdf.hpp
//    coarse_minimum_near, using p's scan profile); only the best survivor is refined, in the bracket
//    of its coarse minimum.
//  - If no sample survives the filter, that iteration uses all samples (filter_relaxed is set); a
//    joint with |G[i]| below consensus_tolerance does not constrain (no consensus yet).
//  - The first sphere is the r0 sphere; if it already has no sample outside, D = -r0 (saturated).
// Gradient of D with respect to the trajectory (and p), exact for the algorithm's output with the
// sample set fixed: r_{k+1} = r_k - g(p + r_k s_k) gives
//   dD = sum_k c_k dg_k,  c_k = prod_{m > k} (1 - grad g_m . s_m),
// with dg_k the envelope-theorem gradient of g_j at y_k (svsdf.hpp). A saturated D has no gradient;
// then g_j(p)'s is used so that the penalty still pushes the link out (documented deviation).
//
// Laziness (not a change of the algorithm): evaluate() computes the links in `needed` and only the
// links their outputs depend on. The filter of link j reads G[j-2] and G[j-1], which only links j-2
// and j-1 contribute to (joint i moves links i..7), so an inside link j >= 2 first computes links
// j-2 and j-1; D and escape of every computed link equal those of the full Algorithm 1.
//
// Thread-safety: one KcSvsdf per thread (workspace inside); SDF and SweptBody shared read-only.

#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include <Eigen/Core>

#include "porter/backend/robot_sdf.hpp"
#include "porter/backend/svsdf.hpp"
#include "porter/backend/swept_body.hpp"
#include "porter/backend/trajectory_gradient.hpp"

namespace porter::backend {

struct KcSvsdfSettings {
  SvsdfSettings svsdf;
  /// Directions on the sphere per ball-search iteration (a Fibonacci lattice, rotated about z by
  /// the golden angle every iteration: deterministic). >= 4.
  int ball_samples = 32;
  /// Termination: the worst violator's g below this, m. > 0.
  double epsilon_m = 2e-3;
  /// r0, m: larger than any depth of interest (the Scout Mini's box is 0.155 m tall, the payload
  /// tubes 0.06 m thick). > 0.
  double initial_radius_m = 0.3;
  /// Iteration cap of the ball search. >= 1.
  int max_iterations = 10;
  /// The KinematicFilter of eq. kc-svsdf-filter. false = each link's SVSDF independently (the
  /// paper's ablation baseline, svsdf_per_link).
  bool kinematic_filter = true;
  /// A joint whose accumulated |G[i]| is below this (m: escapes are J^T times unit or metric
  /// vectors) has no consensus and does not constrain the samples: eq. kc-svsdf-filter's sign test
  /// is undefined at G[i] = 0 and would otherwise follow rounding noise. >= 0.
  double consensus_tolerance = 1e-6;
};

inline constexpr std::uint32_t kAllLinks = (1u << kNumLinks) - 1;

/// First guesses of t*_j per link, s (NaN: none), e.g. a point's t* at the previous evaluation.
/// They only speed the t* scans up (SearchOptions::hint_t_s); results do not depend on them.
using TimeHints = std::array<float, kNumLinks>;

/// D[j] and everything needed to differentiate it.
struct LinkDistance {
  bool computed = false;
  double d = 0.0;                 ///< D[j], m (negative inside)
  double g = 0.0;                 ///< g_j(p) (eq. g), m
  double t_star_s = 0.0;          ///< t*_j(p)
  bool inside = false;            ///< g_j(p) <= 0: D came from the ball search
  int iterations = 0;             ///< ball-search radius updates
  bool converged = true;          ///< the ball search met epsilon (false: iteration cap)
  bool filter_relaxed = false;    ///< some iteration had no survivor
  bool saturated = false;         ///< D = -r0
  bool far = false;               ///< above the caller's cap: value only (see evaluate())
  /// Some minimum behind D lies on the edge of its search window (or of a ball sample's bracket):
  /// the gradient ignores the window's own motion there (svsdf.hpp), so it is approximate.
  bool on_window_edge = false;
  Eigen::Vector3d grad_p = Eigen::Vector3d::Zero();  ///< dD/dp
  DofVector escape = DofVector::Zero();              ///< the nabla_q^(j) added to G
  /// dD/d(trajectory) = sum_k weights[k] * terms[k].
  std::vector<PointSensitivity> terms;
  std::vector<double> weights;
};

struct KcSvsdfResult {
  std::array<LinkDistance, kNumLinks> links;
  double t0_star_s = 0.0;                ///< the base's t*
  /// The window searched for links 1..7: the base's near-minimal times widened by dt (svsdf.hpp
  /// base_tie_band_m), [t0* - dt, t0* + dt] for a sharp unique minimum.
  double window_lo_s = 0.0;
  double window_hi_s = 0.0;
  DofVector G = DofVector::Zero();       ///< sum of the computed links' escapes

  /// Adds weight * dD[link]/d(trajectory parameters) to grad.
  void add_gradient(const Trajectory& trajectory, int link, double weight, TrajectoryGradient& grad) const;
};

struct KcSvsdfStats {
  std::int64_t queries = 0;
  std::int64_t links_computed = 0;
  std::int64_t inside_links = 0;
  std::int64_t ball_iterations = 0;
  std::int64_t ball_samples = 0;      ///< samples whose g was evaluated (coarse scan)
  std::int64_t ball_filtered = 0;     ///< samples rejected by the KinematicFilter
  std::int64_t filter_relaxed = 0;
  std::int64_t window_edge_hits = 0;  ///< a windowed t* on the window's edge (dt maybe too small)
  void add(const KcSvsdfStats& o);
};

class KcSvsdf {
 public:
  KcSvsdf(const RobotSdf& sdf, const SweptBody& body, const KcSvsdfSettings& settings);

  const KcSvsdfSettings& settings() const { return settings_; }

  /// Algorithm 1 at p_W for the links in `needed` (bit j = link j; see "Laziness"). A finite d_cap
  /// says that D values above it are not used (the safety penalty passes s_thr): a link j >= 1 whose
  /// coarse scan proves g_j > d_cap is left `far` (value only, no refinement, no gradient, no
  /// escape) unless a ball search needs its escape. The base is always searched exactly (t0*).
  void evaluate(const Eigen::Vector3d& p_W, std::uint32_t needed, KcSvsdfResult& out,
                double d_cap = std::numeric_limits<double>::infinity(), const TimeHints* hints = nullptr);

  SvsdfEvaluator& svsdf() { return eval_; }
  const SvsdfEvaluator& svsdf() const { return eval_; }
  KcSvsdfStats& stats() { return stats_; }
  const KcSvsdfStats& stats() const { return stats_; }

 private:
  void ensure(int j, const Eigen::Vector3d& p, KcSvsdfResult& out, bool exact);
  double hint(int j) const {
    return hints_ ? static_cast<double>((*hints_)[static_cast<std::size_t>(j)]) : std::numeric_limits<double>::quiet_NaN();
  }
  void ball_search(int j, const Eigen::Vector3d& p, const SvsdfValue& at_p, KcSvsdfResult& out);

  KcSvsdfSettings settings_;
  SvsdfEvaluator eval_;
  SvsdfValue base_;                     ///< g_0(p) of the current query
  double d_cap_ = std::numeric_limits<double>::infinity();
  const TimeHints* hints_ = nullptr;
  ScanProfile profile_;                 ///< p's scan over the window of the link being searched
  std::vector<Eigen::Vector3d> lattice_;
  std::vector<Eigen::Vector3d> term_grads_;  ///< grad_p g at each recorded y_k
  std::vector<double> a_;                    ///< grad g_k . s_k per recorded iteration
  BodyState state_;
  KcSvsdfStats stats_;
};

}  // namespace porter::backend
