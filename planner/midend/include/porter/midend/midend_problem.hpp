#pragma once
// The mid-end optimization problem (paper §V, eq. midend_problem) assembled from a reference
// path: decision vector, cost and analytic gradient, and the trajectory a decision vector
// describes.
//
// Trajectory model. Segment s (eta_s = +-1, M_s pieces) is its own MincoS3<8> over
// z = [p_x, p_y, q1..q6]. Its boundary states are
//   - the global start: the first reference node with the reference's start velocity and
//     acceleration (ReferencePath::start; zero for a start at rest, the paper's case); the goal:
//     the last reference node at rest (velocity and acceleration zero). A path cut out of a longer
//     trajectory (ReferencePath::cut_start_position / cut_end_position: the back-end's piece windows) starts
//     and ends at the given states instead; the rest-boundary terms apply only where the base rests
//     there, and the min-speed term stays on the pieces next to a cut;
//   - a gear switch g between segments g and g+1: a decision state
//       position z_g (8), heading theta_g, joint velocity qd_g (6), joint acceleration qdd_g (6);
//     base velocity pinned to eta_s * v_ns * [cos theta_g, sin theta_g] on each side (so the
//     base reverses through the switch while yaw = atan2(eta zdot_y, eta zdot_x) = theta_g on
//     both sides), base acceleration zero (as REMANI), joint velocity/acceleration shared by both
//     sides (the arm stays C^2 through the switch);
//   - a rest junction g between a moving segment and a still segment (reference_path.hpp, step
//     5b: the base rests at the goal / start pose while the arm finishes / starts): the same
//     decision state as a gear switch, but the base position is the still segment's (fixed; z_g's
//     base entries and theta_g are unused and get a zero gradient) and the base velocity and
//     acceleration are zero, so the moving side ends (starts) at rest like the goal (start).
// A still segment's waypoints hold the base at its pose too (their base entries are unused), so
// its MINCO base columns are constant; pieces() writes them exactly constant, and the sampled
// base terms (wheels, min speed, base residual) are skipped on its pieces.
// Decision vector x (in this order): for each segment, its interior waypoints (8 x (M_s - 1),
// column-major) then its M_s time variables tau; then for each junction (gear switch or rest
// junction) [z_g (8), theta_g, qd_g (6), qdd_g (6)]; last, one global time-scale variable sigma. Piece
// durations are T_i = exp(sigma) * T(tau_i) (T(tau): time_map.hpp). sigma is redundant (it is 0
// in the initial guess) but gives L-BFGS a direct direction for speeding the whole trajectory
// up or down, which the penalties otherwise make a long, narrow valley in the tau_i.
//
// Cost = energy (W diagonal) + rho_T * T_total + penalties integrated over kappa samples per
// piece (wheel omega/alpha, joint q/qd/qdd, pose residuals e_b and e_m to the reference node
// nearest in time: a piece spans one or more reference edges whose nodes sit at fixed fractions
// of its duration (reference_path.hpp, step 8); a sample at fraction j/kappa uses the node with
// the nearest fraction, and both at half weight when exactly midway — for a one-edge piece,
// node i when j < kappa/2, node i+1 when j > kappa/2), plus the boundary-heading term at every
// rest boundary and the non-singular speed term (midend_settings.hpp). A piece of m
// edges uses the kappa the reference path gives it (ReferenceSegment::intervals: about
// samples_per_edge per edge, gear_sample_factor times more next to a gear switch).
//
// Rest boundaries: at the global start (when the base starts at rest) and goal (and at rest
// junctions) v = a = 0 and the sampled wheel terms see only
// the guarded (zero) rates. Near a rest instant t0, p_xy'(t) = (t - t0)^2 U(t) with
// U = j/2 + s (t - t0)/6 + c (t - t0)^2/24 (j, s, c = jerk, snap, crackle at t0), so the exact
// limits are omega_b = (U x U')/|U|^2 and alpha_b = (U x U'')/|U|^2 - 2 (U x U')(U . U')/|U|^4 at
// U = j/2, U' = s/6, U'' = c/12 (the same rule porter::Trajectory uses); they are penalized as
// one extra sample (trapezoid end weight) at each rest boundary, with |U|^2 guarded by
// boundary_jerk_guard_mps3^2/4.
//
// Penalty sampling: the hot loop runs a fast kernel (src/piece_sampler.hpp) that returns the same
// value and partials as the straightforward reference integrand (src/sample_penalty.hpp through
// minco::integrate_piece_penalty); set_reference_sampling(true) switches to the reference, which
// the tests compare against.
//
// Extra cost (extension point for the back-end's safety term): set_extra_cost() attaches a
// function K(trajectory) that receives the trajectory x describes and returns its value and,
// when asked, its partials with respect to every piece's coefficients and duration (each held
// fixed while the other varies: the convention of minco::integrate_piece_penalty). The mid-end
// propagates them through MINCO to x together with its own terms; K is reported as
// CostBreakdown::extra and can be masked with kTermExtra.
//
// Not thread-safe (workspace inside); build one per solve. evaluate() does not allocate after
// the first call (except inside an extra cost, which builds a Trajectory per call).

