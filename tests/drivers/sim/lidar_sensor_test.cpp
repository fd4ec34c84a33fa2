// The simulated MID-360 as a sensor of the simulated world (porter/sim/lidar_sensor.hpp), stepped
// by the Simulator as porter-sim steps it (1 ms): packets at the real rate, rays from the pose of
// the moving base, hits on the robot and payload where the world's joint angles put them, and
// obstacles added and removed at run time seen from the next step on. Packets are decoded with
// the driver's decoder and their points taken to the world frame with the sensor's pose at each
// point's time.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "porter/core/payload.hpp"
#include "porter/core/payload_loader.hpp"
#include "porter/core/robot_loader.hpp"
#include "porter/core/scene_loader.hpp"
#include "porter/livox/decoder.hpp"
#include "porter/sim/lidar_sensor.hpp"
#include "porter/sim/simulator.hpp"

namespace porter::sim {
namespace {

const std::string kConfig = std::string(PORTER_SOURCE_DIR) + "/config/";

World empty_world() {
  Scene scene = load_scene(kConfig + "scenes/empty.yaml");
  RobotModel robot = attach_payload(load_robot_model(kConfig + "robots/scout_mini_piper/robot.yaml"),
                                    load_payload(scene.payload_file));
  return World(std::move(scene), std::move(robot));
}

/// The shipped mount: the point frame 0.2875 m above the mast link (-0.22, 0, 0.245).
livox::sim::Mid360SimParams shipped_params() {
  livox::sim::Mid360SimParams p;
  p.T_B_S.translation() = Eigen::Vector3d(-0.22, 0.0, 0.245 + 0.2875);
  return p;
}

struct WorldPoint {
  double t_s;
  Eigen::Vector3d p_W;
};

/// A Simulator hosting only the LiDAR, with the base and joints set by the test.
struct Rig {
  Rig() : sim(empty_world()) {
    base = sim.world().scene().start.base;
    q = sim.world().scene().start.q_rad;
    // The arm turned to the left: at q1 = 0 the T bar lies in the arm's plane right behind it,
    // seen from the mast, and no ray reaches it.
    q[0] = 0.8;
    sim.set_base_source(std::make_unique<FunctionBaseSource>([this] {
      BaseTruth b;
      b.pose_W = base;
      return b;
    }));
    sim.set_joint_source(std::make_unique<FunctionJointSource>([this] {
      JointTruth j;
      j.q_rad = q;
      return j;
    }));
    auto sensor = std::make_unique<LidarSensor>(
        shipped_params(), sim.world(), [this](const std::vector<livox::sim::SimPacket>& p) {
          on_packets(p);
        });
    lidar = sensor.get();
    EXPECT_TRUE(lidar->ok()) << lidar->error();
    sim.add_sensor(std::move(sensor));
  }

  void on_packets(const std::vector<livox::sim::SimPacket>& packets) {
    for (const livox::sim::SimPacket& p : packets) {
      EXPECT_GE(p.time_s, last_packet_s);
      last_packet_s = p.time_s;
      livox::DecodedPacket d;
      ASSERT_EQ(livox::decode_packet(p.bytes.data(), p.size, {}, d), livox::DecodeStatus::ok);
      if (d.is_imu()) {
        ++imu_packets;
        continue;
      }
      ++point_packets;
      for (std::size_t i = 0; i < d.num_points; ++i) {
        if (d.points[i].is_no_return()) continue;
        // Sensor time is time since the simulation's start (time_type no_sync).
        const double t = static_cast<double>(d.header.timestamp_ns + d.sample_offset_ns(i)) * 1e-9;
        const Eigen::Vector3d p_S(d.points[i].x_m, d.points[i].y_m, d.points[i].z_m);
        points.push_back({t, lidar->lidar().T_W_S(t) * p_S});
      }
    }
  }

  /// Points above the ground (the empty scene has nothing else but the robot and payload).
  std::vector<WorldPoint> above_ground(double z_min_m = 0.03) const {
    std::vector<WorldPoint> out;
    for (const WorldPoint& w : points) {
      if (w.p_W.z() > z_min_m) out.push_back(w);
    }
    return out;
  }

  void run(double seconds) {
    const double end = sim.time_s() + seconds;
    while (sim.time_s() < end - 1e-9) sim.step_to(sim.time_s() + 0.001);
  }

  Simulator sim;
  BasePose base;
  JointVector q;
  LidarSensor* lidar = nullptr;
  std::vector<WorldPoint> points;
  long point_packets = 0, imu_packets = 0;
  double last_packet_s = 0.0;
};

Eigen::Vector3d centroid(const std::vector<WorldPoint>& pts) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const WorldPoint& w : pts) c += w.p_W;
  return pts.empty() ? c : Eigen::Vector3d(c / static_cast<double>(pts.size()));
}

