// The front-end's and the mid-end's settings files (settings_yaml.hpp).
#include <optional>

#include "porter/midend/midend.hpp"
#include "porter/pipeline/settings_yaml.hpp"
#include "yaml_fields.hpp"

namespace porter::pipeline {

using detail::Fields;
using detail::kMaxAngle_rad, detail::kMaxLength_m, detail::kMaxSpeed, detail::kMaxTime_s, detail::kMaxWeight;
using detail::kMinCell_m, detail::kMinStep_rad, detail::kMinStep_s;

void load_frontend_yaml(const std::string& file, frontend::FrontendSettings& s) {
  const yaml::Reader root = yaml::Reader::load_file(file);
  const Fields top(root, {"hybrid_astar_budget_fraction", "layered_arm_budget_fraction", "arm_time_scale",
                          "min_layer_time_s", "bridge_margin_layers", "hybrid_astar", "layered_arm", "whole_body_rrt",
                          "time_allocation"});
  top.fraction("hybrid_astar_budget_fraction", s.hybrid_astar_budget_fraction);
  top.fraction("layered_arm_budget_fraction", s.layered_arm_budget_fraction);
  top.positive("arm_time_scale", s.arm_time_scale, kMaxWeight);
  top.number("min_layer_time_s", s.min_layer_time_s, kMinStep_s, kMaxTime_s);
  top.integer("bridge_margin_layers", s.bridge_margin_layers, 0);
  {
    frontend::HybridAStarSettings& h = s.hybrid_astar;
    const Fields f(top.section("hybrid_astar"),
                   {"xy_resolution_m", "yaw_bins", "step_length_m", "steering_samples", "turning_radius_m",
                    "collision_step_m", "reverse_cost_factor", "gear_switch_cost_m", "steering_cost",
                    "steering_change_cost", "heuristic_weight", "rs_heuristic_range_m", "analytic_expansion_range_m",
                    "analytic_expansion_interval", "max_shot_cusps", "whole_body_guidance", "arm_blocked_cost_factor",
                    "narrow_shape_draws", "heuristic_resolution_m", "max_expansions"});
    f.number("xy_resolution_m", h.xy_resolution_m, 0.02, 1.0);
    f.integer("yaw_bins", h.yaw_bins, 8, 360);
    f.number("step_length_m", h.step_length_m, kMinCell_m, kMaxLength_m);
    f.integer("steering_samples", h.steering_samples, 3, 15);
    f.nonnegative("turning_radius_m", h.turning_radius_m, kMaxLength_m);
    f.number("collision_step_m", h.collision_step_m, 0.005, 0.5);
    f.number("reverse_cost_factor", h.reverse_cost_factor, 1.0, 1e6);
    f.nonnegative("gear_switch_cost_m", h.gear_switch_cost_m, kMaxLength_m);
    f.nonnegative("steering_cost", h.steering_cost, kMaxWeight);
    f.nonnegative("steering_change_cost", h.steering_change_cost, kMaxWeight);
    f.number("heuristic_weight", h.heuristic_weight, 1.0, 100.0);
    f.nonnegative("rs_heuristic_range_m", h.rs_heuristic_range_m, kMaxLength_m);
    f.nonnegative("analytic_expansion_range_m", h.analytic_expansion_range_m, kMaxLength_m);
    f.integer("analytic_expansion_interval", h.analytic_expansion_interval, 1);
    f.integer("max_shot_cusps", h.max_shot_cusps, 0, 3);
    f.flag("whole_body_guidance", h.whole_body_guidance);
    f.nonnegative("arm_blocked_cost_factor", h.arm_blocked_cost_factor, kMaxWeight);
    f.integer("narrow_shape_draws", h.narrow_shape_draws, 0, 100000);
    f.number("heuristic_resolution_m", h.heuristic_resolution_m, kMinCell_m, kMaxLength_m);
    f.integer("max_expansions", h.max_expansions, 1);
  }
  {
    frontend::LayeredArmSettings& l = s.layered_arm;
    const Fields f(top.section("layered_arm"),
                   {"arm_speed_fraction", "goal_bias", "hold_bias", "local_bias", "corridor_bias", "corridor_draws",
                    "corridor_margin_m", "max_corridor_targets", "corridor_target_bias", "chain_retries",
                    "frontier_bias", "frontier_window", "optimize_before_connection", "max_parent_candidates",
                    "max_connect_candidates", "refine_iterations", "shortcut_attempts", "shortcut_max_layers",
                    "max_iterations"});
    f.fraction("arm_speed_fraction", l.arm_speed_fraction);
    f.probability("goal_bias", l.goal_bias);
    f.probability("hold_bias", l.hold_bias);
    f.probability("local_bias", l.local_bias);
    f.probability("corridor_bias", l.corridor_bias);
    f.integer("corridor_draws", l.corridor_draws, 1);
    f.nonnegative("corridor_margin_m", l.corridor_margin_m, kMaxLength_m);
    f.integer("max_corridor_targets", l.max_corridor_targets, 0);
    f.probability("corridor_target_bias", l.corridor_target_bias);
    f.integer("chain_retries", l.chain_retries, 0);
    f.probability("frontier_bias", l.frontier_bias);
    f.integer("frontier_window", l.frontier_window, 1);
    f.flag("optimize_before_connection", l.optimize_before_connection);
    f.integer("max_parent_candidates", l.max_parent_candidates, 1);
    f.integer("max_connect_candidates", l.max_connect_candidates, 1);
    f.integer("refine_iterations", l.refine_iterations, 0);
    f.integer("shortcut_attempts", l.shortcut_attempts, 0);
    f.integer("shortcut_max_layers", l.shortcut_max_layers, 2);
    f.integer("max_iterations", l.max_iterations, 1);
  }
  {
    frontend::WholeBodyRrtSettings& w = s.whole_body_rrt;
    const Fields f(top.section("whole_body_rrt"),
                   {"max_extend_m", "max_extend_q_rad", "reverse_cost_factor", "gear_switch_cost_m",
                    "joint_cost_weight_m_per_rad", "goal_bias", "sampling_margin_m", "neighbours", "edge_step_m",
                    "edge_q_step_rad", "refine_iterations", "max_iterations"});
    f.number("max_extend_m", w.max_extend_m, kMinCell_m, kMaxLength_m);
    f.number("max_extend_q_rad", w.max_extend_q_rad, kMinStep_rad, kMaxAngle_rad);
    f.number("reverse_cost_factor", w.reverse_cost_factor, 1.0, 1e6);
    f.nonnegative("gear_switch_cost_m", w.gear_switch_cost_m, kMaxLength_m);
    f.nonnegative("joint_cost_weight_m_per_rad", w.joint_cost_weight_m_per_rad, kMaxWeight);
    f.probability("goal_bias", w.goal_bias);
    f.nonnegative("sampling_margin_m", w.sampling_margin_m, kMaxLength_m);
    f.integer("neighbours", w.neighbours, 1);
    f.number("edge_step_m", w.edge_step_m, kMinCell_m, kMaxLength_m);
    f.number("edge_q_step_rad", w.edge_q_step_rad, kMinStep_rad, kMaxAngle_rad);
    f.integer("refine_iterations", w.refine_iterations, 0);
    f.integer("max_iterations", w.max_iterations, 1);
  }
  {
    frontend::TimeAllocationSettings& t = s.time_allocation;
    const Fields f(top.section("time_allocation"),
                   {"base_speed_fraction", "base_accel_fraction", "joint_speed_fraction", "min_step_time_s"});
    f.fraction("base_speed_fraction", t.base_speed_fraction);
    f.fraction("base_accel_fraction", t.base_accel_fraction);
    f.fraction("joint_speed_fraction", t.joint_speed_fraction);
    f.number("min_step_time_s", t.min_step_time_s, kMinStep_s, kMaxTime_s);
  }
  detail::check(file, [&](std::string* why) { return frontend::validate_settings(s, why); });
}

void load_midend_yaml(const std::string& file, midend::MidendSettings& s) {
  const yaml::Reader root = yaml::Reader::load_file(file);
  const Fields top(root, {"transcription", "objective", "penalties", "residuals", "guards", "reference", "solver", "verify"});
  {
    const Fields f(top.section("transcription"),
                   {"samples_per_piece", "samples_per_edge", "gear_sample_factor", "max_sample_interval_s"});
    f.integer("samples_per_piece", s.samples_per_piece, 2, 64);
    f.integer("samples_per_edge", s.samples_per_edge, 1, 64);
    f.integer("gear_sample_factor", s.gear_sample_factor, 1, 16);
    f.zero_or_in("max_sample_interval_s", s.max_sample_interval_s, kMinStep_s, kMaxTime_s);
  }
  {
    const Fields f(top.section("objective"), {"energy_weight_base", "energy_weight_joint", "time_weight_per_s"});
    f.positive("energy_weight_base", s.energy_weight_base, kMaxWeight);
    f.positive("energy_weight_joint", s.energy_weight_joint, kMaxWeight);
    f.positive("time_weight_per_s", s.time_weight_per_s, kMaxWeight);
  }
  {
    const Fields f(top.section("penalties"),
                   {"kind", "smoothing", "weight_wheel_velocity", "weight_wheel_acceleration", "weight_joint_position",
                    "weight_joint_velocity", "weight_joint_acceleration", "limit_penalty_fraction",
                    "weight_residual_base", "weight_residual_arm", "weight_min_speed", "min_speed_fraction",
                    "slow_reference_fraction", "weight_boundary_heading"});
    f.choice(
        "kind", s.penalty_kind,
        [](const std::string& n) -> std::optional<minco::PenaltyKind> {
          if (n == "smoothed_l1") return minco::PenaltyKind::kSmoothedL1;
          if (n == "cubic") return minco::PenaltyKind::kCubic;
          return std::nullopt;
        },
        "smoothed_l1, cubic");
    f.fraction("smoothing", s.penalty_smoothing);
    f.nonnegative("weight_wheel_velocity", s.weight_wheel_velocity, kMaxWeight);
    f.nonnegative("weight_wheel_acceleration", s.weight_wheel_acceleration, kMaxWeight);
    f.nonnegative("weight_joint_position", s.weight_joint_position, kMaxWeight);
    f.nonnegative("weight_joint_velocity", s.weight_joint_velocity, kMaxWeight);
    f.nonnegative("weight_joint_acceleration", s.weight_joint_acceleration, kMaxWeight);
    f.fraction("limit_penalty_fraction", s.limit_penalty_fraction);
    f.nonnegative("weight_residual_base", s.weight_residual_base, kMaxWeight);
    f.nonnegative("weight_residual_arm", s.weight_residual_arm, kMaxWeight);
    f.nonnegative("weight_min_speed", s.weight_min_speed, kMaxWeight);
    f.probability("min_speed_fraction", s.min_speed_fraction);
    f.fraction("slow_reference_fraction", s.slow_reference_fraction);
    f.nonnegative("weight_boundary_heading", s.weight_boundary_heading, kMaxWeight);
  }
  {
    const Fields f(top.section("residuals"), {"base_bound_m", "arm_bound_rad", "yaw_weight_m2", "penalty_fraction"});
    f.positive("base_bound_m", s.residual_base_bound_m, kMaxLength_m);
    f.positive("arm_bound_rad", s.residual_arm_bound_rad, kMaxAngle_rad);
    f.nonnegative("yaw_weight_m2", s.residual_yaw_weight_m2, kMaxWeight);
    f.fraction("penalty_fraction", s.residual_penalty_fraction);
  }
  {
    const Fields f(top.section("guards"), {"speed_guard_mps", "yaw_gate_speed_mps", "boundary_jerk_guard_mps3"});
    f.positive("speed_guard_mps", s.speed_guard_mps, kMaxSpeed);
    f.positive("yaw_gate_speed_mps", s.yaw_gate_speed_mps, kMaxSpeed);
    f.positive("boundary_jerk_guard_mps3", s.boundary_jerk_guard_mps3, kMaxSpeed);
  }
  {
    const Fields f(top.section("reference"),
                   {"coincident_tolerance", "min_segment_length_m", "still_max_base_m", "still_max_yaw_rad",
                    "still_min_arm_rad", "densify_factor", "max_pieces_per_edge", "piece_length_m",
                    "piece_arm_motion_rad", "max_edges_per_piece", "piece_duration_ratio", "initial_speed_fraction",
                    "min_initial_piece_duration_s"});
    f.nonnegative("coincident_tolerance", s.coincident_tolerance, kMaxWeight);
    f.nonnegative("min_segment_length_m", s.min_segment_length_m, kMaxLength_m);
    f.nonnegative("still_max_base_m", s.still_max_base_m, kMaxLength_m);
    f.nonnegative("still_max_yaw_rad", s.still_max_yaw_rad, kMaxAngle_rad);
    f.nonnegative("still_min_arm_rad", s.still_min_arm_rad, kMaxAngle_rad);
    f.number("densify_factor", s.densify_factor, 1.0, 1e6);
    f.integer("max_pieces_per_edge", s.max_pieces_per_edge, 1);
    f.number("piece_length_m", s.piece_length_m, 0.01, kMaxLength_m);  // pieces per metre
    f.number("piece_arm_motion_rad", s.piece_arm_motion_rad, 0.01, kMaxAngle_rad);  // pieces per radian
    f.integer("max_edges_per_piece", s.max_edges_per_piece, 1);
    f.number("piece_duration_ratio", s.piece_duration_ratio, 1.0, 1e6);
    f.fraction("initial_speed_fraction", s.initial_speed_fraction);
    f.positive("min_initial_piece_duration_s", s.min_initial_piece_duration_s, kMaxTime_s);
  }
  {
    const Fields f(top.section("solver"), {"max_iterations", "relative_cost_tolerance", "relative_cost_past",
                                           "memory_size", "max_line_search", "line_search", "variable_scale",
                                           "max_restarts", "restart_min_decrease"});
    f.integer("max_iterations", s.max_iterations, 1);
    f.positive("relative_cost_tolerance", s.relative_cost_tolerance, kMaxWeight);
    f.integer("relative_cost_past", s.relative_cost_past, 1);
    f.integer("memory_size", s.memory_size, 3, 64);
    f.integer("max_line_search", s.max_line_search, 1);
    f.choice("line_search", s.line_search, detail::parse_line_search, detail::kLineSearches);
    f.positive("variable_scale", s.variable_scale, kMaxWeight);
    f.integer("max_restarts", s.max_restarts, 0);
    f.nonnegative("restart_min_decrease", s.restart_min_decrease, kMaxWeight);
  }
  {
    const Fields f(top.section("verify"), {"tolerance", "step_s"});
    f.nonnegative("tolerance", s.verify_tolerance, kMaxWeight);
    f.zero_or_in("step_s", s.verify_step_s, kMinStep_s, kMaxTime_s);
  }
  detail::check(file, [&](std::string* why) { return midend::validate_settings(s, why); });
}

}  // namespace porter::pipeline
