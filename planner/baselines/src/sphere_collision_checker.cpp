#include "porter/baselines/sphere_collision_checker.hpp"

#include "porter/planner/angle.hpp"

#include <algorithm>
#include <cmath>

namespace porter::baselines {
namespace {

using planner::CollisionResult;

CollisionResult hit(int link, int other = -1) {
  CollisionResult r;
  r.in_collision = true;
  r.link = link;
  r.other_link = other;
  return r;
}

bool finite(const RobotConfiguration& c) {
  return std::isfinite(c.base.x_m) && std::isfinite(c.base.y_m) && std::isfinite(c.base.yaw_rad) && c.q_rad.allFinite();
}

}  // namespace

SphereCollisionChecker::SphereCollisionChecker(const RobotModel& model, const SphereCheckerSettings& settings)
    : model_(&model), settings_(settings), kinematics_(model), spheres_(cover_robot(model, settings.cover)) {
  // Reach: the arm stretched out, every joint offset and every sphere at its farthest.
  double chain = 0.0;
  for (const ArmJoint& j : model.joints) chain += j.T_parent_joint.translation().norm();
  chain += model.T_L6_EE.translation().norm();
  for (const LinkSpheres& s : spheres_) {
    for (const Eigen::Vector3d& c : s.centers_L) reach_m_ = std::max(reach_m_, c.norm() + s.radius_m);
  }
  reach_m_ += chain;
}

void SphereCollisionChecker::set_map(const OccupancyGrid& occupancy_W) {
  field_ = DistanceField::build(occupancy_W, Eigen::AlignedBox3d(), settings_.max_distance_m);
  const Eigen::AlignedBox3d b = occupancy_W.bounds_W();
  map_xy_ = Eigen::AlignedBox2d(b.min().head<2>(), b.max().head<2>());
  resolution_m_ = occupancy_W.resolution_m();
}

double SphereCollisionChecker::step_m() const {
  return settings_.motion_step_m > 0.0 ? settings_.motion_step_m : resolution_m_;
}

CollisionResult SphereCollisionChecker::check_links(const RobotConfiguration& c, int up_to_link, bool environment) const {
  if (!finite(c)) return hit(0);
  if (environment && (field_.empty() || !map_xy_.contains(Eigen::Vector2d(c.base.x_m, c.base.y_m)))) return hit(0);
  if (up_to_link > 0) {
    for (int i = 0; i < kNumArmJoints; ++i) {
      const ArmJoint& j = model_->joints[static_cast<std::size_t>(i)];
      if (c.q_rad[i] < j.lower_rad - 1e-6 || c.q_rad[i] > j.upper_rad + 1e-6) return hit(i + 1);
    }
  }
  backend::ChainKinematics::Workspace ws;
  kinematics_.compute(c, up_to_link, ws);
  std::array<std::vector<Eigen::Vector3d>, kNumLinks> world;
  for (int l = 0; l <= up_to_link; ++l) {
    const LinkSpheres& s = spheres_[static_cast<std::size_t>(l)];
    auto& w = world[static_cast<std::size_t>(l)];
    w.reserve(s.centers_L.size());
    for (const Eigen::Vector3d& cl : s.centers_L) {
      const Eigen::Vector3d p = ws.R_W_L[static_cast<std::size_t>(l)] * cl + ws.t_W_L[static_cast<std::size_t>(l)];
      if (environment) {
        if (!map_xy_.contains(p.head<2>())) return hit(l);
        if (l >= 1 && p.z() - s.radius_m < 0.0) return hit(l);
        if (field_.distance(p) < s.radius_m) return hit(l);
      }
      w.push_back(p);
    }
  }
  if (!settings_.check_self_collision) return {};
  for (int a = 0; a <= up_to_link; ++a) {
    for (int b = a + 1; b <= up_to_link; ++b) {
      if (model_->allowed_collisions[static_cast<std::size_t>(a)][static_cast<std::size_t>(b)]) continue;
      const double r = spheres_[static_cast<std::size_t>(a)].radius_m + spheres_[static_cast<std::size_t>(b)].radius_m;
      for (const Eigen::Vector3d& pa : world[static_cast<std::size_t>(a)]) {
        for (const Eigen::Vector3d& pb : world[static_cast<std::size_t>(b)]) {
          if ((pa - pb).squaredNorm() < r * r) return hit(a, b);
        }
      }
    }
  }
  return {};
}

CollisionResult SphereCollisionChecker::check(const RobotConfiguration& config) const {
  return check_links(config, kEndEffectorLink);
}

CollisionResult SphereCollisionChecker::check_base(const BasePose& base) const {
  RobotConfiguration c;
  c.base = base;
  return check_links(c, 0);
}

CollisionResult SphereCollisionChecker::check_motion(const RobotConfiguration& from, const RobotConfiguration& to) const {
  if (!finite(from) || !finite(to)) return hit(0);
  const double dyaw = planner::angle_difference_rad(to.base.yaw_rad, from.base.yaw_rad);
  // A sphere centre moves at most |dxy| + reach |dyaw| + reach sum |dq| along the segment.
  const double bound = std::hypot(to.base.x_m - from.base.x_m, to.base.y_m - from.base.y_m) +
                       reach_m_ * (std::abs(dyaw) + (to.q_rad - from.q_rad).cwiseAbs().sum());
  const int n = std::max(1, static_cast<int>(std::ceil(bound / step_m())));
  for (int k = 0; k <= n; ++k) {
    const double s = static_cast<double>(k) / n;
    RobotConfiguration c;
    c.base = {from.base.x_m + s * (to.base.x_m - from.base.x_m), from.base.y_m + s * (to.base.y_m - from.base.y_m),
              from.base.yaw_rad + s * dyaw};
    c.q_rad = from.q_rad + s * (to.q_rad - from.q_rad);
    const CollisionResult r = check(c);
    if (r.in_collision) return r;
  }
  return {};
}

double SphereCollisionChecker::inflation_bound_m(int /*link*/) const {
  constexpr double kSqrt3 = 1.7320508075688772;
  return kSqrt3 * settings_.cover.cell_m + 0.5 * kSqrt3 * resolution_m_;
}

CollisionResult SphereCollisionChecker::check_trajectory(const Trajectory& traj) const {
  return check_samples(traj, true);
}

CollisionResult SphereCollisionChecker::check_trajectory_self(const Trajectory& traj) const {
  if (!settings_.check_self_collision) return {};
  return check_samples(traj, false);
}

CollisionResult SphereCollisionChecker::check_samples(const Trajectory& traj, bool environment) const {
  const double step = step_m();
  for (int i = 0; i < traj.num_pieces(); ++i) {
    const TrajectoryPiece& piece = traj.piece(i);
    // Speed bound of any sphere centre over the piece, from a dense sampling of the rates.
    double v_max = 0.0;
    constexpr int kProbe = 32;
    for (int k = 0; k <= kProbe; ++k) {
      const double tau = piece.duration_s * k / kProbe;
      const TrajVector zd = piece_derivative(piece.coeffs, tau, 1);
      const double yaw_rate = traj.base_motion(traj.piece_start_time_s(i) + tau).yaw_rate_radps;
      v_max = std::max(v_max, zd.head<2>().norm() + reach_m_ * (std::abs(yaw_rate) + zd.tail<kNumArmJoints>().cwiseAbs().sum()));
    }
    // 1.5x: the probe may miss the peak between its samples.
    const int n = std::max(1, static_cast<int>(std::ceil(1.5 * v_max * piece.duration_s / step)));
    for (int k = 0; k <= n; ++k) {
      const double t = traj.piece_start_time_s(i) + piece.duration_s * k / n;
      const TrajVector z = traj.position(t);
      RobotConfiguration c;
      c.base = {z[0], z[1], traj.yaw_rad(t)};
      c.q_rad = z.tail<kNumArmJoints>();
      const CollisionResult r = check_links(c, kEndEffectorLink, environment);
      if (r.in_collision) return r;
    }
  }
  return {};
}

}  // namespace porter::baselines