#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "porter/core/trajectory.hpp"
#include "porter/midend/midend_limits.hpp"
#include "porter/midend/midend_result.hpp"
#include "porter/midend/midend_settings.hpp"
#include "porter/midend/reference_path.hpp"
#include "porter/minco/minco_s3.hpp"
#include "porter/minco/penalty.hpp"

namespace porter::midend {

namespace detail {
struct SamplerConstants;  // src/piece_sampler.hpp
}

/// Cost terms, as bits, to evaluate a subset (gradient tests, diagnostics).
enum Term : std::uint32_t {
  kTermEnergy = 1u << 0,
  kTermTime = 1u << 1,
  kTermWheelVelocity = 1u << 2,
  kTermWheelAcceleration = 1u << 3,
  kTermJointPosition = 1u << 4,
  kTermJointVelocity = 1u << 5,
  kTermJointAcceleration = 1u << 6,
  kTermResidualBase = 1u << 7,
  kTermResidualArm = 1u << 8,
  kTermBoundaryHeading = 1u << 9,
  kTermMinSpeed = 1u << 10,
  kTermExtra = 1u << 11,  ///< the extra cost set by MidendProblem::set_extra_cost
  kTermAll = (1u << 12) - 1,
};

/// Partials of an extra cost with respect to each piece's coefficients and duration (pieces in
/// trajectory order; the vectors arrive sized and zeroed).
struct ExtraCostGradient {
  std::vector<PieceCoeffs> coeffs;
  std::vector<double> durations_s;
};

/// An extra cost term over the assembled trajectory. Returns K; when `grad` is non-null, adds
/// dK/dc_i and dK/dT_i to it. Must be deterministic and finite for a usable trajectory (return
/// +infinity to reject it). Called on the solving thread; must not throw.
using ExtraCost = std::function<double(const Trajectory& trajectory, ExtraCostGradient* grad)>;

class MidendProblem {
 public:
  using Minco = minco::MincoS3<kTrajDim>;

  /// `reference` must come from build_reference_path() (kOk) and `limits` must be valid().
  MidendProblem(ReferencePath reference, const MidendLimits& limits, const MidendSettings& settings);

  int num_variables() const { return num_variables_; }
  int num_segments() const { return static_cast<int>(reference_.segments.size()); }
  int num_pieces() const { return reference_.num_pieces(); }
  const ReferencePath& reference() const { return reference_; }

  /// The front-end path as a decision vector: nodes as waypoints and gear states, the reference
  /// durations, gear headings = node yaw, joint rates zero.
  Eigen::VectorXd initial_guess() const;

  /// Restricts evaluate() to a subset of Term bits (default kTermAll).
  void set_terms(std::uint32_t mask);
  /// Evaluates the sampled penalties with the slow reference integrand instead of the fast
  /// kernel (same results up to rounding; for tests).
  void set_reference_sampling(bool on) { reference_sampling_ = on; }
  /// Attaches an extra cost term (empty function: none). See the header comment.
  void set_extra_cost(ExtraCost cost) { extra_cost_ = std::move(cost); }
  /// evaluate() skips the extra cost (CostBreakdown::extra = 0, extra_skipped() true) when the
  /// other terms already sum to more than this: for a caller that only needs to know that the
  /// cost exceeds it (a line-search trial above the current iterate's cost is rejected whatever
  /// the extra term adds, as the term is >= 0). The gradient then omits the extra term. Default
  /// +infinity (never skipped).
  void set_extra_cutoff(double cutoff) { extra_cutoff_ = cutoff; }
  /// Whether the last evaluate() skipped the extra cost (set_extra_cutoff).
  bool extra_skipped() const { return extra_skipped_; }

