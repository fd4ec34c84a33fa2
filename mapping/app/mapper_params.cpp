#include "mapper_params.hpp"

#include <cmath>

#include "porter/core/load_error.hpp"
#include "porter/core/scene_loader.hpp"
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
  // Kept at ROBOT_STATE's 100 Hz: up to a minute.
  out.state_history_s = state.get("history_s").as_in(0.0, 60.0, "s", true);
  if (out.state_wait_s > 1.0) state.get("wait_s").fail("must be in [0, 1]");
  const auto queue = cfg.get("queue");
  queue.expect_keys({"max_clouds"});
  out.max_queued_clouds = queue.get("max_clouds").as_int();
  if (out.max_queued_clouds < 1 || out.max_queued_clouds > 100) queue.get("max_clouds").fail("must be in [1, 100]");
  out.status_log_period_s = cfg.get("status_log_period_s").as_in(0.1, 3600.0, "s");

  MapperParams& p = out.mapper;
  const auto sensor = cfg.get("sensor");
  sensor.expect_keys({"T_B_S"});
  p.T_B_S = sensor.get("T_B_S").as_pose();

  const auto range = cfg.get("range");
  range.expect_keys({"min_m", "max_m", "ground_height_m"});
  // Each ray is traced voxel by voxel up to max_m: 1 km bounds a ray at 1 cm voxels to 1e5
  // steps (the MID-360 reaches 70 m; the window, not this, usually ends a ray).
  p.min_range_m = range.get("min_m").as_in(0.0, 1000.0, "m");
  p.max_range_m = range.get("max_m").as_in(0.0, 1000.0, "m", true);
  p.ground_height_m = range.get("ground_height_m").as_in(-100.0, 100.0, "m");

  const auto map = cfg.get("map");
  map.expect_keys({"resolution_m", "size_voxels", "z_min_m", "recenter_distance_m", "prob_hit",
                   "prob_miss", "clamp_min", "clamp_max", "occupancy_threshold", "new_surface_shadow_m"});
  // The planner's range of resolutions (scene files: kSceneMinResolution_m .. kSceneMaxResolution_m).
  p.map.resolution_m = map.get("resolution_m").as_in(kSceneMinResolution_m, kSceneMaxResolution_m, "m");
  const std::vector<double> size = map.get("size_voxels").as_doubles(3);
  // The window is allocated whole (~4.5 B a voxel: log-odds and packed states): at most 2^28 voxels
  // (~1.2 GB; the shipped window is 1.0e7, 46 MB), each axis in [2, 16384].
  double voxels = 1.0;
  for (int i = 0; i < 3; ++i) {
    if (size[i] != std::floor(size[i]) || size[i] < 2.0 || size[i] > 16384.0) {
      map.get("size_voxels").fail("must be whole numbers in [2, 16384]");
    }
    p.map.dims[i] = static_cast<int>(size[i]);
    voxels *= size[i];
  }
  if (voxels > static_cast<double>(1 << 28)) {
    map.get("size_voxels").fail("a window of " + std::to_string(static_cast<long long>(voxels)) +
                                " voxels exceeds 268435456 (2^28, ~1.2 GB)");
  }
  p.map.z_min_m = map.get("z_min_m").as_in(-kSceneMaxMagnitude_m, kSceneMaxMagnitude_m, "m");
  p.recenter_distance_m = map.get("recenter_distance_m").as_in(0.0, 1000.0, "m");
  p.map.prob_hit = map.get("prob_hit").as_double();
  p.map.prob_miss = map.get("prob_miss").as_double();
  p.map.clamp_min = map.get("clamp_min").as_double();
  p.map.clamp_max = map.get("clamp_max").as_double();
  p.map.occupancy_threshold = map.get("occupancy_threshold").as_double();
  p.map.new_surface_shadow_m = map.get("new_surface_shadow_m").as_in(0.0, 5.0, "m");

  const auto self = cfg.get("self_filter");
  self.expect_keys({"enabled", "margin_m", "cell_m", "arm_pose_period_s"});
  p.self_filter = self.get("enabled").as_bool();
  // The per-link grids cover each link plus the margin at cell_m: a 1 m margin or a 1 mm cell
  // is already ~10^9 cells for the long bar; the arm is posed at most every 10 us.
  p.self.margin_m = self.get("margin_m").as_in(0.0, 1.0, "m");
  p.self.cell_m = self.get("cell_m").as_in(1e-3, 0.5, "m");
  p.arm_pose_period_s = self.get("arm_pose_period_s").as_in(1e-5, 1.0, "s");

  const auto vg = cfg.get("voxel_grid");
  vg.expect_keys({"leaf_m"});
  p.voxel_grid_leaf_m = vg.get("leaf_m").as_in(0.0, 10.0, "m");
  const auto sor = cfg.get("outlier_removal");
  sor.expect_keys({"mean_k", "stddev_mul"});
  p.outlier_mean_k = sor.get("mean_k").as_int();
  if (p.outlier_mean_k < 0 || p.outlier_mean_k > 1000) sor.get("mean_k").fail("must be in [0, 1000]");
  p.outlier_stddev_mul = sor.get("stddev_mul").as_in(0.0, 100.0, "", true);

  const std::string problem = validate(p);
  if (!problem.empty()) throw LoadError(path, "", problem);
  return out;
}

}  // namespace porter::mapping::app
