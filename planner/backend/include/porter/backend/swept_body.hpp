#pragma once
// The motion of every planning link along a whole-body trajectory (the T_j(t) of paper eq. g):
//   - exact evaluation at any instant: flat output z(t), heading by the trajectory's rule (computed
//     here as atan2(eta ydot, eta xdot) while the base moves, from Trajectory::base_motion at rest),
//     forward kinematics up to the link of interest (chain_kinematics.hpp), configuration rates and
//     d yaw / d pdot (for gradients through the heading);
//   - a cache of every link's inverse pose T_Lj_W at scan samples (spacing <= scan_dt_s, the
//     pieces' ends included), read by the coarse t* scans;
//   - per piece and per link, the world AABB of the link's geometry swept over the piece (the
//     paper's AABB prefilter), inflated by the largest displacement of any link point between two
//     consecutive samples so that the motion between samples is covered.
//
// Frames: world W; link frames Lj as in kinematics.hpp. Times in seconds from the trajectory start.
// Thread-safety: reset() needs exclusive access; every const member is reentrant. reset() allocates
// only when the trajectory needs more samples than any before.

#include <array>
#include <optional>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "porter/backend/chain_kinematics.hpp"
#include "porter/core/robot_model.hpp"
#include "porter/core/trajectory.hpp"
#include "porter/core/types.hpp"

namespace porter::backend {

struct SweptBodySettings {
  /// Largest spacing of the scan samples, s. At the Scout Mini's ~1 m/s and the Piper's joint
  /// speeds, 0.02 s keeps consecutive link poses within ~2-3 cm. > 0.
  double scan_dt_s = 0.02;
  /// epsilon in d yaw / d pdot = [-ydot, xdot] / (|pdot|^2 + epsilon^2), > 0: only guards the
  /// division; kept far below the speeds met after leaving rest (at t after a rest instant the
  /// speed grows like t^2 while d pdot / d c grows like t^2 too, so the sensitivity to the
  /// coefficients stays bounded without fading; a larger guard biases it near the start and goal).
  /// At a rest instant the heading comes from a higher derivative, handled exactly.
  double speed_guard_mps = 1e-7;
};

/// Inverse rigid transform, stored to map world points into a link frame with one product.
struct InversePose {
  Eigen::Matrix3d R_L_W;
  Eigen::Vector3d t_L_W;
  Eigen::Vector3d apply(const Eigen::Vector3d& p_W) const { return R_L_W * p_W + t_L_W; }
};

/// Everything known about the robot at one instant.
struct BodyState {
  double t_s = 0.0;
  int piece = 0;
  double tau_s = 0.0;
  bool at_end = false;                       ///< t_s is the trajectory's end
  TrajVector z = TrajVector::Zero();
  TrajVector z_dot = TrajVector::Zero();
  TrajVector z_ddot = TrajVector::Zero();
  RobotConfiguration config;
  DofVector config_rate = DofVector::Zero();  ///< [xdot, ydot, yaw rate, qdot]
  /// The heading is read from p_xy^(heading_order): 1 while moving, the first non-vanishing
  /// derivative at rest; d yaw / d p_xy^(heading_order) (zero for a held heading).
  int heading_order = 1;
  Eigen::Vector2d dyaw_dheading = Eigen::Vector2d::Zero();
  ChainKinematics::Workspace kin;
};

class SweptBody {
 public:
  explicit SweptBody(const RobotModel& model, SweptBodySettings settings = {});

  /// Takes a copy of the trajectory and rebuilds the sample cache and the piece boxes.
  void reset(const Trajectory& trajectory);
  bool valid() const { return trajectory_.has_value(); }

  const RobotModel& model() const { return *model_; }
  const SweptBodySettings& settings() const { return settings_; }
  const Trajectory& trajectory() const { return *trajectory_; }
  double duration_s() const { return trajectory_->total_duration_s(); }

