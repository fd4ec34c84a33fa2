#include "planner_config.hpp"

#include <cmath>
#include <stdexcept>

#include "porter/core/load_error.hpp"
#include "porter/core/scene_loader.hpp"
#include "porter/core/yaml_reader.hpp"
#include "porter/pipeline/settings_yaml.hpp"

namespace porter::planner_app {

double worst_case_plan_s(const pipeline::PlannerSettings& s) {
  return s.pipeline.frontend_budget_s + 2.0 * s.pipeline.midend_budget_s + s.pipeline.backend_budget_s;
}

PlannerConfig load_planner_config(const std::string& path) {
  const auto cfg = yaml::Reader::load_file(path);
  cfg.expect_keys({"robot", "planner_settings", "frame_id", "payload", "payloads", "map", "state", "replan",
                   "braking", "tick_hz"});
  PlannerConfig out;
  out.file = path;
  out.robot_file = yaml::resolve_path(path, cfg.get("robot").as_string());
  out.settings_dir = yaml::resolve_path(path, cfg.get("planner_settings").as_string());
  out.frame_id = cfg.get("frame_id").as_string();
  if (out.frame_id.empty()) cfg.get("frame_id").fail("must not be empty");

  const auto payloads = cfg.get("payloads");
  if (!payloads.is_map()) payloads.fail("must be a map of payload id -> payload YAML");
  for (const std::string& id : payloads.keys()) {
    if (id.empty() || id == "none") payloads.get(id).fail("'none' and '' are reserved for the empty gripper");
    out.payloads[id] = yaml::resolve_path(path, payloads.get(id).as_string());
  }
  out.payload_id = cfg.get("payload").as_string();
  if (out.payload_id != "none" && out.payloads.count(out.payload_id) == 0) {
    cfg.get("payload").fail("must be 'none' or a key of 'payloads'");
  }

  const auto map = cfg.get("map");
  map.expect_keys({"resolution_m", "max_age_s", "margin_m", "block_m", "min_height_m", "max_voxels", "max_mb",
                   "unknown_below_occupied", "robot_clear_radius_m"});
  // Lengths within 1 km (the grid is also bounded by max_voxels and max_mb); the resolution in
  // the planner's range (as for scene files); ages, periods and durations within an hour.
  out.map.resolution_m = map.get("resolution_m").as_in(kSceneMinResolution_m, kSceneMaxResolution_m, "m");
  out.loop.max_map_age_s = map.get("max_age_s").as_in(0.0, 3600.0, "s", true);
  out.map.margin_m = map.get("margin_m").as_in(0.0, 1000.0, "m");
  out.map.block_m = map.get("block_m").as_in(0.0, 1000.0, "m", true);
  out.map.min_height_m = map.get("min_height_m").as_in(0.0, 1000.0, "m", true);
  out.map.max_voxels = map.get("max_voxels").as_in(0.0, 1e10, "voxels", true);
  const int max_mb = map.get("max_mb").as_int();
  if (max_mb < 1 || max_mb > 1024) map.get("max_mb").fail("must be in [1, 1024]");
  out.map.max_bytes = static_cast<std::size_t>(max_mb) << 20;
  const std::string below = map.get("unknown_below_occupied").as_string();
  if (below != "occupied" && below != "free") map.get("unknown_below_occupied").fail("must be 'occupied' or 'free'");
  out.map.fill_unknown_below = below == "occupied";
  out.map.fill_clear_radius_m = map.get("robot_clear_radius_m").as_in(0.0, 100.0, "m");

  const auto state = cfg.get("state");
  state.expect_keys({"max_age_s"});
  out.loop.max_state_age_s = state.get("max_age_s").as_in(0.0, 3600.0, "s", true);

  const auto replan = cfg.get("replan");
  replan.expect_keys(
      {"lead_s", "latency_s", "reserve_s", "collision_step_s", "max_attempts", "seed", "arrival_tolerance_m"});
  out.loop.handoff.lead_s = replan.get("lead_s").as_in(0.0, 3600.0, "s", true);
  out.loop.handoff.latency_s = replan.get("latency_s").as_in(0.0, 3600.0, "s", true);
  // Less than the lead (checked below with it), so at most a minute.
  out.loop.handoff_reserve_s = replan.get("reserve_s").as_in(0.0, 60.0, "s");
  // The executing trajectory is sampled at this step on every map: 1 ms at least.
  out.loop.collision_step_s = replan.get("collision_step_s").as_in(1e-3, 10.0, "s");
  out.loop.arrival_tolerance_m = replan.get("arrival_tolerance_m").as_in(0.0, 100.0, "m", true);
  out.loop.max_attempts = replan.get("max_attempts").as_int();
  if (out.loop.max_attempts < 1 || out.loop.max_attempts > 1000) replan.get("max_attempts").fail("must be in [1, 1000]");
  const int seed = replan.get("seed").as_int();
  if (seed < 0) replan.get("seed").fail("must be >= 0");
  out.loop.seed = static_cast<std::uint64_t>(seed);

  const auto braking = cfg.get("braking");
  braking.expect_keys({"base_decel_mps2", "joint_decel_radps2", "min_duration_s"});
  out.loop.handoff.braking.base_decel_mps2 = braking.get("base_decel_mps2").as_in(0.0, 100.0, "m/s^2", true);
  out.loop.handoff.braking.joint_decel_radps2 = braking.get("joint_decel_radps2").as_in(0.0, 1e4, "rad/s^2", true);
  out.loop.handoff.braking.min_duration_s = braking.get("min_duration_s").as_in(0.0, 60.0, "s", true);

  out.tick_hz = cfg.get("tick_hz").as_positive();
  if (out.tick_hz > 100.0) cfg.get("tick_hz").fail("must be in (0, 100]");

  out.settings = pipeline::load_planner_settings(out.settings_dir);
  out.settings.kernels.kernels.resolution_m = out.map.resolution_m;
  const double worst = worst_case_plan_s(out.settings);
  if (out.loop.handoff.lead_s <= worst + out.loop.handoff.latency_s) {
    replan.get("lead_s").fail("must exceed the pipeline's longest plan (" + std::to_string(worst) +
                              " s, from " + out.settings_dir + ") plus latency_s");
  }
  if (out.loop.handoff_reserve_s + out.loop.handoff.latency_s >= out.loop.handoff.lead_s)
    replan.get("reserve_s").fail("plus latency_s must be less than lead_s");
  try {
    out.loop.validate();
  } catch (const std::invalid_argument& e) {
    throw LoadError(path, "", e.what());
  }
  return out;
}

}  // namespace porter::planner_app
