// The simulated MID-360: packet stream and timing, decoded points against the rays' truth,
// robot and payload hits, IMU, motion, noise, dropout, run-time obstacles.
#include <cmath>
#include <map>

#include <gtest/gtest.h>

#include "porter/core/kinematics.hpp"
#include "porter/livox/decoder.hpp"
#include "porter/livox_sim/scripted_motion.hpp"
#include "porter/livox_sim/simulated_mid360.hpp"
#include "sim_support.hpp"

namespace porter::livox::sim {
namespace {

using test::closed_room;
using test::shipped_params;
using test::start_configuration;

struct SimRun {
  std::vector<SimPacket> packets;
  std::vector<SimRay> rays;
};

/// Advances in uneven steps up to t_end.
SimRun run(SimulatedMid360& lidar, double t_start, double t_end) {
  SimRun r;
  static const double kSteps[] = {0.0013, 0.037, 0.0005, 0.01, 0.0211};
  double t = t_start;
  for (int i = 0; t < t_end; ++i) {
    const double next = std::min(t_end, t + kSteps[i % 5]);
    lidar.advance(t, next, r.packets, &r.rays);
    t = next;
  }
  return r;
}

TEST(SimulatedMid360, EachIntervalsPacketsOnceInTimeOrderWithTheProtocolsTiming) {
  const RobotModel robot = test::robot_with("t_bar");
  double step_lo = 0.0, step_hi = 0.0, asked_min = 1e9, asked_max = -1e9;
  bool asked_outside = false;
  SimulatedMid360 lidar(shipped_params(), robot, closed_room(4, 4, 3), [&](double t) {
    asked_min = std::min(asked_min, t);
    asked_max = std::max(asked_max, t);
    asked_outside = asked_outside || t <= step_lo || t > step_hi + 1e-12;
    return start_configuration();
  });
  ASSERT_TRUE(lidar.ok()) << lidar.error();
  std::vector<SimPacket> packets;
  std::vector<SimRay> rays;
  static const double kSteps[] = {0.0013, 0.037, 0.0005, 0.01, 0.0211};
  for (int i = 0; step_hi < 1.0; ++i) {
    step_lo = step_hi;
    step_hi = std::min(1.0, step_lo + kSteps[i % 5]);
    const std::size_t before = packets.size();
    lidar.advance(step_lo, step_hi, packets, &rays);
    for (std::size_t k = before; k < packets.size(); ++k) {
      EXPECT_GT(packets[k].time_s, step_lo);
      EXPECT_LE(packets[k].time_s, step_hi);
      if (k > before) {
        EXPECT_GE(packets[k].time_s, packets[k - 1].time_s);
      }
    }
  }
  EXPECT_FALSE(asked_outside) << "state asked at " << asked_min << ".." << asked_max;

  std::size_t n_points = 0, n_imu = 0, returns = 0;
  std::uint64_t last_ts = 0;
  DecodedPacket d;
  for (const SimPacket& p : packets) {
    ASSERT_EQ(decode_packet(p.bytes.data(), p.size, {}, d), DecodeStatus::ok);
    if (p.stream == SimPacket::Stream::imu) {
      EXPECT_TRUE(d.is_imu());
      EXPECT_EQ(d.header.udp_cnt, n_imu);
      ++n_imu;
      EXPECT_EQ(d.header.timestamp_ns, n_imu * 5'000'000ULL);  // 200 Hz, k = 1, 2, ...
      continue;
    }
    const std::uint64_t j = n_points++;
    EXPECT_EQ(p.size, 1380u);
    EXPECT_EQ(d.header.data_type, 1);
    EXPECT_EQ(d.header.time_type, 0);
    EXPECT_EQ(d.header.dot_num, 96);
    EXPECT_EQ(d.header.time_interval_100ns, 4750);  // 95 x 5 us
    EXPECT_EQ(d.header.timestamp_ns, j * 480000);   // 96 points at 200,000 points/s
    EXPECT_DOUBLE_EQ(p.time_s, (j * 96 + 95) / 200000.0);
    if (j > 0) {
      EXPECT_GT(d.header.timestamp_ns, last_ts);
    }
    last_ts = d.header.timestamp_ns;
    // udp_cnt restarts with each 10 Hz frame: 0.1 s / 0.48 ms = 208.33 packets per frame.
    const auto frame = static_cast<std::uint64_t>(std::floor(j * 96 / 20000.0));
    const std::uint64_t first_of_frame = (frame * 20000 + 95) / 96;
    EXPECT_EQ(d.header.udp_cnt, j - first_of_frame) << j;
    EXPECT_EQ(d.header.frame_cnt, frame % 256);
    for (std::size_t i = 0; i < d.num_points; ++i) returns += d.points[i].is_no_return() ? 0 : 1;
  }
  // (0, 1 s]: packets 0..2082 (the last point of packet 2082 is at 0.99999 s) and IMU 1..200.
  EXPECT_EQ(n_points, 2083u);
  EXPECT_EQ(n_imu, 200u);
  // A closed room returns every ray: 200,000 points/s.
  EXPECT_EQ(returns, 2083u * 96u);
  EXPECT_EQ(rays.size(), 2083u * 96u);
  EXPECT_EQ(lidar.stats().returns, 2083u * 96u);
}

TEST(SimulatedMid360, DecodedPointsAreTheRaysHitsInEveryDataType) {
  for (DataType type : {DataType::kCartesianHigh, DataType::kCartesianLow, DataType::kSpherical}) {
    Mid360SimParams params = shipped_params();
    params.data_type = type;
    params.imu_enabled = false;
    SimulatedMid360 lidar(params, test::robot_with("long_bar"), closed_room(3, 5, 2.5),
                          [](double) { return start_configuration(1.0, 0.5, 0.3); });
    const SimRun r = run(lidar, 0.0, 0.1);
    ASSERT_EQ(r.rays.size(), r.packets.size() * 96);
    const float tol = type == DataType::kCartesianLow ? 0.0087f : type == DataType::kSpherical ? 0.0015f : 0.00087f;
    DecodedPacket d;
    for (std::size_t k = 0; k < r.packets.size(); ++k) {
      ASSERT_EQ(decode_packet(r.packets[k].bytes.data(), r.packets[k].size, {}, d), DecodeStatus::ok);
      for (std::size_t i = 0; i < 96; ++i) {
        const SimRay& ray = r.rays[k * 96 + i];
        ASSERT_TRUE(ray.returned);
        const Eigen::Vector3f p(d.points[i].x_m, d.points[i].y_m, d.points[i].z_m);
        const float tol_r = type == DataType::kSpherical ? tol + 1.75e-4f * ray.point_S.norm() : tol;
        ASSERT_LT((p - ray.point_S).norm(), tol_r) << static_cast<int>(type);
        // The point, put in the world with the sensor pose, is the ray's hit.
        const Eigen::Vector3f p_W = (lidar.T_W_S(ray.t_s) * p.cast<double>()).cast<float>();
        ASSERT_LT((p_W - ray.hit_W).norm(), tol_r + 1e-4f);
      }
    }
  }
}

TEST(SimulatedMid360, RobotAndEachPayloadAppearInTheCloudOnTheirSurfaces) {
  for (const std::string payload : {"t_bar", "long_bar", "arc"}) {
    const RobotModel robot = test::robot_with(payload);
    // The scenes' start pose with the arm turned 0.8 rad to the left: at q1 = 0 the T bar
    // lies in the arm's plane right behind it, seen from the mast, and no ray reaches it.
    RobotConfiguration c = start_configuration();
    c.q_rad[0] = 0.8;
    SimulatedMid360 lidar(shipped_params(), robot, {}, [&](double) { return c; });
    const SimRun r = run(lidar, 0.0, 1.0);
    KinematicsWorkspace ws;
    forward_kinematics(robot, c, ws);
    std::map<HitKind, int> count;
    double worst = 0.0;
    for (const SimRay& ray : r.rays) {
      ++count[ray.kind];
      if (ray.kind != HitKind::robot && ray.kind != HitKind::payload) continue;
      EXPECT_TRUE(ray.returned);
      const Eigen::Vector3d p_L = ws.T_W_L[ray.index].inverse() * ray.hit_W.cast<double>();
      double off = 1e9;
      for (const auto& s : robot.links[ray.index].shapes) {
        const bool is_payload = s.name.rfind("payload '", 0) == 0;
        if (is_payload != (ray.kind == HitKind::payload)) continue;
        off = std::min(off, std::fabs(shape_signed_distance(s, p_L)));
      }
      worst = std::max(worst, off);
    }
    RecordProperty(payload + "_robot_hits", count[HitKind::robot]);
    RecordProperty(payload + "_payload_hits", count[HitKind::payload]);
    // The payload is in view of the mast-top sensor: thousands of its points every second.
    EXPECT_GT(count[HitKind::payload], 1000) << payload;
    EXPECT_GT(count[HitKind::robot], 100) << payload;
    EXPECT_GT(count[HitKind::ground], 10000) << payload;
    EXPECT_LT(worst, 0.0006) << payload;
  }
}

TEST(SimulatedMid360, ImuReadsGravityRotationAndAcceleration) {
  Mid360SimParams params = shipped_params();
  auto imu_of = [&](const StateFunction& state, double t_end) {
    SimulatedMid360 lidar(params, test::robot_with(""), {}, state);
    std::vector<SimPacket> packets;
    lidar.advance(0.0, t_end, packets);
    std::vector<ImuSample> out;
    DecodedPacket d;
    for (const SimPacket& p : packets) {
      if (p.stream != SimPacket::Stream::imu) continue;
      EXPECT_EQ(decode_packet(p.bytes.data(), p.size, {}, d), DecodeStatus::ok);
      out.push_back(d.imu);
    }
    return out;
  };
  // Level and still: +1 g on z, no rotation.
  for (const ImuSample& s : imu_of([](double) { return start_configuration(); }, 0.2)) {
    EXPECT_NEAR(s.accel_g[0], 0.0f, 1e-6f);
    EXPECT_NEAR(s.accel_g[2], 1.0f, 1e-6f);
    EXPECT_NEAR(s.gyro_radps[2], 0.0f, 1e-6f);
  }
  // Turning on the spot at 0.5 rad/s: the IMU, 0.2103 m from the axis, feels w^2 r inwards.
  const double w = 0.5;
  const auto turning = imu_of([&](double t) { return start_configuration(0, 0, w * t); }, 0.5);
  const Eigen::Vector3d p_B = params.T_B_S * params.p_S_imu_m;
  const double r = p_B.head<2>().norm();
  for (std::size_t k = 2; k < turning.size(); ++k) {
    const ImuSample& s = turning[k];
    EXPECT_NEAR(s.gyro_radps[2], w, 1e-5);
    const double a_xy = std::hypot(s.accel_g[0], s.accel_g[1]) * kStandardGravity_mps2;
    EXPECT_NEAR(a_xy, w * w * r, 2e-4);
    // Pointing from the IMU to the axis (the point frame is the base frame's axes here).
    const double dot = (s.accel_g[0] * -p_B.x() + s.accel_g[1] * -p_B.y()) * kStandardGravity_mps2;
    EXPECT_NEAR(dot, w * w * r * r, 1e-4);
  }
  // Speeding up along x at 0.5 m/s^2.
  const auto accelerating = imu_of([](double t) { return start_configuration(0.25 * t * t, 0, 0); }, 0.3);
  for (std::size_t k = 2; k < accelerating.size(); ++k) {
    EXPECT_NEAR(accelerating[k].accel_g[0] * kStandardGravity_mps2, 0.5, 1e-5);
    EXPECT_NEAR(accelerating[k].accel_g[2], 1.0, 1e-6);
  }
}

TEST(SimulatedMid360, PointsOfAMovingRobotAreTakenFromTheSensorPoseAtTheirOwnTime) {
  // Driving at 1 m/s while turning at 0.5 rad/s in a closed room.
  const ScriptedMotion motion({{0.0, start_configuration(-1.0, 0.0, 0.0)},
                               {1.0, start_configuration(0.0, 0.0, 0.5)}});
  const Mid360SimParams params = shipped_params();
  const auto room = closed_room(4, 4, 3);
  SimulatedMid360 lidar(params, test::robot_with("t_bar"), room,
                        [&](double t) { return motion.at(t); });
  const SimRun r = run(lidar, 0.0, 0.5);
  auto off_surface = [&](const Eigen::Vector3d& p_W) {
    double off = std::fabs(p_W.z());  // the ground
    for (const auto& s : room) off = std::min(off, std::fabs(shape_signed_distance(s, p_W)));
    return off;
  };
  int checked = 0, far_with_frame_pose = 0;
  double worst = 0.0;
  for (const SimRay& ray : r.rays) {
    if (ray.kind != HitKind::ground && ray.kind != HitKind::obstacle) continue;
    const Eigen::Isometry3d T_W_B = motion.at(ray.t_s).base.T_W_B();
    const Eigen::Vector3d p_W = T_W_B * params.T_B_S * ray.point_S.cast<double>();
    worst = std::max(worst, off_surface(p_W));
    // The same point put in the world with the pose at the start of its 0.1 s frame.
    const double frame_start = std::floor(ray.t_s * 10.0) / 10.0;
    const Eigen::Vector3d p_frame = motion.at(frame_start).base.T_W_B() * params.T_B_S * ray.point_S.cast<double>();
    if (off_surface(p_frame) > 0.01) ++far_with_frame_pose;
    ++checked;
  }
  EXPECT_GT(checked, 90000);
  EXPECT_LT(worst, 0.001);  // rounding to 1 mm, interpolation of the pose between samples
  // Without per-point times most points of a moving sensor land off the walls.
  EXPECT_GT(far_with_frame_pose, checked / 3);
}

TEST(SimulatedMid360, RangeNoiseAndDropoutFollowTheirParameters) {
  Mid360SimParams params = shipped_params();
  params.range_noise_stddev_m = 0.02;
  params.dropout_probability = 0.3;
  params.imu_enabled = false;
  SimulatedMid360 lidar(params, test::robot_with(""), closed_room(4, 4, 3),
                        [](double) { return start_configuration(); });
  const SimRun r = run(lidar, 0.0, 0.5);
  double sum = 0.0, sum2 = 0.0;
  int n = 0, dropped = 0;
  for (const SimRay& ray : r.rays) {
    ASSERT_TRUE(ray.kind != HitKind::none);
    if (!ray.returned) {
      ++dropped;
      continue;
    }
    const double err = ray.point_S.norm() - (ray.hit_W - ray.origin_W).norm();
    sum += err;
    sum2 += err * err;
    ++n;
  }
  const double fraction = static_cast<double>(dropped) / r.rays.size();
  EXPECT_NEAR(fraction, 0.3, 0.005);
  EXPECT_NEAR(sum / n, 0.0, 0.0005);
  EXPECT_NEAR(std::sqrt(sum2 / n), 0.02, 0.0005);
  // The same seed gives the same stream, byte for byte.
  SimulatedMid360 again(params, test::robot_with(""), closed_room(4, 4, 3),
                        [](double) { return start_configuration(); });
  const SimRun r2 = run(again, 0.0, 0.5);
  ASSERT_EQ(r2.packets.size(), r.packets.size());
  for (std::size_t k = 0; k < r.packets.size(); ++k) EXPECT_EQ(r.packets[k].bytes, r2.packets[k].bytes);
}

TEST(SimulatedMid360, ObstaclesAddedAndRemovedAtRunTimeAndSkippedIntervals) {
  Mid360SimParams params = shipped_params();
  params.scene.ground_plane = false;
  SimulatedMid360 lidar(params, test::robot_with(""), {}, [](double) { return start_configuration(); });
  auto count = [](const SimRun& r, HitKind k) {
    int c = 0;
    for (const SimRay& ray : r.rays) c += ray.kind == k ? 1 : 0;
    return c;
  };
  EXPECT_EQ(count(run(lidar, 0.0, 0.1), HitKind::obstacle), 0);
  // To the left: straight ahead the arm hides most of what lies behind it.
  lidar.set_obstacles({test::box("crate", {0.0, 2.0, 0.5}, {0.5, 0.5, 1.0})});
  const SimRun with = run(lidar, 0.1, 0.2);
  EXPECT_GT(count(with, HitKind::obstacle), 200);
  lidar.set_obstacles({});
  // (0.2, 0.5] is skipped: the next call produces only packets after 0.5 s.
  const SimRun after = run(lidar, 0.5, 0.6);
  EXPECT_EQ(count(after, HitKind::obstacle), 0);
  ASSERT_FALSE(after.rays.empty());
  EXPECT_GT(after.rays.front().t_s, 0.5 - 0.0005);
  // Point packets 1041..1249 end in (0.5, 0.6], IMU samples 101..120.
  EXPECT_EQ(after.packets.size(), 209u + 20u);
}

}  // namespace
}  // namespace porter::livox::sim
