// The planner settings files: the shipped ones load and hold the in-class defaults (so the CLI,
// the daemon and a default-constructed PlannerSettings plan alike); a missing, unknown,
// out-of-range or mistyped key is refused with the file and the key in the message.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "pipeline_fixtures.hpp"
#include "hostile_config.hpp"
#include "porter/core/load_error.hpp"

namespace porter::pipeline {
namespace {

namespace fs = std::filesystem;

std::string shipped_dir() { return testing::source_dir() + "/config/planner"; }

std::string read(const std::string& file) {
  std::ifstream in(file);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(PlannerSettingsYaml, TheShippedFilesHoldTheDefaults) {
  const PlannerSettings loaded = load_planner_settings(shipped_dir());
  const PlannerSettings defaults;
  EXPECT_EQ(loaded.pipeline.frontend_budget_s, defaults.pipeline.frontend_budget_s);
  EXPECT_EQ(loaded.pipeline.midend_budget_s, defaults.pipeline.midend_budget_s);
  EXPECT_EQ(loaded.pipeline.backend_budget_s, defaults.pipeline.backend_budget_s);
  EXPECT_EQ(loaded.pipeline.collision, defaults.pipeline.collision);
  EXPECT_EQ(loaded.pipeline.safety, defaults.pipeline.safety);
  EXPECT_EQ(loaded.pipeline.self_collision_term, defaults.pipeline.self_collision_term);
  EXPECT_EQ(loaded.pipeline.retry_arm_residual_scale, defaults.pipeline.retry_arm_residual_scale);
  EXPECT_EQ(loaded.pipeline.goal_position_tolerance_m, defaults.pipeline.goal_position_tolerance_m);
  EXPECT_EQ(loaded.pipeline.goal_yaw_tolerance_rad, defaults.pipeline.goal_yaw_tolerance_rad);
  EXPECT_EQ(loaded.pipeline.free_arm_candidates, defaults.pipeline.free_arm_candidates);
  EXPECT_EQ(loaded.kernels.kernels.resolution_m, defaults.kernels.kernels.resolution_m);
  EXPECT_EQ(loaded.kernels.kernels.max_sample_error_m, defaults.kernels.kernels.max_sample_error_m);
  EXPECT_EQ(loaded.kernels.kernels.base_yaw_samples, defaults.kernels.kernels.base_yaw_samples);
  EXPECT_EQ(loaded.kernels.kernels.lattice_subdivision, defaults.kernels.kernels.lattice_subdivision);
  EXPECT_EQ(loaded.kernels.map.safety_margin_m, defaults.kernels.map.safety_margin_m);
  EXPECT_EQ(loaded.kernels.map.distance_cap_m, defaults.kernels.map.distance_cap_m);
  EXPECT_EQ(loaded.kernels.motion_step_m, defaults.kernels.motion_step_m);
  EXPECT_EQ(loaded.kernels.check_self_collision, defaults.kernels.check_self_collision);
  EXPECT_EQ(loaded.kernels.self.sample_spacing_m, defaults.kernels.self.sample_spacing_m);
  EXPECT_EQ(loaded.kernels.self.prove_pairs, defaults.kernels.self.prove_pairs);
  EXPECT_EQ(loaded.kernels.self.proof_max_boxes, defaults.kernels.self.proof_max_boxes);
  EXPECT_EQ(loaded.kernels.self.proof_min_cell_m, defaults.kernels.self.proof_min_cell_m);
  EXPECT_EQ(loaded.spheres.cover.cell_m, defaults.spheres.cover.cell_m);
  EXPECT_EQ(loaded.spheres.max_distance_m, defaults.spheres.max_distance_m);
  EXPECT_EQ(loaded.spheres.check_self_collision, defaults.spheres.check_self_collision);
  EXPECT_EQ(loaded.spheres.motion_step_m, defaults.spheres.motion_step_m);
  EXPECT_EQ(loaded.backend.max_iterations, defaults.backend.max_iterations);
  EXPECT_EQ(loaded.backend.relative_cost_tolerance, defaults.backend.relative_cost_tolerance);
  EXPECT_EQ(loaded.backend.relative_cost_past, defaults.backend.relative_cost_past);
  EXPECT_EQ(loaded.backend.memory_size, defaults.backend.memory_size);
  EXPECT_EQ(loaded.backend.max_line_search, defaults.backend.max_line_search);
  EXPECT_EQ(loaded.backend.line_search, defaults.backend.line_search);
  EXPECT_EQ(loaded.backend.variable_scale, defaults.backend.variable_scale);
  EXPECT_EQ(loaded.backend.probe_first_step, defaults.backend.probe_first_step);
  EXPECT_EQ(loaded.backend.skip_safety_above_current, defaults.backend.skip_safety_above_current);
  EXPECT_EQ(loaded.backend.recheck_every_iterations, defaults.backend.recheck_every_iterations);
  EXPECT_EQ(loaded.backend.weight_escalation_factor, defaults.backend.weight_escalation_factor);
  EXPECT_EQ(loaded.backend.max_weight_escalations, defaults.backend.max_weight_escalations);
  EXPECT_EQ(loaded.backend.window_grow_pieces, defaults.backend.window_grow_pieces);
  EXPECT_EQ(loaded.backend.window_max_fraction, defaults.backend.window_max_fraction);
  EXPECT_EQ(loaded.safety_terms.svsdf.weight, defaults.safety_terms.svsdf.weight);
  EXPECT_EQ(loaded.safety_terms.svsdf.threads, defaults.safety_terms.svsdf.threads);
  EXPECT_EQ(loaded.safety_terms.svsdf.freeze_ball_decisions, defaults.safety_terms.svsdf.freeze_ball_decisions);
  EXPECT_EQ(loaded.safety_terms.spheres.cover.cell_m, defaults.safety_terms.spheres.cover.cell_m);
  EXPECT_EQ(loaded.safety_terms.spheres.safety_margin_m, defaults.safety_terms.spheres.safety_margin_m);
  EXPECT_EQ(loaded.safety_terms.spheres.weight, defaults.safety_terms.spheres.weight);
  EXPECT_EQ(loaded.safety_terms.spheres.samples_per_piece, defaults.safety_terms.spheres.samples_per_piece);
  EXPECT_EQ(loaded.safety_terms.spheres.crop_margin_m, defaults.safety_terms.spheres.crop_margin_m);
  EXPECT_EQ(loaded.safety_terms.spheres.max_distance_m, defaults.safety_terms.spheres.max_distance_m);
  EXPECT_EQ(loaded.self_collision.weight, defaults.self_collision.weight);
  EXPECT_EQ(loaded.self_collision.sample_interval_s, defaults.self_collision.sample_interval_s);
  EXPECT_EQ(loaded.self_collision.point_spacing_m, defaults.self_collision.point_spacing_m);
  EXPECT_EQ(loaded.self_collision.slack_m, defaults.self_collision.slack_m);
  EXPECT_EQ(loaded.self_collision.relative_to_warm_start, defaults.self_collision.relative_to_warm_start);
  EXPECT_EQ(loaded.self_collision.warm_start_slack_m, defaults.self_collision.warm_start_slack_m);
  EXPECT_EQ(loaded.frontend.hybrid_astar_budget_fraction, defaults.frontend.hybrid_astar_budget_fraction);
  EXPECT_EQ(loaded.frontend.layered_arm_budget_fraction, defaults.frontend.layered_arm_budget_fraction);
  EXPECT_EQ(loaded.frontend.arm_time_scale, defaults.frontend.arm_time_scale);
  EXPECT_EQ(loaded.frontend.min_layer_time_s, defaults.frontend.min_layer_time_s);
  EXPECT_EQ(loaded.frontend.bridge_margin_layers, defaults.frontend.bridge_margin_layers);
  EXPECT_EQ(loaded.frontend.hybrid_astar.xy_resolution_m, defaults.frontend.hybrid_astar.xy_resolution_m);
  EXPECT_EQ(loaded.frontend.hybrid_astar.yaw_bins, defaults.frontend.hybrid_astar.yaw_bins);
  EXPECT_EQ(loaded.frontend.hybrid_astar.step_length_m, defaults.frontend.hybrid_astar.step_length_m);
  EXPECT_EQ(loaded.frontend.hybrid_astar.steering_samples, defaults.frontend.hybrid_astar.steering_samples);
  EXPECT_EQ(loaded.frontend.hybrid_astar.turning_radius_m, defaults.frontend.hybrid_astar.turning_radius_m);
  EXPECT_EQ(loaded.frontend.hybrid_astar.collision_step_m, defaults.frontend.hybrid_astar.collision_step_m);
  EXPECT_EQ(loaded.frontend.hybrid_astar.reverse_cost_factor, defaults.frontend.hybrid_astar.reverse_cost_factor);
  EXPECT_EQ(loaded.frontend.hybrid_astar.gear_switch_cost_m, defaults.frontend.hybrid_astar.gear_switch_cost_m);
  EXPECT_EQ(loaded.frontend.hybrid_astar.steering_cost, defaults.frontend.hybrid_astar.steering_cost);
  EXPECT_EQ(loaded.frontend.hybrid_astar.steering_change_cost, defaults.frontend.hybrid_astar.steering_change_cost);
  EXPECT_EQ(loaded.frontend.hybrid_astar.heuristic_weight, defaults.frontend.hybrid_astar.heuristic_weight);
  EXPECT_EQ(loaded.frontend.hybrid_astar.rs_heuristic_range_m, defaults.frontend.hybrid_astar.rs_heuristic_range_m);
  EXPECT_EQ(loaded.frontend.hybrid_astar.analytic_expansion_range_m, defaults.frontend.hybrid_astar.analytic_expansion_range_m);
  EXPECT_EQ(loaded.frontend.hybrid_astar.analytic_expansion_interval, defaults.frontend.hybrid_astar.analytic_expansion_interval);
  EXPECT_EQ(loaded.frontend.hybrid_astar.max_shot_cusps, defaults.frontend.hybrid_astar.max_shot_cusps);
  EXPECT_EQ(loaded.frontend.hybrid_astar.whole_body_guidance, defaults.frontend.hybrid_astar.whole_body_guidance);
  EXPECT_EQ(loaded.frontend.hybrid_astar.arm_blocked_cost_factor, defaults.frontend.hybrid_astar.arm_blocked_cost_factor);
  EXPECT_EQ(loaded.frontend.hybrid_astar.narrow_shape_draws, defaults.frontend.hybrid_astar.narrow_shape_draws);
  EXPECT_EQ(loaded.frontend.hybrid_astar.heuristic_resolution_m, defaults.frontend.hybrid_astar.heuristic_resolution_m);
  EXPECT_EQ(loaded.frontend.hybrid_astar.max_expansions, defaults.frontend.hybrid_astar.max_expansions);
  EXPECT_EQ(loaded.frontend.layered_arm.arm_speed_fraction, defaults.frontend.layered_arm.arm_speed_fraction);
  EXPECT_EQ(loaded.frontend.layered_arm.goal_bias, defaults.frontend.layered_arm.goal_bias);
  EXPECT_EQ(loaded.frontend.layered_arm.hold_bias, defaults.frontend.layered_arm.hold_bias);
  EXPECT_EQ(loaded.frontend.layered_arm.local_bias, defaults.frontend.layered_arm.local_bias);
  EXPECT_EQ(loaded.frontend.layered_arm.corridor_bias, defaults.frontend.layered_arm.corridor_bias);
  EXPECT_EQ(loaded.frontend.layered_arm.corridor_draws, defaults.frontend.layered_arm.corridor_draws);
  EXPECT_EQ(loaded.frontend.layered_arm.corridor_margin_m, defaults.frontend.layered_arm.corridor_margin_m);
  EXPECT_EQ(loaded.frontend.layered_arm.max_corridor_targets, defaults.frontend.layered_arm.max_corridor_targets);
  EXPECT_EQ(loaded.frontend.layered_arm.corridor_target_bias, defaults.frontend.layered_arm.corridor_target_bias);
  EXPECT_EQ(loaded.frontend.layered_arm.chain_retries, defaults.frontend.layered_arm.chain_retries);
  EXPECT_EQ(loaded.frontend.layered_arm.frontier_bias, defaults.frontend.layered_arm.frontier_bias);
  EXPECT_EQ(loaded.frontend.layered_arm.frontier_window, defaults.frontend.layered_arm.frontier_window);
  EXPECT_EQ(loaded.frontend.layered_arm.optimize_before_connection, defaults.frontend.layered_arm.optimize_before_connection);
  EXPECT_EQ(loaded.frontend.layered_arm.max_parent_candidates, defaults.frontend.layered_arm.max_parent_candidates);
  EXPECT_EQ(loaded.frontend.layered_arm.max_connect_candidates, defaults.frontend.layered_arm.max_connect_candidates);
  EXPECT_EQ(loaded.frontend.layered_arm.refine_iterations, defaults.frontend.layered_arm.refine_iterations);
  EXPECT_EQ(loaded.frontend.layered_arm.shortcut_attempts, defaults.frontend.layered_arm.shortcut_attempts);
  EXPECT_EQ(loaded.frontend.layered_arm.shortcut_max_layers, defaults.frontend.layered_arm.shortcut_max_layers);
  EXPECT_EQ(loaded.frontend.layered_arm.max_iterations, defaults.frontend.layered_arm.max_iterations);
  EXPECT_EQ(loaded.frontend.whole_body_rrt.max_extend_m, defaults.frontend.whole_body_rrt.max_extend_m);
  EXPECT_EQ(loaded.frontend.whole_body_rrt.max_extend_q_rad, defaults.frontend.whole_body_rrt.max_extend_q_rad);
  EXPECT_EQ(loaded.frontend.whole_body_rrt.reverse_cost_factor, defaults.frontend.whole_body_rrt.reverse_cost_factor);
  EXPECT_EQ(loaded.frontend.whole_body_rrt.gear_switch_cost_m, defaults.frontend.whole_body_rrt.gear_switch_cost_m);
  EXPECT_EQ(loaded.frontend.whole_body_rrt.joint_cost_weight_m_per_rad, defaults.frontend.whole_body_rrt.joint_cost_weight_m_per_rad);
  EXPECT_EQ(loaded.frontend.whole_body_rrt.goal_bias, defaults.frontend.whole_body_rrt.goal_bias);
  EXPECT_EQ(loaded.frontend.whole_body_rrt.sampling_margin_m, defaults.frontend.whole_body_rrt.sampling_margin_m);
  EXPECT_EQ(loaded.frontend.whole_body_rrt.neighbours, defaults.frontend.whole_body_rrt.neighbours);
  EXPECT_EQ(loaded.frontend.whole_body_rrt.edge_step_m, defaults.frontend.whole_body_rrt.edge_step_m);
  EXPECT_EQ(loaded.frontend.whole_body_rrt.edge_q_step_rad, defaults.frontend.whole_body_rrt.edge_q_step_rad);
  EXPECT_EQ(loaded.frontend.whole_body_rrt.refine_iterations, defaults.frontend.whole_body_rrt.refine_iterations);
  EXPECT_EQ(loaded.frontend.whole_body_rrt.max_iterations, defaults.frontend.whole_body_rrt.max_iterations);
  EXPECT_EQ(loaded.frontend.time_allocation.base_speed_fraction, defaults.frontend.time_allocation.base_speed_fraction);
  EXPECT_EQ(loaded.frontend.time_allocation.base_accel_fraction, defaults.frontend.time_allocation.base_accel_fraction);
  EXPECT_EQ(loaded.frontend.time_allocation.joint_speed_fraction, defaults.frontend.time_allocation.joint_speed_fraction);
  EXPECT_EQ(loaded.frontend.time_allocation.min_step_time_s, defaults.frontend.time_allocation.min_step_time_s);
  EXPECT_EQ(loaded.midend.samples_per_piece, defaults.midend.samples_per_piece);
  EXPECT_EQ(loaded.midend.samples_per_edge, defaults.midend.samples_per_edge);
  EXPECT_EQ(loaded.midend.gear_sample_factor, defaults.midend.gear_sample_factor);
  EXPECT_EQ(loaded.midend.max_sample_interval_s, defaults.midend.max_sample_interval_s);
  EXPECT_EQ(loaded.midend.energy_weight_base, defaults.midend.energy_weight_base);
  EXPECT_EQ(loaded.midend.energy_weight_joint, defaults.midend.energy_weight_joint);
  EXPECT_EQ(loaded.midend.time_weight_per_s, defaults.midend.time_weight_per_s);
  EXPECT_EQ(loaded.midend.penalty_kind, defaults.midend.penalty_kind);
  EXPECT_EQ(loaded.midend.penalty_smoothing, defaults.midend.penalty_smoothing);
  EXPECT_EQ(loaded.midend.weight_wheel_velocity, defaults.midend.weight_wheel_velocity);
  EXPECT_EQ(loaded.midend.weight_wheel_acceleration, defaults.midend.weight_wheel_acceleration);
  EXPECT_EQ(loaded.midend.weight_joint_position, defaults.midend.weight_joint_position);
  EXPECT_EQ(loaded.midend.weight_joint_velocity, defaults.midend.weight_joint_velocity);
  EXPECT_EQ(loaded.midend.weight_joint_acceleration, defaults.midend.weight_joint_acceleration);
  EXPECT_EQ(loaded.midend.limit_penalty_fraction, defaults.midend.limit_penalty_fraction);
  EXPECT_EQ(loaded.midend.weight_residual_base, defaults.midend.weight_residual_base);
  EXPECT_EQ(loaded.midend.weight_residual_arm, defaults.midend.weight_residual_arm);
  EXPECT_EQ(loaded.midend.weight_min_speed, defaults.midend.weight_min_speed);
  EXPECT_EQ(loaded.midend.min_speed_fraction, defaults.midend.min_speed_fraction);
  EXPECT_EQ(loaded.midend.slow_reference_fraction, defaults.midend.slow_reference_fraction);
  EXPECT_EQ(loaded.midend.weight_boundary_heading, defaults.midend.weight_boundary_heading);
  EXPECT_EQ(loaded.midend.residual_base_bound_m, defaults.midend.residual_base_bound_m);
  EXPECT_EQ(loaded.midend.residual_arm_bound_rad, defaults.midend.residual_arm_bound_rad);
  EXPECT_EQ(loaded.midend.residual_yaw_weight_m2, defaults.midend.residual_yaw_weight_m2);
  EXPECT_EQ(loaded.midend.residual_penalty_fraction, defaults.midend.residual_penalty_fraction);
  EXPECT_EQ(loaded.midend.speed_guard_mps, defaults.midend.speed_guard_mps);
  EXPECT_EQ(loaded.midend.yaw_gate_speed_mps, defaults.midend.yaw_gate_speed_mps);
  EXPECT_EQ(loaded.midend.boundary_jerk_guard_mps3, defaults.midend.boundary_jerk_guard_mps3);
  EXPECT_EQ(loaded.midend.coincident_tolerance, defaults.midend.coincident_tolerance);
  EXPECT_EQ(loaded.midend.min_segment_length_m, defaults.midend.min_segment_length_m);
  EXPECT_EQ(loaded.midend.still_max_base_m, defaults.midend.still_max_base_m);
  EXPECT_EQ(loaded.midend.still_max_yaw_rad, defaults.midend.still_max_yaw_rad);
  EXPECT_EQ(loaded.midend.still_min_arm_rad, defaults.midend.still_min_arm_rad);
  EXPECT_EQ(loaded.midend.densify_factor, defaults.midend.densify_factor);
  EXPECT_EQ(loaded.midend.max_pieces_per_edge, defaults.midend.max_pieces_per_edge);
  EXPECT_EQ(loaded.midend.piece_length_m, defaults.midend.piece_length_m);
  EXPECT_EQ(loaded.midend.piece_arm_motion_rad, defaults.midend.piece_arm_motion_rad);
  EXPECT_EQ(loaded.midend.max_edges_per_piece, defaults.midend.max_edges_per_piece);
  EXPECT_EQ(loaded.midend.piece_duration_ratio, defaults.midend.piece_duration_ratio);
  EXPECT_EQ(loaded.midend.initial_speed_fraction, defaults.midend.initial_speed_fraction);
  EXPECT_EQ(loaded.midend.min_initial_piece_duration_s, defaults.midend.min_initial_piece_duration_s);
  EXPECT_EQ(loaded.midend.max_iterations, defaults.midend.max_iterations);
  EXPECT_EQ(loaded.midend.relative_cost_tolerance, defaults.midend.relative_cost_tolerance);
  EXPECT_EQ(loaded.midend.relative_cost_past, defaults.midend.relative_cost_past);
  EXPECT_EQ(loaded.midend.memory_size, defaults.midend.memory_size);
  EXPECT_EQ(loaded.midend.max_line_search, defaults.midend.max_line_search);
  EXPECT_EQ(loaded.midend.line_search, defaults.midend.line_search);
  EXPECT_EQ(loaded.midend.variable_scale, defaults.midend.variable_scale);
  EXPECT_EQ(loaded.midend.max_restarts, defaults.midend.max_restarts);
  EXPECT_EQ(loaded.midend.restart_min_decrease, defaults.midend.restart_min_decrease);
  EXPECT_EQ(loaded.midend.verify_tolerance, defaults.midend.verify_tolerance);
  EXPECT_EQ(loaded.midend.verify_step_s, defaults.midend.verify_step_s);
}

/// A copy of the shipped settings in a scratch directory, one file edited.
class EditedSettings : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("porter_settings_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
                                        "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
    for (const char* f : {"pipeline.yaml", "frontend.yaml", "midend.yaml", "backend.yaml"})
      fs::copy_file(shipped_dir() + "/" + f, dir_ / f, fs::copy_options::overwrite_existing);
  }
  void TearDown() override { fs::remove_all(dir_); }

  /// Replaces `from` (which must occur once) in `file` by `to`.
  void edit(const std::string& file, const std::string& from, const std::string& to) {
    std::string text = read((dir_ / file).string());
    const auto at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    ASSERT_EQ(text.find(from, at + 1), std::string::npos) << from;
    text.replace(at, from.size(), to);
    std::ofstream(dir_ / file) << text;
  }
  /// The LoadError message of loading the directory ("" when it loads).
  std::string error() const {
    try {
      load_planner_settings(dir_.string());
    } catch (const LoadError& e) {
      return e.what();
    }
    return "";
  }
  fs::path dir_;
};

TEST_F(EditedSettings, AMissingKeyIsRefusedNamingIt) {
  edit("midend.yaml", "  memory_size: 32                  # [3, 64]\n", "");
  const std::string e = error();
  EXPECT_NE(e.find("midend.yaml"), std::string::npos) << e;
  EXPECT_NE(e.find("solver.memory_size"), std::string::npos) << e;
  EXPECT_NE(e.find("missing"), std::string::npos) << e;
}

TEST_F(EditedSettings, AnUnknownKeyIsRefusedNamingIt) {
  edit("backend.yaml", "  probe_first_step: true\n", "  probe_first_step: true\n  stop_after_safe_iterations: 3\n");
  const std::string e = error();
  EXPECT_NE(e.find("backend.yaml"), std::string::npos) << e;
  EXPECT_NE(e.find("solver.stop_after_safe_iterations"), std::string::npos) << e;
  EXPECT_NE(e.find("unknown key"), std::string::npos) << e;
}

TEST_F(EditedSettings, AnOutOfRangeValueIsRefusedNamingIt) {
  edit("pipeline.yaml", "retry_arm_residual_scale: 0.5", "retry_arm_residual_scale: 1.5");
  std::string e = error();
  EXPECT_NE(e.find("pipeline.yaml"), std::string::npos) << e;
  EXPECT_NE(e.find("retry_arm_residual_scale"), std::string::npos) << e;
  EXPECT_NE(e.find("(0, 1]"), std::string::npos) << e;
  SetUp();  // fresh copies
  edit("frontend.yaml", "  yaw_bins: 72", "  yaw_bins: 4");
  e = error();
  EXPECT_NE(e.find("frontend.yaml"), std::string::npos) << e;
  EXPECT_NE(e.find("hybrid_astar.yaw_bins"), std::string::npos) << e;
  SetUp();
  edit("midend.yaml", "  memory_size: 32", "  memory_size: 2");
  e = error();
  EXPECT_NE(e.find("solver.memory_size"), std::string::npos) << e;
  EXPECT_NE(e.find("[3, 64]"), std::string::npos) << e;
}

TEST_F(EditedSettings, AWrongTypeOrChoiceIsRefusedNamingIt) {
  edit("pipeline.yaml", "safety: kc_svsdf ", "safety: spheres ");
  std::string e = error();
  EXPECT_NE(e.find("pipeline.yaml"), std::string::npos) << e;
  EXPECT_NE(e.find("key 'safety'"), std::string::npos) << e;
  SetUp();
  edit("backend.yaml", "  max_iterations: 200 ", "  max_iterations: many ");
  e = error();
  EXPECT_NE(e.find("backend.yaml"), std::string::npos) << e;
  EXPECT_NE(e.find("solver.max_iterations"), std::string::npos) << e;
}

TEST_F(EditedSettings, ACombinationTheStageRefusesNamesTheFile) {
  // Each probability is in [0, 1], their sum is not: the front-end's own check.
  edit("frontend.yaml", "  goal_bias: 0.45", "  goal_bias: 0.8");
  const std::string e = error();
  EXPECT_NE(e.find("frontend.yaml"), std::string::npos) << e;
  EXPECT_NE(e.find("local_bias"), std::string::npos) << e;
}

TEST_F(EditedSettings, AnAbsurdBudgetIsRefusedNamingIt) {
  // 1e9 s: milliseconds written where seconds are meant.
  edit("pipeline.yaml", "  frontend_s: 1.0 ", "  frontend_s: 1e9 ");
  const std::string e = error();
  EXPECT_NE(e.find("pipeline"), std::string::npos) << e;
  EXPECT_NE(e.find("budgets.frontend_s"), std::string::npos) << e;
  EXPECT_NE(e.find("(0, 3600]"), std::string::npos) << e;
}

TEST_F(EditedSettings, AnEditedValueIsUsed) {
  edit("pipeline.yaml", "  midend_s: 0.1 ", "  midend_s: 0.25 ");
  EXPECT_EQ(error(), "");
  EXPECT_EQ(load_planner_settings(dir_.string()).pipeline.midend_budget_s, 0.25);
}

TEST(PlannerSettingsYaml, AMissingFileIsRefusedNamingIt) {
  try {
    load_planner_settings("/nonexistent/planner");
    FAIL() << "loaded a missing directory";
  } catch (const LoadError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/planner/pipeline.yaml"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace porter::pipeline

// Every number of the four shipped files replaced by hostile values: NaN, infinities and 1e300
// are refused naming the file (or, for a check across the files, the directory's *.yaml);
// 0, -1, 1e-300, 1e9 load or are refused, never crash (tests/support/hostile_config.hpp).
TEST(PlannerSettingsHostile, EveryNumberIsRangeChecked) {
  const auto load = [](const std::string& f) {
    porter::pipeline::load_planner_settings(std::filesystem::path(f).parent_path().string());
  };
  for (const char* file : {"planner/pipeline.yaml", "planner/frontend.yaml", "planner/midend.yaml", "planner/backend.yaml"}) {
    EXPECT_GE(porter::test::check_hostile_numbers(file, load, "*.yaml"), 11 * 10) << file;
  }
}
