#include "porter/backend/swept_body.hpp"

#include <algorithm>
#include <cmath>

namespace porter::backend {
namespace {

Eigen::AlignedBox3d transformed_box(const Eigen::AlignedBox3d& box_L, const InversePose& inv) {
  // World pose from the inverse: R_W_L = R_L_W^T, t_W_L = -R_W_L t_L_W.
  const Eigen::Matrix3d R = inv.R_L_W.transpose();
  const Eigen::Vector3d t = -R * inv.t_L_W;
  const Eigen::Vector3d c = R * box_L.center() + t;
  const Eigen::Vector3d e = R.cwiseAbs() * (0.5 * box_L.sizes());
  return Eigen::AlignedBox3d(c - e, c + e);
}

/// Rotation angle between two link orientations given as R_L_W.
double rotation_angle(const Eigen::Matrix3d& Ra_L_W, const Eigen::Matrix3d& Rb_L_W) {
  const double trace = (Ra_L_W.array() * Rb_L_W.array()).sum();  // tr(Ra_L_W Rb_L_W^T)
  return std::acos(std::clamp(0.5 * (trace - 1.0), -1.0, 1.0));
}

}  // namespace

SweptBody::SweptBody(const RobotModel& model, SweptBodySettings settings)
    : model_(&model), kinematics_(model), settings_(settings) {}

void SweptBody::evaluate(double t_s, BodyState& s, int up_to_link) const {
  const Trajectory& traj = *trajectory_;
  const double total = traj.total_duration_s();
  const double t = std::isnan(t_s) ? 0.0 : std::clamp(t_s, 0.0, total);
  double tau = 0.0;
  const int piece = traj.locate(t, &tau);
  evaluate_piece(piece, tau, s, up_to_link);
  s.t_s = t;
  s.at_end = t >= total;
}

void SweptBody::evaluate_piece(int piece_index, double tau_s, BodyState& s, int up_to_link) const {
  const Trajectory& traj = *trajectory_;
  const double t = traj.piece_start_time_s(piece_index) + tau_s;
  s.t_s = t;
  s.at_end = piece_index + 1 == traj.num_pieces() && tau_s >= traj.piece(piece_index).duration_s;
  s.piece = piece_index;
  s.tau_s = tau_s;
  const TrajectoryPiece& piece = traj.piece(s.piece);
  s.z = piece_derivative(piece.coeffs, s.tau_s, 0);
  s.z_dot = piece_derivative(piece.coeffs, s.tau_s, 1);
  s.z_ddot = piece_derivative(piece.coeffs, s.tau_s, 2);
  const double xd = s.z_dot[0], yd = s.z_dot[1];
  const double v2 = xd * xd + yd * yd;
  double yaw, yaw_rate;
  const double eps = settings_.speed_guard_mps;
  if (v2 >= kRestSpeed_mps * kRestSpeed_mps) {
    // The heading rule of trajectory.hpp while the base moves.
    yaw = std::atan2(piece.eta * yd, piece.eta * xd);
    yaw_rate = (xd * s.z_ddot[1] - yd * s.z_ddot[0]) / v2;
    s.heading_order = 1;
    s.dyaw_dheading = Eigen::Vector2d(-yd, xd) / (v2 + eps * eps);
  } else {
    // At rest the rule reads the first non-vanishing derivative u = +-p^(k) (k >= 2); the sign
    // does not change d yaw / d p^(k) = [-u_y, u_x] / |u|^2.
    const BaseMotion bm = traj.base_motion(t);
    yaw = bm.yaw_rad;
    yaw_rate = bm.yaw_rate_radps;
    s.heading_order = 1;
    s.dyaw_dheading.setZero();
    for (int k = 2; k <= kTrajDegree && !bm.held; ++k) {
      const TrajVector u = piece_derivative(piece.coeffs, s.tau_s, k);
      const double u2 = u[0] * u[0] + u[1] * u[1];
      if (u2 >= kVanishing * kVanishing) {
        s.heading_order = k;
        s.dyaw_dheading = Eigen::Vector2d(-u[1], u[0]) / u2;
        break;
      }
    }
  }
  s.config.base = {s.z[0], s.z[1], yaw};
  s.config.q_rad = s.z.tail<kNumArmJoints>();
  s.config_rate << xd, yd, yaw_rate, s.z_dot.tail<kNumArmJoints>();
  kinematics_.compute(s.config, up_to_link, s.kin);
}

void SweptBody::config_to_flat(const BodyState& state, const DofVector& d_config, TrajVector& d_z,
                               TrajVector& d_heading) const {
  d_z << d_config[0], d_config[1], d_config.tail<kNumArmJoints>();
  d_heading.setZero();
  d_heading.head<2>() = d_config[2] * state.dyaw_dheading;
}

void SweptBody::reset(const Trajectory& trajectory) {
  trajectory_ = trajectory;
  const Trajectory& traj = *trajectory_;
  const int pieces = traj.num_pieces();

  sample_times_.clear();
  std::vector<int>& first_sample = piece_first_sample_;
  first_sample.assign(static_cast<std::size_t>(pieces) + 1, 0);
  for (int i = 0; i < pieces; ++i) {
    first_sample[static_cast<std::size_t>(i)] = static_cast<int>(sample_times_.size());
    const double t0 = traj.piece_start_time_s(i);
    const double T = traj.piece(i).duration_s;
    const int n = std::max(1, static_cast<int>(std::ceil(T / settings_.scan_dt_s - 1e-9)));
    for (int k = 0; k < n; ++k) sample_times_.push_back(t0 + T * k / n);
  }
  first_sample[static_cast<std::size_t>(pieces)] = static_cast<int>(sample_times_.size());
  sample_times_.push_back(traj.total_duration_s());
  sample_piece_.resize(sample_times_.size());
  for (int i = 0; i < pieces; ++i) {
    for (int k = first_sample[static_cast<std::size_t>(i)]; k < first_sample[static_cast<std::size_t>(i) + 1]; ++k) {
      sample_piece_[static_cast<std::size_t>(k)] = i;
    }
  }
  sample_piece_.back() = pieces - 1;

  const std::size_t num = sample_times_.size();
  poses_.resize(num * kNumLinks);
  centers_.resize(num * kNumLinks);
  BodyState state;
  for (std::size_t k = 0; k < num; ++k) {
    evaluate(sample_times_[k], state);
    for (int j = 0; j < kNumLinks; ++j) {
      const Eigen::Matrix3d& R = state.kin.R_W_L[static_cast<std::size_t>(j)];
      const Eigen::Vector3d& t = state.kin.t_W_L[static_cast<std::size_t>(j)];
      InversePose& inv = poses_[k * kNumLinks + static_cast<std::size_t>(j)];
      inv.R_L_W = R.transpose();
      inv.t_L_W = -inv.R_L_W * t;
      centers_[k * kNumLinks + static_cast<std::size_t>(j)] =
          R * model_->links[static_cast<std::size_t>(j)].bounding_center + t;
    }
  }

  boxes_.assign(static_cast<std::size_t>(pieces) * kNumLinks, Eigen::AlignedBox3d());
  for (auto& b : link_boxes_) b.setEmpty();
  max_step_m_.fill(0.0);
  for (int j = 0; j < kNumLinks; ++j) {
    std::vector<double>& prefix = step_prefix_m_[static_cast<std::size_t>(j)];
    prefix.assign(num, 0.0);
    const Link& link = model_->links[static_cast<std::size_t>(j)];
    if (link.bounds.isEmpty()) continue;
    for (int i = 0; i < pieces; ++i) {
      const int a = first_sample[static_cast<std::size_t>(i)];
      const int b = first_sample[static_cast<std::size_t>(i) + 1];  // the piece's end sample
      Eigen::AlignedBox3d box;
      double step = 0.0;
      for (int k = a; k <= b; ++k) {
        box.extend(transformed_box(link.bounds, sample_pose(k, j)));
        if (k > a) {
          const double d = (sample_center(k, j) - sample_center(k - 1, j)).norm() +
                           link.bounding_radius_m *
                               rotation_angle(sample_pose(k - 1, j).R_L_W, sample_pose(k, j).R_L_W);
          step = std::max(step, d);
          prefix[static_cast<std::size_t>(k)] = prefix[static_cast<std::size_t>(k) - 1] + d;
        }
      }
      box.min().array() -= step;
      box.max().array() += step;
      boxes_[static_cast<std::size_t>(i) * kNumLinks + static_cast<std::size_t>(j)] = box;
      link_boxes_[static_cast<std::size_t>(j)].extend(box);
      max_step_m_[static_cast<std::size_t>(j)] = std::max(max_step_m_[static_cast<std::size_t>(j)], step);
    }
  }
}

int SweptBody::samples_within_motion(int link, int k_from, int k_last, double budget_m) const {
  if (!(budget_m > 0.0) || k_last <= k_from) return 0;
  const std::vector<double>& c = step_prefix_m_[static_cast<std::size_t>(link)];
  // First sample whose motion from k_from reaches the budget; everything before it is within.
  // Most skips are short: a few linear steps first, then a binary search over the rest.
  const double limit = c[static_cast<std::size_t>(k_from)] + budget_m;
  constexpr int kLinear = 8;
  int k = k_from + 1;
  for (; k <= k_last && k <= k_from + kLinear; ++k) {
    if (c[static_cast<std::size_t>(k)] >= limit) return k - k_from - 1;
  }
  if (k > k_last) return k_last - k_from;
  const auto it = std::lower_bound(c.begin() + k, c.begin() + k_last + 1, limit);
  return static_cast<int>(it - (c.begin() + k_from + 1));
}

int SweptBody::first_sample_at_or_after(double t_s) const {
  return static_cast<int>(std::lower_bound(sample_times_.begin(), sample_times_.end(), t_s) -
                          sample_times_.begin());
}

}  // namespace porter::backend
