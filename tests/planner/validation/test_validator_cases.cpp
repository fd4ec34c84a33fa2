// Hand-made cases with known answers: a drive through a wall, a known clearance, joint-limit
// breaches, a self-collision, a goal missed and a start not kept; sample spacing.
#include <cmath>

#include <gtest/gtest.h>

#include "porter/core/kinematics.hpp"
#include "porter/validation/validator.hpp"
#include "validation_fixture.hpp"

namespace porter::validation {
namespace {

using test::carry_arm;
using test::flat;

struct Extent {
  Eigen::AlignedBox3d box;  ///< of the whole robot with payload, base frame at the origin
  int max_x_body = -1;      ///< body reaching farthest along +x
  double lowest_z_arm = 1e9;  ///< lowest point of links 1..7 and the payload
};

// Exact bounds of the robot at the carrying pose with its base at the origin, from the core's
// kinematics and shape bounds (not the validator's).
Extent carry_extent() {
  const RobotModel model = attach_payload(test::robot(), test::t_bar());
  RobotConfiguration c;
  c.q_rad = carry_arm();
  KinematicsWorkspace ws;
  forward_kinematics(model, c, ws);
  Extent e;
  double best_x = -1e9;
  const size_t bare_shapes = test::robot().links[7].shapes.size();
  for (int k = 0; k < kNumLinks; ++k) {
    const auto& shapes = model.links[static_cast<size_t>(k)].shapes;
    for (size_t i = 0; i < shapes.size(); ++i) {
      const Eigen::AlignedBox3d b = shape_bounds(shapes[i], ws.T_W_L[static_cast<size_t>(k)]);
      e.box.extend(b);
      const int body = (k == 7 && i >= bare_shapes) ? kPayloadBody : k;
      if (b.max().x() > best_x) best_x = b.max().x(), e.max_x_body = body;
      if (k != 0) e.lowest_z_arm = std::min(e.lowest_z_arm, b.min().z());
    }
  }
  return e;
}

// Base x on a rest-to-rest ramp from x0 to x1 over T.
double ramp_x(double x0, double x1, double T, double t) {
  const double s = t / T;
  return x0 + (x1 - x0) * s * s * s * (10 - 15 * s + 6 * s * s);
}

TEST(ValidatorCases, DriveThroughAWallIsACollisionFirstSeenWithinOneCentimetreOfContact) {
  const Extent e = carry_extent();
  const double wall_x = 0.5;
  const Scene scene = test::line_scene(-3, 3, {test::box_obstacle("wall", {wall_x, -5, 0}, {wall_x + 0.2, 5, 2.5})});
  const FlatTrajectory traj = test::line_trajectory(-3, 3, 16.0);
  const ValidationReport r = validate_trajectory(test::robot(), test::t_bar(), scene, traj);
  ASSERT_TRUE(r.collision.found);
  EXPECT_FALSE(r.valid);
  EXPECT_EQ(r.collision.obstacle, "wall");
  EXPECT_EQ(r.collision.body, body_name(test::robot(), "t_bar", e.max_x_body));
  // The robot's front reaches the wall face when x_b + max_x = wall_x; the first sample in
  // collision comes at most one sample step (1 cm of motion) later.
  const double overlap = ramp_x(-3, 3, 16.0, r.collision.t_s) + e.box.max().x() - wall_x;
  EXPECT_GE(overlap, 0.0);
  EXPECT_LE(overlap, 0.0100001);
  EXPECT_GT(r.collision.depth_m, 0.0);
  EXPECT_LE(r.collision.depth_m, overlap + 1e-3);
  EXPECT_LT(r.clearances.at(0).min_m, -0.05);  // it drives right through
  ASSERT_FALSE(r.failures.empty());
  EXPECT_NE(r.failures[0].find("collision"), std::string::npos);
}

TEST(ValidatorCases, ClearanceToAWallBesideThePathIsMeasuredToAMillimetre) {
  const Extent e = carry_extent();
  const double gap = 0.123;
  const double face_y = e.box.max().y() + gap;
  const Scene scene = test::line_scene(-3, 3, {test::box_obstacle("side", {-10, face_y, 0}, {10, face_y + 0.3, 3})});
  const FlatTrajectory traj = test::line_trajectory(-3, 3, 16.0);
  const ValidationReport r = validate_trajectory(test::robot(), test::t_bar(), scene, traj);
  EXPECT_TRUE(r.valid) << (r.failures.empty() ? "" : r.failures[0]);
  EXPECT_FALSE(r.collision.found);
  EXPECT_FALSE(r.self_collision.found);
  ASSERT_EQ(r.clearances.size(), 2u);
  EXPECT_EQ(r.clearances[0].obstacle, "side");
  EXPECT_NEAR(r.clearances[0].min_m, gap, 1e-3);
  EXPECT_EQ(r.clearances[1].obstacle, "ground");
  EXPECT_NEAR(r.clearances[1].min_m, e.lowest_z_arm, 1e-9);
  EXPECT_TRUE(r.start.ok);
  EXPECT_TRUE(r.goal.ok);
  EXPECT_LE(r.max_step_m, 0.01);
  for (const auto& l : r.limits) EXPECT_TRUE(l.kept) << l.quantity;
}

// Recorded configurations (e.g. the simulator's ground truth) are judged like trajectory samples:
// beside a wall the clearance is the gap; shifted into the wall they collide, at the first
// configuration inside it.
TEST(ValidatorCases, RecordedConfigurationsGetTheTrajectoryChecksClearanceAndCollision) {
  const Extent e = carry_extent();
  const double gap = 0.123;
  const double face_y = e.box.max().y() + gap;
  const Scene scene = test::line_scene(-3, 3, {test::box_obstacle("side", {-10, face_y, 0}, {10, face_y + 0.3, 3})});
  std::vector<double> times;
  std::vector<WholeBodyConfig> configs;
  for (int i = 0; i <= 20; ++i) {
    WholeBodyConfig c;
    c.x_m = -2.0 + 0.2 * i;
    c.q_rad = carry_arm();
    times.push_back(0.1 * i);
    configs.push_back(c);
  }
  const ValidationReport beside = check_configurations(test::robot(), test::t_bar(), scene, times, configs);
  EXPECT_TRUE(beside.valid);
  EXPECT_FALSE(beside.collision.found);
  EXPECT_EQ(beside.samples, 21);
  ASSERT_EQ(beside.clearances.size(), 2u);
  EXPECT_NEAR(beside.clearances[0].min_m, gap, 1e-3);
  EXPECT_NEAR(beside.clearances[1].min_m, e.lowest_z_arm, 1e-9);

  // From the 11th configuration on the robot stands 0.2 m into the wall.
  for (size_t i = 10; i < configs.size(); ++i) configs[i].y_m = gap + 0.2;
  const ValidationReport into = check_configurations(test::robot(), test::t_bar(), scene, times, configs);
  EXPECT_FALSE(into.valid);
  ASSERT_TRUE(into.collision.found);
  EXPECT_EQ(into.collision.obstacle, "side");
  EXPECT_DOUBLE_EQ(into.collision.t_s, 1.0);
  EXPECT_EQ(into.collision.samples, 11);
  // The robot's farthest point is 0.2 m inside; FCL's depth of the first colliding shape is at most that.
  EXPECT_GT(into.collision.depth_m, 0.1);
  EXPECT_LE(into.collision.depth_m, 0.2 + 1e-3);
  EXPECT_LT(into.clearances[0].min_m, 0.0);
}

TEST(ValidatorCases, JointPositionBreachReportsItsWorstRatio) {
  Eigen::Matrix<double, 6, 1> q = carry_arm();
  q[0] = 2.8;  // joint1's range is +-2.6179 rad
  const FlatTrajectory traj({test::ramp(flat(0, 0, carry_arm()), flat(0, 0, q), 4.0),
                             test::ramp(flat(0, 0, q), flat(0, 0, carry_arm()), 4.0)},
                            0.0);
  const Scene scene = test::line_scene(0, 0, {});
  const ValidationReport r = validate_trajectory(test::robot(), test::t_bar(), scene, traj);
  EXPECT_FALSE(r.valid);
  const LimitCheck& pos = r.limits.at(0);
  ASSERT_EQ(pos.quantity, "joint_position");
  EXPECT_FALSE(pos.kept);
  EXPECT_EQ(pos.where, "joint1");
  EXPECT_NEAR(pos.worst_ratio, 2.8 / 2.6179, 1e-9);
  EXPECT_NEAR(pos.t_s, 4.0, 1e-9);
  EXPECT_TRUE(r.limits.at(1).kept);  // 15/8 * 2.8 / 4 = 1.31 rad/s of 1.5
  EXPECT_TRUE(r.limits.at(2).kept);
  EXPECT_TRUE(r.goal.ok);
}

TEST(ValidatorCases, JointSpeedAndAccelerationBreachesReportTheirWorstRatios) {
  Eigen::Matrix<double, 6, 1> q = carry_arm();
  q[5] = 2.0;  // joint6: 2 rad/s, 4 rad/s^2
  const FlatTrajectory traj({test::ramp(flat(0, 0, carry_arm()), flat(0, 0, q), 1.5)}, 0.0);
  Scene scene = test::line_scene(0, 0, {});
  scene.goal.q_rad = q;
  const ValidationReport r = validate_trajectory(test::robot(), test::t_bar(), scene, traj);
  EXPECT_FALSE(r.valid);
  EXPECT_TRUE(r.limits.at(0).kept);
  const LimitCheck& vel = r.limits.at(1);
  EXPECT_FALSE(vel.kept);
  EXPECT_EQ(vel.where, "joint6");
  EXPECT_NEAR(vel.worst_ratio, (15.0 / 8.0) * 2.0 / 1.5 / 2.0, 1e-9);  // peak at mid-piece, a sample
  const LimitCheck& acc = r.limits.at(2);
  EXPECT_FALSE(acc.kept);
  EXPECT_NEAR(acc.worst_ratio, (10.0 / std::sqrt(3.0)) * 2.0 / (1.5 * 1.5) / 4.0, 0.01);
  EXPECT_TRUE(r.goal.ok);
}

// A configuration where a surface point of an arm link lies 5 mm or more inside the base's
// geometry, found with the core's kinematics and exact signed distances.
bool find_folded_configuration(Eigen::Matrix<double, 6, 1>* q_out, int* link_out) {
  const RobotModel& model = test::robot();
  KinematicsWorkspace ws;
  RobotConfiguration c;
  for (double q2 = 0.0; q2 <= 3.14; q2 += 0.1)
    for (double q3 = -2.9; q3 <= 0.0; q3 += 0.1) {
      c.q_rad << 0.0, q2, q3, 0.0, 0.0, 0.0;
      forward_kinematics(model, c, ws);
      for (int k = 2; k <= 6; ++k)
        for (const auto& s : model.links[static_cast<size_t>(k)].shapes) {
          const TriangleMesh m = shape_to_mesh(s);
          for (const auto& v : m.vertices_m) {
            const Eigen::Vector3d p = ws.T_W_L[static_cast<size_t>(k)] * v;
            for (const auto& b : model.links[0].shapes)
              if (shape_signed_distance(b, p) < -0.005) {
                *q_out = c.q_rad;
                *link_out = k;
                return true;
              }
          }
        }
    }
  return false;
}

TEST(ValidatorCases, ArmFoldedIntoTheBaseIsASelfCollision) {
  Eigen::Matrix<double, 6, 1> q;
  int link = -1;
  ASSERT_TRUE(find_folded_configuration(&q, &link));
  const FlatTrajectory traj({test::ramp(flat(0, 0, q), flat(0.2, 0, q), 2.0)}, 0.0);
  Scene scene = test::line_scene(0, 0.2, {});
  scene.start.q_rad = scene.goal.q_rad = q;
  ValidationSettings settings;
  settings.check_ground = false;
  const ValidationReport r = validate_trajectory(test::robot(), test::t_bar(), scene, traj, settings);
  ASSERT_TRUE(r.self_collision.found) << "link " << link << " q " << q.transpose();
  EXPECT_FALSE(r.valid);
  EXPECT_DOUBLE_EQ(r.self_collision.t_s, 0.0);
  const std::string base = test::robot().links[0].name;
  EXPECT_TRUE(r.self_collision.body_a == base || r.self_collision.body_b == base)
      << r.self_collision.body_a << " / " << r.self_collision.body_b;
  EXPECT_GT(r.self_collision.depth_m, 0.0);
  EXPECT_EQ(r.self_collision.samples, r.samples);
}

TEST(ValidatorCases, GoalMissedAndStartNotKeptAreReportedWithTheirErrors) {
  const Scene scene = test::line_scene(-3, 3, {});
  const ValidationReport short_of_goal =
      validate_trajectory(test::robot(), test::t_bar(), scene, test::line_trajectory(-3, 2.7, 16.0));
  EXPECT_FALSE(short_of_goal.valid);
  EXPECT_TRUE(short_of_goal.start.ok);
  EXPECT_FALSE(short_of_goal.goal.ok);
  EXPECT_NEAR(short_of_goal.goal.position_error_m, 0.3, 1e-12);
  EXPECT_NEAR(short_of_goal.goal.yaw_error_rad, 0.0, 1e-12);
  ASSERT_EQ(short_of_goal.failures.size(), 1u);
  EXPECT_EQ(short_of_goal.failures[0].rfind("goal missed", 0), 0u);

  const ValidationReport late_start =
      validate_trajectory(test::robot(), test::t_bar(), scene, test::line_trajectory(-2.8, 3, 16.0));
  EXPECT_FALSE(late_start.valid);
  EXPECT_FALSE(late_start.start.ok);
  EXPECT_NEAR(late_start.start.position_error_m, 0.2, 1e-12);
  EXPECT_TRUE(late_start.goal.ok);
}

TEST(ValidatorCases, NoPointMovesMoreThanTheStepBetweenSamples) {
  // Turning drive with the arm swinging: every vertex of every shape, sample to sample.
  Eigen::Matrix<double, 6, 1> q = carry_arm();
  q[0] = 1.0;
  q[3] = -0.8;
  const FlatTrajectory traj({test::ramp(flat(0, 0, carry_arm()), flat(2, 1, q), 5.0)}, 0.3);
  ValidationSettings settings;
  double worst_bound = 0.0;
  const auto times = sample_times(test::robot(), test::t_bar(), traj, settings, &worst_bound);
  EXPECT_LE(worst_bound, settings.max_step_m);
  std::vector<std::pair<int, Eigen::Vector3d>> points;  // body, point in the body frame
  for (int k = 0; k < kNumLinks; ++k)
    for (const auto& s : test::robot().links[static_cast<size_t>(k)].shapes)
      for (const auto& v : shape_to_mesh(s).vertices_m) points.emplace_back(k, v);
  for (auto s : test::t_bar().shapes) {
    s.T_parent_shape = test::t_bar().T_EE_P * s.T_parent_shape;
    for (const auto& v : shape_to_mesh(s).vertices_m) points.emplace_back(kPayloadBody, v);
  }
  double worst = 0.0;
  BodyPoses prev = body_poses(test::robot(), config_at(traj, times[0]));
  for (size_t i = 1; i < times.size(); ++i) {
    EXPECT_LT(times[i - 1], times[i]);
    EXPECT_LE(times[i] - times[i - 1], settings.max_dt_s + 1e-12);
    const BodyPoses cur = body_poses(test::robot(), config_at(traj, times[i]));
    for (const auto& [b, p] : points)
      worst = std::max(worst, (cur[static_cast<size_t>(b)] * p - prev[static_cast<size_t>(b)] * p).norm());
    prev = cur;
  }
  EXPECT_LE(worst, settings.max_step_m + 1e-12);
  EXPECT_GT(worst, 0.5 * settings.max_step_m);  // and the sampling is not wastefully fine
  EXPECT_DOUBLE_EQ(times.front(), 0.0);
  EXPECT_DOUBLE_EQ(times.back(), traj.duration_s());
}

}  // namespace
}  // namespace porter::validation
