#pragma once
// Self-collision penalty of the back-end (Porter's addition; the paper's safety term J_s sees
// obstacle points only). Why: the back-end moves the arm within the mid-end's residual bound to
// push the payload out of obstacles, and can swing an arm link or the payload into the base or
// into another link on the way (bridge h_b 1.1 seed 12, kc_svsdf: after ~90 iterations the
// obstacles are clear but links 0 and 3 touch, for the remaining 500 iterations). The mid-end has
// no such term either; porter-plan re-solves it with a tighter arm residual bound instead.
//
//   J_self = w * sum_i (T_i / kappa_i) sum_k omega_k sum_(a,b) sum_(p in P_b) L(max(0, s_ab - d_a(p; q(tau_k)))),
//   L(x) = x^3,
// over the pieces i of the trajectory, trapezoid samples tau_k = k T_i / kappa_i (omega = 1/2 at
// the ends, 1 inside; kappa_i fixed by prepare() from the warm start's durations and
// sample_interval_s), the link pairs (a, b) the self-collision check examines (not allowed by the
// model, not proven free), and surface samples P_b of link b (link frame, the pair's link with
// fewer samples) carried into link a's frame by the arm configuration q; d_a is link a's signed
// distance field (robot_sdf.hpp). It depends on the joint angles only (never on the base pose).
//
// Surface samples: the nodes of a lattice of spacing h (point_spacing_m) over the link's bounds
// whose field value is within h sqrt(3)/2 of zero, projected onto the zero level along the field's
// gradient (a few steps). Every surface point is within h sqrt(3) of a sample (h sqrt(3)/2 to a
// lattice node, at most as far again to that node's projection), typically about h/2.
// Threshold: s_ab = the self-collision check's inflation bound (a pair it reports is at most that
// far apart) + the field error of link a + h sqrt(3)/2 (sampling, the typical case rather than the
// worst) + slack_m: with J_self = 0 the check's self-collision part passes in practice, not by
// proof; the kernel re-check decides. By default (relative_to_warm_start) prepare()
// lowers it for pairs that the warm start already brings closer than s_ab: see the setting.
//
// Gradient: with n = grad d_a rotated to the world, d d / d q_m = n . (J_b(p) - J_a(p))_m, the
// difference of the point's Jacobians as a point of link b and of link a (joints below a cancel);
// then through the piece polynomials (TrajectoryGradient::add_local) and, for the durations, the
// quadrature weight and the sample times' dependence on T_i.
// Pruning (exact for the value used, the C^1 field): a pair is skipped when the links' bounding
// spheres are farther apart than s_ab + the field error; the samples of b sit in a sphere tree
// whose node is skipped when the field's lower bound at its centre (LinkSdf::distance_fast's
// sd_lower, minus the error bound again) exceeds the node radius + s_ab.
//
// Thread-safety: immutable after construction except prepare()/evaluate(), which use internal
// workspaces: one term per solve.

#include <array>
#include <vector>

#include "porter/backend/chain_kinematics.hpp"
#include "porter/backend/robot_sdf.hpp"
#include "porter/backend/trajectory_gradient.hpp"
#include "porter/core/robot_model.hpp"
#include "porter/core/trajectory.hpp"
#include "porter/planner/collision/point_tree.hpp"

namespace porter::backend {

struct SelfCollisionTermSettings {
  /// w: cost per m^3 of violation and second of trajectory. > 0.
  double weight = 1e6;
  /// Largest spacing of the time samples, s (kappa_i = ceil(T_i / this), at least 2). > 0.
  double sample_interval_s = 0.05;
  /// Lattice spacing h of the surface samples, m. > 0.
  double point_spacing_m = 0.015;
  /// Added to every pair's threshold, m. >= 0.
  double slack_m = 0.005;
  /// prepare() lowers a pair's threshold to its closest approach along the warm start minus
  /// warm_start_slack_m (not below 0) where that is smaller: the term then only stops the pair
  /// from coming closer than the mid-end's trajectory (which passed the self-collision check)
  /// brought it. Why: some pairs pass within the derived threshold in every pose (the Piper's
  /// link 3 over the base: 10 715 violations along bridge h_b 1.1 seed 12's warm start), and the
  /// term would fight the path itself.
  bool relative_to_warm_start = true;
  double warm_start_slack_m = 0.003;  ///< >= 0
};

struct SelfCollisionStats {
  int samples = 0;          ///< configurations evaluated
  int pair_tests = 0;       ///< (sample, pair) combinations past the bounding-sphere test
  int point_queries = 0;    ///< field values computed
  int violations = 0;       ///< of those, closer than the pair's threshold
  double min_margin_m = 0.0;  ///< smallest d - s_ab met (0 when nothing was queried; < 0: violated)
  double cost = 0.0;
  double time_s = 0.0;
};

class SelfCollisionTerm {
 public:
  /// `pairs`: the (a, b) link pairs to keep apart (any order, a != b, both with geometry);
  /// `check_inflation_m`: the self-collision check's inflation bound (SelfCollisionChecker::
  /// inflation_bound_m()). `model` and `sdf` must outlive the term. Throws std::invalid_argument
  /// on bad settings or pairs.
  SelfCollisionTerm(const RobotModel& model, const RobotSdf& sdf, const std::vector<std::array<int, 2>>& pairs,
                    double check_inflation_m, const SelfCollisionTermSettings& settings = {});

