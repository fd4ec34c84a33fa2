// The self-filter on simulated clouds of the robot carrying each shipped payload: the points on
// the robot and the payload go, the scene's points beyond the margin stay.
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "mapping_support.hpp"
#include "porter/core/kinematics.hpp"

namespace porter::mapping {
namespace {

using livox::sim::HitKind;
using livox::sim::Waypoint;

/// Exact distance from p_W to the robot's geometry at `config` (core's shapes, not the filter's
/// grids): the independent check.
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

std::vector<CollisionShape> room_with_post() {
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
          box("ceiling", {0, 0, h + t / 2}, {2 * hx + 2 * t, 2 * hy + 2 * t, t}),
          // A post 0.3 m beside the base: scene points close to, but beyond, the margin.
          box("post", {0.0, 0.65, 0.6}, {0.1, 0.1, 1.2})};
}

TEST(SelfFilter, RemovesTheRobotAndEachPayloadAndNoScenePointBeyondTheMargin) {
  const app::MapperConfig cfg = test::shipped_config();
  const double margin = cfg.mapper.self.margin_m;
  for (const std::string payload : {"t_bar", "long_bar", "arc"}) {
    const RobotModel robot = test::robot_with(payload);
    // The base turns in place while the arm moves: robot points sweep through the sensor frame.
    JointVector q2 = test::carry_arm();
    q2[0] += 0.6;
    q2[1] -= 0.2;
    test::SimDrive drive(robot, room_with_post(),
                         {Waypoint{0.0, test::config_at(0, 0, 0)}, Waypoint{1.0, test::config_at(0.1, 0, 0.4, q2)}},
                         cfg.mapper.T_B_S);
    ASSERT_TRUE(drive.lidar().ok()) << drive.lidar().error();
    Mapper mapper(robot, cfg.mapper);
    StateBuffer states;
    std::uint64_t self_hits = 0, self_removed = 0, scene_removed = 0, scene_beyond_removed = 0, scene_near = 0;
    double worst_removed_scene_m = -1.0;
    for (int k = 0; k < 10; ++k) {
      const test::SimCloud c = drive.next(states);
      FilteredCloud f;
      std::vector<std::uint8_t> removed;
      mapper.filter(c.cloud, states, f, &removed);
      ASSERT_EQ(removed.size(), c.rays.size());
      for (std::size_t i = 0; i < c.rays.size(); ++i) {
        const livox::sim::SimRay& r = c.rays[i];
        if (r.kind == HitKind::robot || r.kind == HitKind::payload) {
          ++self_hits;
          self_removed += removed[i];
          continue;
        }
        const double d = robot_distance(robot, drive.motion().at(r.t_s), r.hit_W.cast<double>());
        scene_near += d <= margin;
        if (!removed[i]) continue;
        ++scene_removed;
        worst_removed_scene_m = std::max(worst_removed_scene_m, d);
        // The arm is posed on a 5 ms grid: 2 mm of motion at most in this drive.
        scene_beyond_removed += d > margin + 0.002;
      }
    }
    const double fraction = static_cast<double>(self_removed) / static_cast<double>(self_hits);
    RecordProperty(payload + "_robot_payload_hits", static_cast<int>(self_hits));
    RecordProperty(payload + "_removed_fraction", std::to_string(fraction));
    RecordProperty(payload + "_scene_points_within_margin", static_cast<int>(scene_near));
    RecordProperty(payload + "_scene_points_removed", static_cast<int>(scene_removed));
    EXPECT_GT(self_hits, 5000u) << payload;
    EXPECT_GE(fraction, 0.999) << payload << ": " << self_removed << " of " << self_hits;
    EXPECT_EQ(scene_beyond_removed, 0u) << payload << ": worst " << worst_removed_scene_m << " m";
  }
}

TEST(SelfFilter, GridAnswersEqualTheExactDistanceTest) {
  const RobotModel robot = test::robot_with("t_bar");
  SelfFilterParams p;
  p.margin_m = 0.04;
  p.cell_m = 0.02;
  SelfFilter filter(robot, p);
  filter.set_arm(test::carry_arm());
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> ux(-0.6, 1.4), uy(-0.8, 0.8), uz(-0.1, 1.4);
  int inside = 0;
  for (int i = 0; i < 20000; ++i) {
    const Eigen::Vector3d p_B(ux(rng), uy(rng), uz(rng));
    const bool exact = robot_distance(robot, test::config_at(0, 0, 0), p_B) <= p.margin_m;
    ASSERT_EQ(filter.contains(p_B), exact) << p_B.transpose();
    inside += exact;
  }
  EXPECT_GT(inside, 300);
  EXPECT_GT(filter.boundary_cells(), 0);
}

}  // namespace
}  // namespace porter::mapping