  /// Cost at x (size num_variables()); writes the gradient to grad (same size) when non-null and
  /// the per-term split to breakdown when non-null. Returns +infinity (gradient zeroed) when a
  /// MINCO system is singular or a value is non-finite.
  double evaluate(const double* x, double* grad, CostBreakdown* breakdown);
  double evaluate(const Eigen::VectorXd& x, Eigen::VectorXd* grad, CostBreakdown* breakdown) {
    return evaluate(x.data(), grad ? grad->data() : nullptr, breakdown);
  }

  /// The decision vector of `trajectory` (one of this problem's trajectories, e.g. a solve's
  /// result) with the global time scale folded into the piece times (sigma = 0): waypoints and
  /// gear states read from the pieces, tau from their durations. False when the piece count or a
  /// piece's eta differs, or when pieces() does not map the result back to the same pieces
  /// (within 1e-6 relative).
  /// With exact = false the map back is not compared: x then describes the problem's trajectory
  /// through the same waypoints, gear states and piece durations (for a trajectory this problem
  /// cannot express exactly, e.g. one whose pieces join only C^2; false still when the piece count
  /// or an eta differs, or x describes no trajectory).
  bool decision_from_trajectory(const Trajectory& trajectory, Eigen::VectorXd& x, bool exact = true);

  /// The pieces x describes, segment after segment (eta per piece). Empty if x is unusable.
  std::vector<TrajectoryPiece> pieces(const double* x);
  /// Yaw at the start of the trajectory (the first reference node's; ReferencePath::
  /// cut_start_yaw_rad for a cut).
  double start_yaw_rad() const {
    return reference_.cut_start_position ? reference_.cut_start_yaw_rad : reference_.segments.front().nodes.front().base.yaw_rad;
  }

 private:
  struct SegmentLayout {
    int q_offset = 0;     ///< first waypoint variable
    int tau_offset = 0;   ///< first time variable
    int pieces = 0;
    std::vector<double> min_speed;  ///< per piece: speed kept by the min-speed term (0: none), m/s
    std::vector<int> kappa;       ///< per piece: sampling intervals
    std::vector<std::vector<double>> fractions;  ///< per piece: its nodes' time fractions
    bool still = false;        ///< a still segment: base held at still_base
    Eigen::Vector2d still_base = Eigen::Vector2d::Zero();
    bool rest_start = false;   ///< the base rests at the segment's start (global start, still
    bool rest_end = false;     ///< neighbour) / end (goal, still neighbour)
  };
  struct GearLayout {
    int offset = 0;       ///< [z (8), theta, qd (6), qdd (6)]
    bool rest = false;    ///< a rest junction (with a still segment): base fixed at `base`
    Eigen::Vector2d base = Eigen::Vector2d::Zero();
  };
  static constexpr int kGearVars = kTrajDim + 1 + 2 * kNumArmJoints;

  /// Builds the segment's MINCO from x; false if the system is unusable.
  bool build_segment(int s, const double* x);
  double piece_penalty(int s, int i, CostBreakdown* breakdown);
  double boundary_heading(int s, bool at_start, CostBreakdown* breakdown);
  double cut_jerk(int s, bool at_start, const Eigen::Vector2d& held, CostBreakdown* breakdown);
  double rest_rates(int s, bool at_start, CostBreakdown* breakdown);
  double extra_cost(const double* x, bool want_grad, CostBreakdown* breakdown);

  ReferencePath reference_;
  double extra_cutoff_ = std::numeric_limits<double>::infinity();
  bool extra_skipped_ = false;
  MidendLimits limits_;
  MidendSettings settings_;
  minco::PenaltyFunction penalty_;
  Minco::Vector energy_weights_;
  std::uint32_t terms_ = kTermAll;
  bool reference_sampling_ = false;
  std::shared_ptr<const detail::SamplerConstants> sampler_;
  std::vector<std::vector<std::array<double, 2>>> node_dir_;  ///< (cos, sin) of node yaws
  ExtraCost extra_cost_;
  ExtraCostGradient extra_grad_;
  int num_variables_ = 0;
  int time_scale_index_ = 0;
  std::vector<SegmentLayout> segment_layout_;
  std::vector<GearLayout> gear_layout_;

  // Workspace, one entry per segment.
  std::vector<Minco> minco_;
  std::vector<Eigen::VectorXd> durations_, dtdtau_;
  std::vector<Minco::Coefficients> grad_c_;
  std::vector<Eigen::VectorXd> grad_t_;
  std::vector<Minco::Waypoints> waypoints_, grad_q_;
  Eigen::VectorXd grad_t_total_;
  std::vector<double> sample_work_;  ///< the fast sampler's rows (piece_sampler.hpp)
};

}  // namespace porter::midend