  /// Fixes the time sampling (kappa per piece) from the warm start.
  void prepare(const Trajectory& initial);
  /// J_self of `trajectory` (same piece count as prepare()'s; otherwise kappa is re-derived from
  /// it); adds its gradient to `grad` (reset() to the trajectory's pieces by the caller).
  double evaluate(const Trajectory& trajectory, TrajectoryGradient& grad, SelfCollisionStats* stats = nullptr);

  /// J_self of one arm configuration without the time integral (cost per second), with
  /// d/dq when non-null: the integrand, for tests.
  double configuration_cost(const JointVector& q_rad, Eigen::Matrix<double, kNumArmJoints, 1>* grad_q,
                            SelfCollisionStats* stats = nullptr);

  int num_pairs() const { return static_cast<int>(pairs_.size()); }
  /// Pair k as (field link a, sampled link b), its derived threshold and the one in use, m.
  std::array<int, 2> pair(int k) const { return {pairs_[static_cast<std::size_t>(k)].a, pairs_[static_cast<std::size_t>(k)].b}; }
  double threshold_m(int k) const { return pairs_[static_cast<std::size_t>(k)].threshold_m; }
  double active_threshold_m(int k) const { return pairs_[static_cast<std::size_t>(k)].active_m; }
  /// Surface samples of link j (link frame), empty when j is not sampled by any pair.
  std::vector<Eigen::Vector3f> samples(int link) const;

 private:
  struct Pair {
    int a = 0;  ///< the link whose field is read
    int b = 0;  ///< the sampled link
    double threshold_m = 0.0;  ///< derived from the check's inflation (header comment)
    double active_m = 0.0;     ///< in use: threshold_m, or less after prepare() (relative_to_warm_start)
    double reach_m = 0.0;  ///< bounding radii + active threshold + field error: farther centres are skipped
  };

  const RobotModel* model_;
  const RobotSdf* sdf_;
  SelfCollisionTermSettings settings_;
  ChainKinematics kinematics_;
  ChainKinematics::Workspace ws_;
  std::vector<Pair> pairs_;
  planner::PointTreePool samples_;        ///< tree j = surface samples of link j (empty if unused)
  std::array<double, kNumLinks> err_m_{};  ///< field error bound of link j (fine or coarse)
  std::vector<int> kappa_;
  std::vector<double>* track_min_ = nullptr;  ///< prepare(): per pair, the smallest d met

  void set_active_threshold(Pair& e, double threshold_m) const;
  /// Calls f(piece, k, tau, q) for every time sample of every piece (kappa_ set).
  template <class F>
  void for_each_sample(const Trajectory& trajectory, F&& f) const {
    for (int i = 0; i < trajectory.num_pieces(); ++i) {
      const TrajectoryPiece& piece = trajectory.piece(i);
      const int kappa = kappa_[static_cast<std::size_t>(i)];
      for (int k = 0; k <= kappa; ++k) {
        const double tau = k * piece.duration_s / kappa;
        const TrajVector z = piece_derivative(piece.coeffs, tau, 0);
        JointVector q;
        for (int m = 0; m < kNumArmJoints; ++m) q[m] = z[2 + m];
        f(i, k, tau, q);
      }
    }
  }
};

/// The surface samples of a link's field (header comment), link frame.
std::vector<Eigen::Vector3f> surface_samples(const LinkSdf& sdf, double spacing_m);

}  // namespace porter::backend