TEST(LidarSensor, SendsPacketsAtTheRealRateAndSeesTheRobotAndItsPayload) {
  Rig rig;
  rig.run(1.0);
  // 200,000 points/s in packets of 96; IMU at 200 Hz.
  EXPECT_NEAR(static_cast<double>(rig.lidar->stats().rays), 200000.0, 96.0);
  EXPECT_NEAR(rig.point_packets, 200000 / 96, 1);
  EXPECT_NEAR(rig.imu_packets, 200, 1);
  const auto& hits = rig.lidar->stats().hits_by_kind;
  EXPECT_GT(hits[static_cast<int>(livox::sim::HitKind::payload)], 1000u);
  EXPECT_GT(hits[static_cast<int>(livox::sim::HitKind::robot)], 0u);
  EXPECT_EQ(hits[static_cast<int>(livox::sim::HitKind::obstacle)], 0u);
  // Everything above the ground lies on the robot or its payload, within reach of the base.
  const std::vector<WorldPoint> self = rig.above_ground();
  ASSERT_GT(self.size(), 1000u);
  for (const WorldPoint& w : self) {
    ASSERT_LT(std::hypot(w.p_W.x(), w.p_W.y()), 2.0) << w.p_W.transpose();
    ASSERT_LT(w.p_W.z(), 2.5) << w.p_W.transpose();
  }
}

/// Points above the ground more than 0.35 m left (y > 0) and right of the base's centre line:
/// the base is 0.58 m wide, so these are points on the arm and payload reaching out.
std::pair<long, long> left_right(const std::vector<WorldPoint>& pts) {
  long left = 0, right = 0;
  for (const WorldPoint& w : pts) {
    if (w.p_W.y() > 0.35) ++left;
    if (w.p_W.y() < -0.35) ++right;
  }
  return {left, right};
}

TEST(LidarSensor, TheArmAndPayloadAreSeenWhereTheWorldsJointAnglesPutThem) {
  Rig rig;
  rig.run(0.5);
  const Eigen::Vector3d before = centroid(rig.above_ground());
  const auto [left0, right0] = left_right(rig.above_ground());
  const std::uint64_t payload_hits =
      rig.lidar->stats().hits_by_kind[static_cast<int>(livox::sim::HitKind::payload)];
  rig.points.clear();
  rig.run(0.5);
  const Eigen::Vector3d again = centroid(rig.above_ground());
  EXPECT_LT((again - before).norm(), 0.01) << "a still robot looks the same from frame to frame";
  // The arm turns about its first joint from the left to the right: the payload's points swing
  // with it.
  rig.q[0] = -0.8;
  rig.run(0.05);  // the frame in progress still holds points of the old pose
  rig.points.clear();
  rig.run(0.5);
  const auto [left1, right1] = left_right(rig.above_ground());
  EXPECT_GT(left0, 200);
  EXPECT_LT(right0, left0 / 10) << "turned left";
  EXPECT_GT(right1, 200);
  EXPECT_LT(left1, right1 / 10) << "turned right";
  EXPECT_GT(rig.lidar->stats().hits_by_kind[static_cast<int>(livox::sim::HitKind::payload)],
            payload_hits + 500);
}

TEST(LidarSensor, RaysStartFromThePoseOfTheMovingBase) {
  Rig rig;
  for (int k = 0; k < 300; ++k) {
    rig.base.x_m += 0.001;     // 1 m/s
    rig.base.yaw_rad += 0.002; // 2 rad/s
    rig.run(0.001);
    const double t = rig.sim.time_s();
    const Eigen::Isometry3d expected = rig.sim.world().robot_at(t).config.base.T_W_B() *
                                       rig.lidar->lidar().params().T_B_S;
    ASSERT_LT((rig.lidar->lidar().T_W_S(t).matrix() - expected.matrix()).norm(), 1e-9) << t;
  }
  // Ground points stay on the ground whatever the motion (each ray posed at its own time).
  for (const WorldPoint& w : rig.points) {
    if (std::hypot(w.p_W.x() - rig.base.x_m, w.p_W.y() - rig.base.y_m) > 3.0) {
      ASSERT_NEAR(w.p_W.z(), 0.0, 2e-3) << w.t_s;
    }
  }
}

TEST(LidarSensor, ObstaclesAddedAndRemovedAtRunTimeAreSeen) {
  Rig rig;
  rig.run(0.2);
  // Behind the robot (the arm and payload hide much of the view ahead).
  const Eigen::Vector3d center(-3.0, 0.0, 0.5), size(0.5, 2.0, 1.0);
  auto in_box = [&](const std::vector<WorldPoint>& pts) {
    long n = 0;
    for (const WorldPoint& w : pts) {
      const Eigen::Vector3d d = (w.p_W - center).cwiseAbs();
      if ((d.array() <= 0.5 * size.array() + 0.01).all() && w.p_W.z() > 0.03) ++n;
    }
    return n;
  };
  EXPECT_EQ(in_box(rig.points), 0);
  SimCommand add;
  add.kind = SimCommand::Kind::add_box;
  add.target = "crate";
  add.center_W = center;
  add.size_m = size;
  ASSERT_TRUE(rig.sim.apply(add).ok);
  rig.points.clear();
  rig.run(0.2);
  EXPECT_EQ(rig.lidar->rebuilds(), 1u);
  EXPECT_GT(in_box(rig.points), 200);
  EXPECT_GT(rig.lidar->stats().hits_by_kind[static_cast<int>(livox::sim::HitKind::obstacle)], 200u);
  SimCommand remove;
  remove.kind = SimCommand::Kind::remove_obstacle;
  remove.target = "crate";
  ASSERT_TRUE(rig.sim.apply(remove).ok);
  rig.points.clear();
  rig.run(0.2);
  EXPECT_EQ(rig.lidar->rebuilds(), 2u);
  EXPECT_EQ(in_box(rig.points), 0);
}

}  // namespace
}  // namespace porter::sim
