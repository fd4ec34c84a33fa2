// The self-filter on a moving robot, through porter-mapper's node (queue, state wait, ROBOT_STATE
// conversion) with ROBOT_STATE as porter-state publishes it: the base pose at utime, the newest
// ARM_STATE sample's joint angles (older than utime by the arm's latency, stamped arm_utime),
// no joints at all until the first ARM_STATE, and a stall of porter-state under load. For each
// shipped payload the base drives and turns while the arm swings; the map the node builds must
// hold no occupied voxel that the scene (a closed room, exact geometry) does not explain, and the
// self-filter must remove >= 99.9 % of the points that hit the robot or its payload.
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include <gtest/gtest.h>

#include "mapper_node.hpp"
#include "mapping_support.hpp"
#include "porter/core/geometry.hpp"
#include "porter/core/kinematics.hpp"

namespace porter::mapping {
namespace {

using livox::sim::HitKind;
using livox::sim::Waypoint;

std::vector<CollisionShape> closed_room() {
  const double t = 0.2, hx = 4, hy = 4, h = 3;
  auto box = [](const std::string& name, Eigen::Vector3d c, Eigen::Vector3d size) {
    CollisionShape s;
    s.name = name;
    s.geometry = Box{size};
    s.T_parent_shape.translation() = c;
    return s;
  };
  return {box("wall +x", {hx + t / 2, 0, h / 2}, {t, 2 * hy + 2 * t, h}),
          box("wall -x", {-hx - t / 2, 0, h / 2}, {t, 2 * hy + 2 * t, h}),
          box("wall +y", {0, hy + t / 2, h / 2}, {2 * hx + 2 * t, t, h}),
          box("wall -y", {0, -hy - t / 2, h / 2}, {2 * hx + 2 * t, t, h}),
          box("ceiling", {0, 0, h + t / 2}, {2 * hx + 2 * t, 2 * hy + 2 * t, t})};
}

double robot_distance(const RobotModel& robot, const RobotConfiguration& config, const Eigen::Vector3d& p_W) {
  KinematicsWorkspace ws;
  forward_kinematics(robot, config, ws);
  double d = std::numeric_limits<double>::infinity();
  for (int l = 0; l < kNumLinks; ++l) {
    const Eigen::Vector3d p_L = ws.T_W_L[static_cast<std::size_t>(l)].inverse(Eigen::Isometry) * p_W;
    for (const CollisionShape& s : robot.links[static_cast<std::size_t>(l)].shapes) d = std::min(d, shape_signed_distance(s, p_L));
  }
  return d;
}

porter::point_cloud_t cloud_msg(const SensorCloud& c, std::int64_t scan_id) {
  porter::point_cloud_t m{};
  m.utime = c.utime;
  m.frame_id = "lidar";
  m.scan_id = scan_id;
  m.num_points = static_cast<std::int32_t>(c.size());
  m.x_m = c.x_m;
  m.y_m = c.y_m;
  m.z_m = c.z_m;
  m.intensity.assign(c.size(), 100.0f);
  m.time_offset_ns = c.time_offset_ns;
  m.line.assign(c.size(), 0);
  m.tag.assign(c.size(), 0);
  return m;
}

// What porter-state publishes at `t_s` (simulated seconds): the base at t (odometry), the newest
// arm sample that has reached it, or no joints before the first one.
struct StateStream {
  double arm_period_s = 0.005;   // ARM_STATE rate 200 Hz
  double arm_latency_s = 0.03;   // sample instant to porter-state: CAN, porter-arm, LCM, its loop
  double arm_first_s = 0.35;     // the first ARM_STATE reaches porter-state then
  porter::robot_state_t at(double t_s, const livox::sim::ScriptedMotion& motion) const {
    porter::robot_state_t m{};
    m.utime = test::SimDrive::kEpochUs + std::llround(t_s * 1e6);
    m.frame_id = "world";
    const RobotConfiguration c = motion.at(t_s);
    m.x_m = c.base.x_m;
    m.y_m = c.base.y_m;
    m.yaw_rad = c.base.yaw_rad;
    m.base_utime = m.pose_utime = m.utime;
    m.pose_source = porter::robot_state_t::POSE_WHEEL_ODOM;
    m.base_valid = m.pose_valid = true;
    if (t_s >= arm_first_s) {
      // The newest sample k * period with k * period + latency <= t.
      const double t_arm = std::floor((t_s - arm_latency_s) / arm_period_s + 1e-9) * arm_period_s;
      const RobotConfiguration a = motion.at(t_arm);
      m.num_joints = kNumArmJoints;
      m.q_rad.assign(a.q_rad.data(), a.q_rad.data() + kNumArmJoints);
      m.qd_radps.assign(kNumArmJoints, 0.0);
      m.arm_utime = test::SimDrive::kEpochUs + std::llround(t_arm * 1e6);
      m.arm_valid = true;
    }
    return m;
  }
};

TEST(MovingSelfFilter, NoPhantomOfTheRobotOrPayloadInTheMapWhileDrivingAndSwingingTheArm) {
  app::MapperConfig cfg = test::shipped_config();
  cfg.mapper.map.dims = {200, 200, 48};
  cfg.mapper.max_range_m = 4.5;
  cfg.publish_rate_hz = 10.0;
  const double margin = cfg.mapper.self.margin_m;
  const std::vector<CollisionShape> room = closed_room();
  for (const std::string payload : {"t_bar", "long_bar", "arc"}) {
    SCOPED_TRACE(payload);
    const RobotModel robot = test::robot_with(payload);
    // Base: 0.8 m/s ahead, then turning; the arm swings its base joint and shoulder (1.25 and
    // 0.4 rad/s) the whole time.
    std::vector<Waypoint> script;
    for (int k = 0; k <= 6; ++k) {
      JointVector q = test::carry_arm();
      q[0] += (k % 2 == 0 ? 0.25 : -0.25) * (k == 0 ? 0.0 : 1.0);
      q[1] += (k % 2 == 0 ? 0.08 : -0.08) * (k == 0 ? 0.0 : 1.0);
      const double t = 0.4 * k;
      script.push_back(Waypoint{t, test::config_at(-1.0 + 0.8 * std::min(t, 1.6) + 0.3 * std::max(0.0, t - 1.6),
                                                   0.2 * std::max(0.0, t - 1.2), 0.5 * std::max(0.0, t - 1.2), q)});
    }
    test::SimDrive drive(robot, room, script, cfg.mapper.T_B_S);
    ASSERT_TRUE(drive.lidar().ok()) << drive.lidar().error();
    const StateStream stream;
    app::MapperNode node(cfg, robot);

    // Events on the simulated clock: ROBOT_STATE every 10 ms (held back during a stall of
    // porter-state from 1.0 to 1.15 s, then all at once), each cloud 10 ms after its last point.
    const int kClouds = 24;
    StateBuffer unused;
    std::vector<test::SimCloud> clouds;
    for (int k = 0; k < kClouds; ++k) clouds.push_back(drive.next(unused));
    std::multimap<std::int64_t, std::pair<int, int>> events;  // time ns -> (0 state index | 1 cloud index)
    for (int i = 0; i <= 100 * (kClouds / 10 + 1); ++i) {
      const double t = 0.01 * i;
      const double rx = t >= 1.0 && t < 1.15 ? 1.15 : t;
      events.emplace(std::llround((rx + 0.001) * 1e9), std::make_pair(0, i));
    }
    for (int k = 0; k < kClouds; ++k) {
      const auto& off = clouds[static_cast<std::size_t>(k)].cloud.time_offset_ns;
      const std::int64_t end_ns = (clouds[static_cast<std::size_t>(k)].cloud.utime - test::SimDrive::kEpochUs) * 1000 +
                                  *std::max_element(off.begin(), off.end());
      events.emplace(end_ns + 10'000'000, std::make_pair(1, k));
    }

    std::uint64_t self_hits = 0, removed = 0, scene_near = 0, processed_hits_clouds = 0;
    std::int64_t phantoms_max = 0;
    Eigen::Vector3d worst_phantom = Eigen::Vector3d::Zero();
    std::map<std::int64_t, int> by_scan;  // scan_id -> cloud index
    auto check_map = [&] {
      const RollingMap& map = node.mapper().map();
      const double res = map.resolution_m();
      std::int64_t phantoms = 0;
      map.for_each_known([&](const Eigen::Vector3i& key, float v) {
        if (!map.occupied(v)) return;
        const Eigen::Vector3d c(map.key_to_coord(key.x()), map.key_to_coord(key.y()), map.key_to_coord(key.z()));
        double d = std::numeric_limits<double>::infinity();
        for (const CollisionShape& o : room) d = std::min(d, shape_signed_distance(o, c));
        // An endpoint on a wall lies in a voxel whose centre is within a half diagonal of it.
        if (d > 0.5 * std::sqrt(3.0) * res + 1e-6) {
          ++phantoms;
          worst_phantom = c;
        }
      });
      phantoms_max = std::max(phantoms_max, phantoms);
    };
    app::StepResult r;
    auto drain = [&](std::int64_t now_ns) {
      while (node.step(now_ns, 0, r)) {
        const test::SimCloud& c = clouds[static_cast<std::size_t>(by_scan.at(r.scan_id))];
        std::uint64_t hits = 0;
        for (const livox::sim::SimRay& ray : c.rays) {
          if (ray.kind == HitKind::robot || ray.kind == HitKind::payload) {
            ++hits;
          } else {
            // Scene points the filter may rightly remove (within the margin of the robot at the
            // point's time, + 2 mm of arm motion within the 5 ms pose grid); the robot with its
            // payload stays within 2 m of the base's origin.
            const RobotConfiguration at = drive.motion().at(ray.t_s);
            if ((ray.hit_W.cast<double>().head<2>() - Eigen::Vector2d(at.base.x_m, at.base.y_m)).norm() > 2.0) continue;
            scene_near += robot_distance(robot, at, ray.hit_W.cast<double>()) <= margin + 0.002;
          }
        }
        self_hits += hits;
        removed += r.report.filter.self;
        processed_hits_clouds += hits > 0;
        check_map();
      }
    };
    for (const auto& [t_ns, ev] : events) {
      if (ev.first == 0) {
        node.on_state(stream.at(0.01 * ev.second, drive.motion()));
      } else {
        by_scan[ev.second + 1] = ev.second;
        node.on_cloud(cloud_msg(clouds[static_cast<std::size_t>(ev.second)].cloud, ev.second + 1), t_ns);
      }
      drain(t_ns);
    }
    drain(std::numeric_limits<std::int64_t>::max() / 2);
    const app::MapperCounters k = node.counters();
    // The clouds that begin before the first ARM_STATE sample cannot be filtered and are
    // dropped (counted); every other cloud is integrated.
    RecordProperty(payload + "_clouds_processed", static_cast<int>(k.clouds_processed));
    RecordProperty(payload + "_self_hits", static_cast<int>(self_hits));
    RecordProperty(payload + "_removed_at_least", static_cast<int>(removed - std::min(removed, scene_near)));
    RecordProperty(payload + "_phantom_voxels_max", static_cast<int>(phantoms_max));
    EXPECT_GE(k.clouds_processed, static_cast<std::uint64_t>(kClouds - 4));
    EXPECT_EQ(k.clouds_processed + k.dropped_queue_full + k.dropped_no_state, static_cast<std::uint64_t>(kClouds));
    EXPECT_EQ(k.dropped_queue_full, 0u);
    EXPECT_GT(self_hits, 10000u);
    // Removed points that are not the robot's are scene points within the margin (at most
    // scene_near of them): the robot's removed points are at least removed - scene_near.
    const double fraction = static_cast<double>(removed - std::min(removed, scene_near)) / static_cast<double>(self_hits);
    EXPECT_GE(fraction, 0.999) << removed << " removed, " << scene_near << " scene points within the margin, of "
                               << self_hits << " robot and payload hits";
    EXPECT_EQ(phantoms_max, 0) << "an occupied voxel no scene obstacle explains, e.g. at " << worst_phantom.transpose();
  }
}

}  // namespace
}  // namespace porter::mapping
