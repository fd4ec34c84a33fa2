// Round trips of the planning types: every field must survive encode/decode.

#include <gtest/gtest.h>

#include "porter/minco_trajectory_t.hpp"
#include "porter/payload_t.hpp"
#include "porter/plan_goal_t.hpp"
#include "porter/planner_status_t.hpp"
#include "roundtrip_support.hpp"

namespace porter {
namespace {

using test::expect_rejects;
using test::roundtrip;

TEST(LcmRoundTrip, PlanGoalWithArm) {
  plan_goal_t m{};
  m.utime = 10'000'000;
  m.goal_id = 5;
  m.frame_id = "world";
  m.x_m = 8.5;
  m.y_m = -1.25;
  m.yaw_rad = 1.5707963267948966;
  m.has_arm = true;
  m.num_joints = 6;
  m.q_rad = {0.0, 1.2, -0.9, 0.0, 0.6, -1.0};
  m.payload_id = "t_bar";
  m.position_tolerance_m = 0.05;
  m.yaw_tolerance_rad = 0.1;
  const plan_goal_t r = roundtrip(m);
  EXPECT_EQ(r.utime, m.utime);
  EXPECT_EQ(r.goal_id, m.goal_id);
  EXPECT_EQ(r.frame_id, m.frame_id);
  EXPECT_EQ(r.x_m, m.x_m);
  EXPECT_EQ(r.y_m, m.y_m);
  EXPECT_EQ(r.yaw_rad, m.yaw_rad);
  EXPECT_EQ(r.has_arm, m.has_arm);
  EXPECT_EQ(r.num_joints, m.num_joints);
  EXPECT_EQ(r.q_rad, m.q_rad);
  EXPECT_EQ(r.payload_id, m.payload_id);
  EXPECT_EQ(r.position_tolerance_m, m.position_tolerance_m);
  EXPECT_EQ(r.yaw_tolerance_rad, m.yaw_tolerance_rad);
  expect_rejects(m, payload_t{});
}

TEST(LcmRoundTrip, PlanGoalBaseOnly) {
  plan_goal_t m{};
  m.utime = 11;
  m.goal_id = 6;
  m.frame_id = "world";
  m.x_m = -3.0;
  m.has_arm = false;
  m.num_joints = 0;
  const plan_goal_t r = roundtrip(m);
  EXPECT_FALSE(r.has_arm);
  EXPECT_EQ(r.num_joints, 0);
  EXPECT_TRUE(r.q_rad.empty());
  EXPECT_EQ(r.x_m, -3.0);
  EXPECT_EQ(r.payload_id, "");
}

TEST(LcmRoundTrip, Payload) {
  payload_t m{};
  m.utime = 12'000'000;
  m.payload_id = "t_bar";
  m.attached = true;
  m.mesh_path = "payloads/t_bar.obj";
  m.mesh_scale = 0.001;
  m.p_EE_P_x_m = 0.01;
  m.p_EE_P_y_m = -0.02;
  m.p_EE_P_z_m = 0.15;
  m.q_EE_P_w = 0.7071067811865476;
  m.q_EE_P_x = 0.7071067811865476;
  m.q_EE_P_y = 0.0;
  m.q_EE_P_z = 0.0;
  m.mass_kg = 1.75;
  // A tetrahedron, inline.
  m.num_vertices = 4;
  m.vertex_x_m = {0.0f, 1.0f, 0.0f, 0.0f};
  m.vertex_y_m = {0.0f, 0.0f, 1.0f, 0.0f};
  m.vertex_z_m = {0.0f, 0.0f, 0.0f, 1.0f};
  m.num_indices = 12;
  m.triangle_indices = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
  const payload_t r = roundtrip(m);
  EXPECT_EQ(r.utime, m.utime);
  EXPECT_EQ(r.payload_id, m.payload_id);
  EXPECT_EQ(r.attached, m.attached);
  EXPECT_EQ(r.mesh_path, m.mesh_path);
  EXPECT_EQ(r.mesh_scale, m.mesh_scale);
  EXPECT_EQ(r.p_EE_P_x_m, m.p_EE_P_x_m);
  EXPECT_EQ(r.p_EE_P_y_m, m.p_EE_P_y_m);
  EXPECT_EQ(r.p_EE_P_z_m, m.p_EE_P_z_m);
  EXPECT_EQ(r.q_EE_P_w, m.q_EE_P_w);
  EXPECT_EQ(r.q_EE_P_x, m.q_EE_P_x);
  EXPECT_EQ(r.q_EE_P_y, m.q_EE_P_y);
  EXPECT_EQ(r.q_EE_P_z, m.q_EE_P_z);
  EXPECT_EQ(r.mass_kg, m.mass_kg);
  EXPECT_EQ(r.num_vertices, m.num_vertices);
  EXPECT_EQ(r.vertex_x_m, m.vertex_x_m);
  EXPECT_EQ(r.vertex_y_m, m.vertex_y_m);
  EXPECT_EQ(r.vertex_z_m, m.vertex_z_m);
  EXPECT_EQ(r.num_indices, m.num_indices);
  EXPECT_EQ(r.triangle_indices, m.triangle_indices);
  expect_rejects(m, plan_goal_t{});
}

TEST(LcmRoundTrip, MincoTrajectory) {
  minco_trajectory_t m{};
  m.utime = 20'000'000;
  m.start_utime = 20'050'000;
  m.plan_id = 3;
  m.frame_id = "world";
  m.payload_id = "long_bar";
  m.dimension = 8;
  m.order = 5;
  m.start_yaw_rad = -0.75;
  m.num_pieces = 3;
  m.durations_s = {0.8, 1.25, 0.6};
  m.eta = {1, -1, 1};
  m.num_coeffs = m.num_pieces * m.dimension * (m.order + 1);
  for (int piece = 0; piece < m.num_pieces; ++piece) {
    for (int d = 0; d < m.dimension; ++d) {
      for (int k = 0; k <= m.order; ++k) {
        m.coeffs.push_back(piece * 100.0 + d + 0.125 * k);
      }
    }
  }
  ASSERT_EQ(static_cast<int>(m.coeffs.size()), m.num_coeffs);
  const minco_trajectory_t r = roundtrip(m);
  EXPECT_EQ(r.utime, m.utime);
  EXPECT_EQ(r.start_utime, m.start_utime);
  EXPECT_EQ(r.plan_id, m.plan_id);
  EXPECT_EQ(r.frame_id, m.frame_id);
  EXPECT_EQ(r.payload_id, m.payload_id);
  EXPECT_EQ(r.dimension, m.dimension);
  EXPECT_EQ(r.order, m.order);
  EXPECT_EQ(r.start_yaw_rad, m.start_yaw_rad);
  EXPECT_EQ(r.num_pieces, m.num_pieces);
  EXPECT_EQ(r.durations_s, m.durations_s);
  EXPECT_EQ(r.eta, m.eta);
  EXPECT_EQ(r.num_coeffs, m.num_coeffs);
  EXPECT_EQ(r.coeffs, m.coeffs);
  // The documented index: ((piece * dimension) + d) * (order + 1) + k.
  const int piece = 2, d = 5, k = 3;
  EXPECT_EQ(r.coeffs[((piece * r.dimension) + d) * (r.order + 1) + k], 200.0 + 5 + 0.375);
  expect_rejects(m, planner_status_t{});
}

TEST(LcmRoundTrip, PlannerStatus) {
  planner_status_t m{};
  m.utime = 30'000'000;
  m.goal_id = 5;
  m.plan_id = 3;
  m.state = planner_status_t::STATE_FAILED;
  m.failure_reason = "back_end: collision at t = 2.4 s";
  m.num_stages = 3;
  m.stage_name = {"front_end", "mid_end", "back_end"};
  m.stage_status = {"success", "success", "not_collision_free"};
  m.stage_time_s = {0.032, 0.115, 0.301};
  m.stage_iterations = {5123, 87, 240};
  m.total_time_s = 0.452;
  m.trajectory_duration_s = 11.5;
  m.min_clearance_m = -1.0;
  const planner_status_t r = roundtrip(m);
  EXPECT_EQ(r.utime, m.utime);
  EXPECT_EQ(r.goal_id, m.goal_id);
  EXPECT_EQ(r.plan_id, m.plan_id);
  EXPECT_EQ(r.state, m.state);
  EXPECT_EQ(r.failure_reason, m.failure_reason);
  EXPECT_EQ(r.num_stages, m.num_stages);
  EXPECT_EQ(r.stage_name, m.stage_name);
  EXPECT_EQ(r.stage_status, m.stage_status);
  EXPECT_EQ(r.stage_time_s, m.stage_time_s);
  EXPECT_EQ(r.stage_iterations, m.stage_iterations);
  EXPECT_EQ(r.total_time_s, m.total_time_s);
  EXPECT_EQ(r.trajectory_duration_s, m.trajectory_duration_s);
  EXPECT_EQ(r.min_clearance_m, m.min_clearance_m);
  expect_rejects(m, minco_trajectory_t{});
}

}  // namespace
}  // namespace porter
