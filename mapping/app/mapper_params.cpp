#include "mapper_params.hpp"

#include <cmath>

#include "porter/core/load_error.hpp"
#include "porter/core/yaml_reader.hpp"

namespace porter::mapping::app {

MapperConfig load_mapper_config(const std::string& path) {
  const auto cfg = yaml::Reader::load_file(path);
  cfg.expect_keys({"lcm_url", "robot", "payload", "frames", "publish_rate_hz", "state", "queue",
                   "status_log_period_s", "sensor", "range", "map", "self_filter", "voxel_grid",
                   "outlier_removal"});
  MapperConfig out;
  out.file = path;
  out.lcm_url = cfg.get("lcm_url").as_string();
  out.robot_yaml = yaml::resolve_path(path, cfg.get("robot").as_string());
  const std::string payload = cfg.get("payload").as_string();
  out.payload_yaml = payload == "none" ? "" : yaml::resolve_path(path, payload);

  const auto frames = cfg.get("frames");
  frames.expect_keys({"cloud", "map"});
  out.cloud_frame_id = frames.get("cloud").as_string();
  out.map_frame_id = frames.get("map").as_string();
  if (out.cloud_frame_id.empty()) frames.get("cloud").fail("must not be empty");
  if (out.map_frame_id.empty()) frames.get("map").fail("must not be empty");

  out.publish_rate_hz = cfg.get("publish_rate_hz").as_positive();
  if (out.publish_rate_hz > 20.0) cfg.get("publish_rate_hz").fail("must be in (0, 20]");
  const auto state = cfg.get("state");
  state.expect_keys({"wait_s", "history_s"});
  out.state_wait_s = state.get("wait_s").as_nonnegative();
  out.state_history_s = state.get("history_s").as_positive();
  if (out.state_wait_s > 1.0) state.get("wait_s").fail("must be in [0, 1]");
  const auto queue = cfg.get("queue");
  queue.expect_keys({"max_clouds"});
  out.max_queued_clouds = queue.get("max_clouds").as_int();
  if (out.max_queued_clouds < 1 || out.max_queued_clouds > 100) queue.get("max_clouds").fail("must be in [1, 100]");
  out.status_log_period_s = cfg.get("status_log_period_s").as_positive();

  MapperParams& p = out.mapper;
  const auto sensor = cfg.get("sensor");
  sensor.expect_keys({"T_B_S"});
  p.T_B_S = sensor.get("T_B_S").as_pose();

  const auto range = cfg.get("range");
  range.expect_keys({"min_m", "max_m", "ground_height_m"});
  p.min_range_m = range.get("min_m").as_nonnegative();
  p.max_range_m = range.get("max_m").as_positive();
  p.ground_height_m = range.get("ground_height_m").as_double();

  const auto map = cfg.get("map");
  map.expect_keys({"resolution_m", "size_voxels", "z_min_m", "recenter_distance_m", "prob_hit",
                   "prob_miss", "clamp_min", "clamp_max", "occupancy_threshold", "new_surface_shadow_m"});
  p.map.resolution_m = map.get("resolution_m").as_positive();
  const std::vector<double> size = map.get("size_voxels").as_doubles(3);
  for (int i = 0; i < 3; ++i) {
    if (size[i] != std::floor(size[i])) map.get("size_voxels").fail("must be whole numbers");
    p.map.dims[i] = static_cast<int>(size[i]);
  }
  p.map.z_min_m = map.get("z_min_m").as_double();
  p.recenter_distance_m = map.get("recenter_distance_m").as_nonnegative();
  p.map.prob_hit = map.get("prob_hit").as_double();
  p.map.prob_miss = map.get("prob_miss").as_double();
  p.map.clamp_min = map.get("clamp_min").as_double();
  p.map.clamp_max = map.get("clamp_max").as_double();
  p.map.occupancy_threshold = map.get("occupancy_threshold").as_double();
  p.map.new_surface_shadow_m = map.get("new_surface_shadow_m").as_nonnegative();

  const auto self = cfg.get("self_filter");
  self.expect_keys({"enabled", "margin_m", "cell_m", "arm_pose_period_s"});
  p.self_filter = self.get("enabled").as_bool();
  p.self.margin_m = self.get("margin_m").as_nonnegative();
  p.self.cell_m = self.get("cell_m").as_positive();
  p.arm_pose_period_s = self.get("arm_pose_period_s").as_positive();

  const auto vg = cfg.get("voxel_grid");
  vg.expect_keys({"leaf_m"});
  p.voxel_grid_leaf_m = vg.get("leaf_m").as_nonnegative();
  const auto sor = cfg.get("outlier_removal");
  sor.expect_keys({"mean_k", "stddev_mul"});
  p.outlier_mean_k = sor.get("mean_k").as_int();
  p.outlier_stddev_mul = sor.get("stddev_mul").as_positive();

  const std::string problem = validate(p);
  if (!problem.empty()) throw LoadError(path, "", problem);
  return out;
}

}  // namespace porter::mapping::app