  /// Exact state at t_s (clamped to [0, duration]), link poses for links 0..up_to_link.
  void evaluate(double t_s, BodyState& state, int up_to_link = kEndEffectorLink) const;
  /// The same from piece i's polynomial at its local time tau_s (at a knot, the piece that ends
  /// there rather than the one that starts there: for costs integrated piece by piece).
  void evaluate_piece(int piece, double tau_s, BodyState& state, int up_to_link = kEndEffectorLink) const;
  const ChainKinematics& kinematics() const { return kinematics_; }
  /// Maps d/d[x, y, yaw, q] at `state` to the flat-output sensitivity there (d/dz and d/dz^(k),
  /// k = state.heading_order).
  void config_to_flat(const BodyState& state, const DofVector& d_config, TrajVector& d_z,
                      TrajVector& d_heading) const;

  // --- Scan samples -----------------------------------------------------------------------------
  int num_samples() const { return static_cast<int>(sample_times_.size()); }
  double sample_time(int k) const { return sample_times_[static_cast<std::size_t>(k)]; }
  const InversePose& sample_pose(int k, int link) const {
    return poses_[static_cast<std::size_t>(k) * kNumLinks + static_cast<std::size_t>(link)];
  }
  /// Centre of link's bounding sphere (RobotModel Link::bounding_center) at sample k, world.
  const Eigen::Vector3d& sample_center(int k, int link) const {
    return centers_[static_cast<std::size_t>(k) * kNumLinks + static_cast<std::size_t>(link)];
  }
  /// First sample of piece i (piece_first_sample(num_pieces) is the end sample); piece i's samples
  /// are [piece_first_sample(i), piece_first_sample(i + 1)], both ends included.
  int piece_first_sample(int piece) const { return piece_first_sample_[static_cast<std::size_t>(piece)]; }
  /// The piece sample k belongs to (the end sample belongs to the last piece).
  int sample_piece(int k) const { return sample_piece_[static_cast<std::size_t>(k)]; }
  /// Smallest k with sample_time(k) >= t_s (num_samples() when none).
  int first_sample_at_or_after(double t_s) const;
  /// Upper bound on how far any point of `link` moves between two consecutive samples, m.
  double max_step_m(int link) const { return max_step_m_[static_cast<std::size_t>(link)]; }
  /// Upper bound on how far any point of `link` moves from sample k_from to sample k_to
  /// (k_from <= k_to): the sum of the per-interval bounds (each <= max_step_m), m. Exact prefix
  /// sums, so the bound over a span is never below the distance between its two end poses.
  double motion_bound_m(int link, int k_from, int k_to) const {
    const std::vector<double>& c = step_prefix_m_[static_cast<std::size_t>(link)];
    return c[static_cast<std::size_t>(k_to)] - c[static_cast<std::size_t>(k_from)];
  }
  /// Largest i in [0, k_last - k_from] with motion_bound_m(link, k_from, k_from + i) < budget_m
  /// (0 when budget_m <= 0): samples k_from + 1 .. k_from + i are within budget_m of k_from's pose.
  int samples_within_motion(int link, int k_from, int k_last, double budget_m) const;

  // --- Prefilter boxes -------------------------------------------------------------------------
  /// World AABB of link's geometry over piece i (inflated as in the header comment).
  const Eigen::AlignedBox3d& piece_box(int link, int piece) const {
    return boxes_[static_cast<std::size_t>(piece) * kNumLinks + static_cast<std::size_t>(link)];
  }
  /// Union of piece_box over all pieces.
  const Eigen::AlignedBox3d& link_box(int link) const { return link_boxes_[static_cast<std::size_t>(link)]; }

 private:
  const RobotModel* model_;
  ChainKinematics kinematics_;
  SweptBodySettings settings_;
  std::optional<Trajectory> trajectory_;
  std::vector<double> sample_times_;
  std::vector<int> piece_first_sample_;
  std::vector<int> sample_piece_;
  std::vector<InversePose> poses_;
  std::vector<Eigen::Vector3d> centers_;
  std::vector<Eigen::AlignedBox3d> boxes_;
  std::array<Eigen::AlignedBox3d, kNumLinks> link_boxes_;
  std::array<double, kNumLinks> max_step_m_{};
  /// Per link: prefix sums of the per-interval motion bounds, [k] = sum over intervals < k.
  std::array<std::vector<double>, kNumLinks> step_prefix_m_;
};

}  // namespace porter::backend
