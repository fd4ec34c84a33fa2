#pragma once
// Shared pieces of the mapper tests and benchmark: the shipped robot and mapper config, and a
// simulated drive (the simulated MID-360 on a scripted robot) that yields 10 Hz clouds as
// porter-lidar publishes them (sensor frame, per-point time offsets) with the ROBOT_STATE
// samples (100 Hz) that cover them.

#include <cmath>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include <octomap/OcTree.h>

#include "mapper_params.hpp"
#include "porter/core/payload.hpp"
#include "porter/core/payload_loader.hpp"
#include "porter/core/robot_loader.hpp"
#include "porter/core/scene.hpp"
#include "porter/core/scene_loader.hpp"
#include "porter/livox_sim/scripted_motion.hpp"
#include "porter/livox_sim/simulated_mid360.hpp"
#include "porter/mapping/mapper.hpp"

namespace porter::mapping::test {

inline std::string source_dir() {
  const char* env = std::getenv("PORTER_SOURCE_DIR");
  return env ? env : PORTER_SOURCE_DIR;
}
inline std::string config_path(const std::string& rel) { return source_dir() + "/config/" + rel; }

/// The shipped robot carrying config/payloads/<payload>.yaml ("" = none).
inline RobotModel robot_with(const std::string& payload) {
  RobotModel robot = load_robot_model(config_path("robots/scout_mini_piper/robot.yaml"));
  if (!payload.empty()) robot = attach_payload(robot, load_payload(config_path("payloads/" + payload + ".yaml")));
  return robot;
}

/// config/mapping/porter_mapper.yaml as shipped.
inline app::MapperConfig shipped_config() { return app::load_mapper_config(config_path("mapping/porter_mapper.yaml")); }

/// The arm pose of the shipped scenes' start.
inline JointVector carry_arm() {
  JointVector q;
  q << 0.0, 0.6, -0.9, 0.0, 0.5, 0.0;
  return q;
}

inline RobotConfiguration config_at(double x, double y, double yaw, const JointVector& q = carry_arm()) {
  RobotConfiguration c;
  c.base = {x, y, yaw};
  c.q_rad = q;
  return c;
}

/// One 10 Hz cloud and what each of its points really hit.
struct SimCloud {
  SensorCloud cloud;
  std::vector<livox::sim::SimRay> rays;  ///< rays[i] is cloud point i
};

/// The simulated MID-360 (mounted as shipped) on a robot following `motion`.
class SimDrive {
 public:
  static constexpr std::int64_t kEpochUs = 1'700'000'000'000'000;  ///< utime of simulated t = 0

  SimDrive(const RobotModel& robot, const std::vector<CollisionShape>& obstacles,
           std::vector<livox::sim::Waypoint> waypoints, const Eigen::Isometry3d& T_B_S,
           double noise_m = 0.0, double dropout = 0.0)
      : motion_(std::move(waypoints)) {
    livox::sim::Mid360SimParams p;
    p.T_B_S = T_B_S;
    p.range_noise_stddev_m = noise_m;
    p.dropout_probability = dropout;
    p.imu_enabled = false;
    lidar_ = std::make_unique<livox::sim::SimulatedMid360>(p, robot, obstacles,
                                                           [this](double t) { return motion_.at(t); });
  }

  livox::sim::SimulatedMid360& lidar() { return *lidar_; }
  const livox::sim::ScriptedMotion& motion() const { return motion_; }

  /// The next 100 ms cloud (returns only, as porter-lidar publishes) and, into `states`, the
  /// 100 Hz state samples up to 10 ms after its last point.
  SimCloud next(StateBuffer& states, std::vector<std::pair<std::int64_t, RobotConfiguration>>* state_log = nullptr) {
    const double t0 = k_ * 0.1, t1 = (k_ + 1) * 0.1;
    ++k_;
    packets_.clear();
    rays_.clear();
    lidar_->advance(t0, t1, packets_, &rays_);
    SimCloud out;
    // A packet sent just after t0 holds points from just before it: the cloud starts at its
    // first point, as porter-lidar stamps it.
    double t_first = t1;
    for (const livox::sim::SimRay& r : rays_) t_first = std::min(t_first, r.t_s);
    const std::int64_t first_us = static_cast<std::int64_t>(std::floor(t_first * 1e6));
    out.cloud.utime = kEpochUs + first_us;
    for (const livox::sim::SimRay& r : rays_) {
      if (!r.returned) continue;
      out.cloud.x_m.push_back(r.point_S.x());
      out.cloud.y_m.push_back(r.point_S.y());
      out.cloud.z_m.push_back(r.point_S.z());
      out.cloud.time_offset_ns.push_back(static_cast<std::int32_t>(std::llround((r.t_s - first_us * 1e-6) * 1e9)));
      out.rays.push_back(r);
    }
    for (; state_k_ * 0.01 <= t1 + 0.0100001; ++state_k_) {
      const double t = state_k_ * 0.01;
      const std::int64_t t_us = kEpochUs + static_cast<std::int64_t>(std::llround(t * 1e6));
      states.add(t_us, motion_.at(t));
      if (state_log) state_log->emplace_back(t_us, motion_.at(t));
    }
    return out;
  }

 private:
  livox::sim::ScriptedMotion motion_;
  std::unique_ptr<livox::sim::SimulatedMid360> lidar_;
  std::vector<livox::sim::SimPacket> packets_;
  std::vector<livox::sim::SimRay> rays_;
  int k_ = 0;
  int state_k_ = 0;
};

/// A lane of the forest along +x from x = 0 to x_end at which every obstacle's footprint stays
/// at least `clearance` from the base's path.
inline double clear_lane(const Scene& scene, double x_end, double clearance) {
  for (double y = 0.0; std::abs(y) < 3.5; y = y > 0.0 ? -y : 0.1 - y) {
    bool ok = true;
    for (double x = 0.0; x <= x_end && ok; x += 0.05) {
      for (const CollisionShape& o : scene.obstacles) ok = ok && footprint_distance(o, {x, y}) >= clearance;
    }
    if (ok) return y;
  }
  return std::nan("");
}

/// Stock OctoMap: insertPointCloud of a filtered cloud (the reference the mapper is held to).
inline void stock_insert(octomap::OcTree& tree, const FilteredCloud& f, double max_range_m, bool discretize = false) {
  octomap::Pointcloud pc;
  pc.reserve(f.points_W.size());
  for (const Eigen::Vector3f& p : f.points_W) pc.push_back(p.x(), p.y(), p.z());
  tree.insertPointCloud(pc, octomap::point3d(f.origin_W.x(), f.origin_W.y(), f.origin_W.z()), max_range_m, false,
                        discretize);
}

}  // namespace porter::mapping::test
