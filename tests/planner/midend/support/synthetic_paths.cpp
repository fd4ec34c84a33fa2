#include "synthetic_paths.hpp"

#include <algorithm>
#include <cmath>

namespace porter::midend::testing {

RobotModel scout_mini_piper_model() {
  RobotModel m;
  m.name = "scout_mini_piper (test)";
  m.base.wheel_radius_m = 0.0875;
  m.base.track_width_m = 0.4165;
  m.base.wheel_omega_max_radps = 12.0;
  m.base.wheel_alpha_max_radps2 = 20.0;
  m.base.min_turning_radius_m = 0.4;
  m.base.nonsingular_speed_mps = 0.05;
  const double lower[6] = {-2.6179, 0.0, -2.967, -1.745, -1.22, -2.09439};
  const double upper[6] = {2.6179, 3.14, 0.0, 1.745, 1.22, 2.09439};
  const double vmax[6] = {1.5, 1.5, 1.5, 2.0, 2.0, 2.0};
  const double amax[6] = {3.0, 3.0, 3.0, 4.0, 4.0, 4.0};
  for (int j = 0; j < 6; ++j) {
    m.joints[j].name = "joint" + std::to_string(j + 1);
    m.joints[j].lower_rad = lower[j];
    m.joints[j].upper_rad = upper[j];
    m.joints[j].velocity_max_radps = vmax[j];
    m.joints[j].acceleration_max_radps2 = amax[j];
  }
  return m;
}

JointVector carry_pose() {
  JointVector q;
  q << 0.0, 1.2, -1.4, 0.0, 0.5, 0.0;
  return q;
}

PathBuilder::PathBuilder(BasePose start, JointVector q_start, double node_spacing_m,
                         double cruise_speed_mps)
    : pose_(start), q_(q_start), spacing_m_(node_spacing_m), speed_mps_(cruise_speed_mps) {
  planner::PathSegment seg;
  seg.eta = 1;
  planner::PathNode n;
  n.config.base = pose_;
  n.config.q_rad = q_;
  n.time_s = 0.0;
  seg.nodes.push_back(n);
  path_.segments.push_back(seg);
}

void PathBuilder::add_node(int eta) {
  planner::PathSegment& last = path_.segments.back();
  if (last.eta != eta) {
    if (last.nodes.size() <= 1 && path_.segments.size() == 1) {
      last.eta = eta;  // the first segment takes the direction of the first motion
    } else {
      planner::PathSegment seg;
      seg.eta = eta;
      seg.nodes.push_back(last.nodes.back());
      path_.segments.push_back(seg);
    }
  }
  planner::PathNode n;
  n.config.base = pose_;
  n.config.q_rad = q_;
  n.time_s = time_s_;
  path_.segments.back().nodes.push_back(n);
}

void PathBuilder::primitive(double length_m, double curvature, int eta) {
  const int n = std::max(1, static_cast<int>(std::ceil(length_m / spacing_m_ - 1e-9)));
  const double ds = length_m / n;
  for (int i = 1; i <= n; ++i) {
    const double sigma = eta * ds;
    const double dyaw = curvature * sigma;
    if (std::abs(curvature) > 1e-12) {
      pose_.x_m += (std::sin(pose_.yaw_rad + dyaw) - std::sin(pose_.yaw_rad)) / curvature;
      pose_.y_m -= (std::cos(pose_.yaw_rad + dyaw) - std::cos(pose_.yaw_rad)) / curvature;
    } else {
      pose_.x_m += sigma * std::cos(pose_.yaw_rad);
      pose_.y_m += sigma * std::sin(pose_.yaw_rad);
    }
    pose_.yaw_rad += dyaw;
    const JointVector q_prev = q_;
    if (arm_moving_) {
      const double s = static_cast<double>(i) / n;
      const double e = s * s * (3.0 - 2.0 * s);
      q_ = q_from_ + e * (q_to_ - q_from_);
    }
    time_s_ += std::max(ds / speed_mps_, (q_ - q_prev).cwiseAbs().maxCoeff() / 0.5);
    add_node(eta);
  }
  if (arm_moving_) {
    q_ = q_to_;
    arm_moving_ = false;
  }
}

PathBuilder& PathBuilder::straight(double length_m, int eta) {
  primitive(length_m, 0.0, eta);
  return *this;
}

PathBuilder& PathBuilder::arc(double radius_m, double angle_rad, int eta) {
  const double length = radius_m * std::abs(angle_rad);
  primitive(length, angle_rad / (eta * length), eta);
  return *this;
}

PathBuilder& PathBuilder::arm_to(const JointVector& q_target) {
  q_from_ = q_;
  q_to_ = q_target;
  arm_moving_ = true;
  return *this;
}

PathBuilder& PathBuilder::arm_only(const JointVector& q_target) {
  time_s_ += (q_target - q_).cwiseAbs().maxCoeff() / 0.5;
  q_ = q_target;
  add_node(path_.segments.back().eta);
  return *this;
}

planner::WholeBodyPath forward_with_turn() {
  JointVector q1 = carry_pose();
  q1[0] = 0.5;
  q1[1] = 1.5;
  JointVector q2 = carry_pose();
  q2[0] = -0.4;
  q2[4] = 0.8;
  PathBuilder b({0.0, 0.0, 0.0}, carry_pose());
  b.arm_to(q1).straight(4.0, 1).arc(1.2, M_PI / 2, 1).arm_to(q2).straight(3.0, 1);
  return b.build();
}

planner::WholeBodyPath three_point_turn() {
  JointVector q1 = carry_pose();
  q1[0] = 0.6;
  q1[5] = 0.8;
  JointVector q2 = carry_pose();
  q2[0] = -0.3;
  q2[2] = -1.0;
  PathBuilder b({1.0, -0.5, 0.3}, carry_pose());
  b.straight(1.2, 1).arm_to(q1).arc(1.0, 1.2, 1).arc(1.0, -1.0, -1).arm_to(q2).arc(1.0, 1.3, 1)
      .straight(1.5, 1);
  return b.build();
}

planner::WholeBodyPath forest_slalom(int num_nodes) {
  // Base length ~ 20 m split into num_nodes nodes.
  const double spacing = 20.0 / std::max(num_nodes - 1, 1);
  JointVector q1 = carry_pose();
  q1[0] = 0.7;
  q1[3] = 0.5;
  JointVector q2 = carry_pose();
  q2[0] = -0.6;
  q2[1] = 1.6;
  JointVector q3 = carry_pose();
  PathBuilder b({-8.0, 2.0, -0.2}, carry_pose(), spacing, 0.6);
  b.straight(2.0, 1).arm_to(q1).arc(2.5, 0.6, 1).arc(2.5, -1.0, 1).arc(2.5, 0.8, 1)
      .arc(1.5, 0.5, -1)
      .arm_to(q2).straight(2.0, 1).arc(2.0, -0.9, 1).arc(2.5, 0.9, 1).arm_to(q3).straight(2.2, 1)
      .arc(3.0, -0.4, 1);
  return b.build();
}

planner::WholeBodyPath straight_line(int num_pieces, double spacing_m) {
  JointVector q1 = carry_pose();
  q1[0] = 0.4;
  PathBuilder b({0.0, 0.0, 0.0}, carry_pose(), spacing_m, 0.5);
  b.arm_to(q1).straight(num_pieces * spacing_m, 1);
  return b.build();
}

}  // namespace porter::midend::testing
