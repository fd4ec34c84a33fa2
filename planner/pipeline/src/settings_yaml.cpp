#include "porter/pipeline/settings_yaml.hpp"

#include "porter/backend/backend.hpp"

#include <optional>

#include "yaml_fields.hpp"

namespace porter::pipeline {

namespace {

using detail::Fields;
using detail::kMaxAngle_rad, detail::kMaxLength_m, detail::kMaxSpeed, detail::kMaxTime_s, detail::kMaxWeight;
using detail::kMinCell_m, detail::kMinStep_rad, detail::kMinStep_s;

}  // namespace


void load_pipeline_yaml(const std::string& file, PlannerSettings& s) {
  const yaml::Reader root = yaml::Reader::load_file(file);
  const Fields top(root, {"budgets", "collision", "safety", "self_collision_term", "retry_arm_residual_scale",
                          "choose_warm_start_by_safety", "goal",
                          "kernels", "spheres"});
  PipelineSettings& p = s.pipeline;
  {
    const Fields f(top.section("budgets"), {"frontend_s", "midend_s", "backend_s"});
    f.positive("frontend_s", p.frontend_budget_s, kMaxTime_s);
    f.positive("midend_s", p.midend_budget_s, kMaxTime_s);
    f.positive("backend_s", p.backend_budget_s, kMaxTime_s);
  }
  top.choice("collision", p.collision, baselines::parse_collision_model, "kernels, spheres");
  top.choice(
      "safety", p.safety,
      [](const std::string& n) {
        const std::optional<baselines::SafetyModel> m = baselines::parse_safety_model(n);
        return m == baselines::SafetyModel::kSpheres ? std::nullopt : m;
      },
      "kc_svsdf, svsdf_per_link (spheres follows from collision: spheres)");
  top.flag("self_collision_term", p.self_collision_term);
  top.fraction("retry_arm_residual_scale", p.retry_arm_residual_scale);
  top.flag("choose_warm_start_by_safety", p.choose_warm_start_by_safety);
  {
    const Fields f(top.section("goal"), {"position_tolerance_m", "yaw_tolerance_rad", "free_arm_candidates"});
    f.nonnegative("position_tolerance_m", p.goal_position_tolerance_m, kMaxLength_m);
    f.number("yaw_tolerance_rad", p.goal_yaw_tolerance_rad, 0.0, 3.14159265358979323846);
    f.integer("free_arm_candidates", p.free_arm_candidates, 0, 100000);
  }
  {
    planner::KernelCheckerSettings& k = s.kernels;
    const Fields f(top.section("kernels"), {"resolution_m", "max_sample_error_m", "base_yaw_samples", "lattice_subdivision",
                                            "safety_margin_m", "distance_cap_m", "motion_step_m", "self_collision"});
    f.number("resolution_m", k.kernels.resolution_m, 0.005, 1.0);
    f.zero_or_in("max_sample_error_m", k.kernels.max_sample_error_m, kMinCell_m, kMaxLength_m);
    f.integer("base_yaw_samples", k.kernels.base_yaw_samples, 0, 4096);
    f.integer("lattice_subdivision", k.kernels.lattice_subdivision, 1, 8);
    f.nonnegative("safety_margin_m", k.map.safety_margin_m, kMaxLength_m);
    f.positive("distance_cap_m", k.map.distance_cap_m, kMaxLength_m);
    f.zero_or_in("motion_step_m", k.motion_step_m, kMinCell_m, kMaxLength_m);
    const Fields self(f.section("self_collision"),
                      {"check", "sample_spacing_m", "prove_pairs", "proof_max_boxes", "proof_min_cell_m"});
    self.flag("check", k.check_self_collision);
    self.number("sample_spacing_m", k.self.sample_spacing_m, 0.001, 0.1);
    self.flag("prove_pairs", k.self.prove_pairs);
    self.integer("proof_max_boxes", k.self.proof_max_boxes, 1);
    self.number("proof_min_cell_m", k.self.proof_min_cell_m, kMinCell_m, kMaxLength_m);
  }
  {
    const Fields f(top.section("spheres"), {"cell_m", "max_distance_m", "check_self_collision", "motion_step_m"});
    f.number("cell_m", s.spheres.cover.cell_m, kMinCell_m, kMaxLength_m);
    f.positive("max_distance_m", s.spheres.max_distance_m, kMaxLength_m);
    f.flag("check_self_collision", s.spheres.check_self_collision);
    f.zero_or_in("motion_step_m", s.spheres.motion_step_m, kMinCell_m, kMaxLength_m);
  }
}

void load_backend_yaml(const std::string& file, PlannerSettings& s) {
  const yaml::Reader root = yaml::Reader::load_file(file);
  const Fields top(root, {"solver", "recheck", "kc_svsdf", "spheres", "self_collision"});
  backend::BackendSettings& b = s.backend;
  {
    const Fields f(top.section("solver"), {"max_iterations", "relative_cost_tolerance", "relative_cost_past", "memory_size",
                                           "max_line_search", "line_search", "variable_scale", "probe_first_step",
                                           "skip_safety_above_current"});
    f.integer("max_iterations", b.max_iterations, 1);
    f.positive("relative_cost_tolerance", b.relative_cost_tolerance, kMaxWeight);
    f.integer("relative_cost_past", b.relative_cost_past, 1);
    f.integer("memory_size", b.memory_size, 3, 64);
    f.integer("max_line_search", b.max_line_search, 1);
    f.choice("line_search", b.line_search, detail::parse_line_search, detail::kLineSearches);
    f.positive("variable_scale", b.variable_scale, kMaxWeight);
    f.flag("probe_first_step", b.probe_first_step);
    f.flag("skip_safety_above_current", b.skip_safety_above_current);
  }
  {
    const Fields f(top.section("recheck"), {"every_iterations", "weight_escalation_factor", "max_weight_escalations",
                                            "window_grow_pieces", "window_max_fraction", "window_cut_jerk_weight"});
    f.integer("every_iterations", b.recheck_every_iterations, 0);
    f.number("weight_escalation_factor", b.weight_escalation_factor, 1.0, 1e6);
    f.integer("max_weight_escalations", b.max_weight_escalations, 0, 64);
    f.integer("window_grow_pieces", b.window_grow_pieces, 0);
    f.number("window_max_fraction", b.window_max_fraction, 1e-9, 1.0);
    f.number("window_cut_jerk_weight", b.window_cut_jerk_weight, 0.0, 1e12);
  }
  {
    backend::SvsdfSafetySettings& t = s.safety_terms.svsdf;
    const Fields f(top.section("kc_svsdf"),
                   {"weight", "threads", "freeze_ball_decisions", "selection_slack_m", "prefilter_slack_m"});
    f.positive("weight", t.weight, kMaxWeight);
    f.integer("threads", t.threads, 1, 64);
    f.flag("freeze_ball_decisions", t.freeze_ball_decisions);
    f.nonnegative("selection_slack_m", t.selection_slack_m, kMaxLength_m);
    f.nonnegative("prefilter_slack_m", t.prefilter_slack_m, kMaxLength_m);
  }
  {
    baselines::SphereSafetySettings& t = s.safety_terms.spheres;
    const Fields f(top.section("spheres"),
                   {"cell_m", "safety_margin_m", "weight", "samples_per_piece", "crop_margin_m", "max_distance_m"});
    f.number("cell_m", t.cover.cell_m, kMinCell_m, kMaxLength_m);
    f.positive("safety_margin_m", t.safety_margin_m, kMaxLength_m);
    f.positive("weight", t.weight, kMaxWeight);
    f.integer("samples_per_piece", t.samples_per_piece, 1, 1024);
    f.nonnegative("crop_margin_m", t.crop_margin_m, kMaxLength_m);
    f.positive("max_distance_m", t.max_distance_m, kMaxLength_m);
  }
  {
    backend::SelfCollisionTermSettings& t = s.self_collision;
    const Fields f(top.section("self_collision"), {"weight", "sample_interval_s", "point_spacing_m", "slack_m",
                                                   "relative_to_warm_start", "warm_start_slack_m"});
    f.positive("weight", t.weight, kMaxWeight);
    f.number("sample_interval_s", t.sample_interval_s, kMinStep_s, kMaxTime_s);
    f.number("point_spacing_m", t.point_spacing_m, kMinCell_m, kMaxLength_m);
    f.nonnegative("slack_m", t.slack_m, kMaxLength_m);
    f.flag("relative_to_warm_start", t.relative_to_warm_start);
    f.nonnegative("warm_start_slack_m", t.warm_start_slack_m, kMaxLength_m);
  }
  detail::check(file, [&](std::string* why) { return backend::validate_settings(b, why); });
}

PlannerSettings load_planner_settings(const std::string& dir) {
  PlannerSettings s;
  const std::string base = dir.empty() || dir.back() == '/' ? dir : dir + "/";
  load_pipeline_yaml(base + "pipeline.yaml", s);
  load_frontend_yaml(base + "frontend.yaml", s.frontend);
  load_midend_yaml(base + "midend.yaml", s.midend);
  load_backend_yaml(base + "backend.yaml", s);
  std::string why;
  if (!validate_settings(s, &why)) throw LoadError(base + "*.yaml", "", why);
  return s;
}

}  // namespace porter::pipeline
