#include "exact_checker.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace porter::test {

ExactCollisionChecker::ExactCollisionChecker(const RobotModel& model, double step_m) : model_(model), step_m_(step_m) {
  // rho[l]: farthest geometry of link l from its frame origin; offset[k]: distance from joint k's
  // origin (link k's frame) to joint k+1's origin (or to the EE frame for k = 6).
  std::array<double, kNumLinks> rho{};
  for (int l = 0; l < kNumLinks; ++l) {
    const Link& link = model.links[static_cast<std::size_t>(l)];
    rho[static_cast<std::size_t>(l)] = link.shapes.empty() ? 0.0 : link.bounding_center.norm() + link.bounding_radius_m;
  }
  std::array<double, kNumLinks> offset{};
  for (int k = 1; k < kNumArmJoints; ++k) offset[static_cast<std::size_t>(k)] = model.joints[static_cast<std::size_t>(k)].T_parent_joint.translation().norm();
  offset[kNumArmJoints] = model.T_L6_EE.translation().norm();
  for (int j = 1; j <= kNumArmJoints; ++j) {
    double chain = 0.0, r = 0.0;
    for (int l = j; l < kNumLinks; ++l) {
      r = std::max(r, chain + rho[static_cast<std::size_t>(l)]);
      if (l < kNumLinks - 1) chain += offset[static_cast<std::size_t>(l)];
    }
    reach_m_[j - 1] = r;
  }
  const Eigen::Vector3d o1 = model.joints[0].T_parent_joint.translation();
  reach_yaw_m_ = std::max(rho[0], o1.head<2>().norm() + reach_m_[0]);
}

bool ExactCollisionChecker::link_collides(int link, const Eigen::Isometry3d& T_W_L) const {
  const Eigen::AlignedBox3d map = grid_.bounds_W();
  for (const CollisionShape& shape : model_.links[static_cast<std::size_t>(link)].shapes) {
    CollisionShape placed = shape;
    placed.T_parent_shape = T_W_L * shape.T_parent_shape;
    const Eigen::AlignedBox3d b = shape_bounds(placed);
    if (link > 0 && b.min().z() < -1e-6) return true;
    if (b.min().x() < map.min().x() || b.min().y() < map.min().y() || b.max().x() > map.max().x() ||
        b.max().y() > map.max().y())
      return true;
    const Eigen::Vector3i lo = grid_.world_to_index(b.min()).cwiseMax(Eigen::Vector3i::Zero());
    const Eigen::Vector3i hi = grid_.world_to_index(b.max()).cwiseMin(grid_.dims() - Eigen::Vector3i::Ones());
    for (int iz = lo.z(); iz <= hi.z(); ++iz)
      for (int iy = lo.y(); iy <= hi.y(); ++iy)
        for (int ix = lo.x(); ix <= hi.x(); ++ix)
          if (grid_.occupied(ix, iy, iz) && shape_intersects_aabb(placed, grid_.voxel_box_W(ix, iy, iz))) return true;
  }
  return false;
}

planner::CollisionResult ExactCollisionChecker::check(const RobotConfiguration& config) const {
  KinematicsWorkspace ws;
  forward_kinematics(model_, config, ws);
  planner::CollisionResult r;
  for (int l = 0; l < kNumLinks; ++l) {
    if (link_collides(l, ws.T_W_L[static_cast<std::size_t>(l)])) {
      r.in_collision = true;
      r.link = l;
      return r;
    }
  }
  return r;
}

planner::CollisionResult ExactCollisionChecker::check_base(const BasePose& base) const {
  planner::CollisionResult r;
  if (link_collides(0, base.T_W_B())) {
    r.in_collision = true;
    r.link = 0;
  }
  return r;
}

planner::CollisionResult ExactCollisionChecker::check_motion(const RobotConfiguration& from,
                                                             const RobotConfiguration& to) const {
  const double dyaw = std::remainder(to.base.yaw_rad - from.base.yaw_rad, 2.0 * M_PI);
  const double bound = std::hypot(to.base.x_m - from.base.x_m, to.base.y_m - from.base.y_m) +
                       reach_yaw_m_ * std::abs(dyaw) + reach_m_.dot((to.q_rad - from.q_rad).cwiseAbs());
  const int n = std::max(1, static_cast<int>(std::ceil(bound / step_m_)));
  for (int k = 0; k <= n; ++k) {
    const double t = static_cast<double>(k) / n;
    RobotConfiguration c;
    c.base = {from.base.x_m + t * (to.base.x_m - from.base.x_m), from.base.y_m + t * (to.base.y_m - from.base.y_m),
              from.base.yaw_rad + t * dyaw};
    c.q_rad = from.q_rad + t * (to.q_rad - from.q_rad);
    const planner::CollisionResult r = check(c);
    if (r) return r;
  }
  return {};
}

planner::CollisionResult ExactCollisionChecker::check_trajectory(const Trajectory& trajectory) const {
  const double total = trajectory.total_duration_s();
  const int n = std::max(1, static_cast<int>(std::ceil(total / 0.01)));
  for (int k = 0; k <= n; ++k) {
    const double t = total * k / n;
    const TrajVector z = trajectory.position(t);
    RobotConfiguration c;
    c.base = {z[0], z[1], trajectory.base_motion(t).yaw_rad};
    c.q_rad = z.tail<kNumArmJoints>();
    const planner::CollisionResult r = check(c);
    if (r) return r;
  }
  return {};
}

}  // namespace porter::test
