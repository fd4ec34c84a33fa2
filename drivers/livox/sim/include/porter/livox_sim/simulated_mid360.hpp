#pragma once
// A simulated Livox MID-360 on the moving robot: casts its scan pattern (scan_pattern.hpp)
// against the world's obstacles, the ground and the robot's own links and payload
// (ray_scene.hpp), each ray from the sensor's pose at that ray's time, and produces the real
// UDP datagrams the sensor would send (point packets of 96 points, IMU packets), byte for byte
// in the layout porter-lidar decodes (porter/livox/packet.hpp).
//
//   SimulatedMid360 lidar(params, robot_with_payload, scene.obstacles,
//                         [&](double t) { return world.configuration_at(t); });
//   std::vector<SimPacket> packets;
//   lidar.advance(t0, t1, packets);   // every packet whose send time lies in (t0, t1]
//
// Time: simulated seconds. Point n (all lines together) is measured at n / point_rate_hz; a
// point packet is sent at the time of its last point, an IMU packet at its sample time. The
// packet timestamps are the sensor's clock: sensor_time_at_zero_ns + t (time since power-on
// for time_type 0, a PTP/GPS epoch time otherwise).
//
// Motion: the state function is called only for times in (t0, t1] of the current advance()
// (on the grid of state_sample_period_s and at the end of each internal 10 ms sub-step; a long
// advance() is worked through in such sub-steps), and the samples are kept for 50 ms; a ray's sensor
// pose is interpolated at its own time, the robot's links are posed at the middle of each
// packet (a packet spans 0.475 ms: at 1 m/s the payload moves 0.24 mm within it). The IMU
// (gyro and specific force at the IMU's position, in the point frame's axes) differentiates
// the sampled sensor motion with backward differences over three sample periods.
//
// Measurement model: ranges below min_range_m (the housing and blind zone) or beyond
// max_range_m give no return (the point is sent as x = y = z = 0, as the sensor does); optional
// Gaussian range noise and independent per-point dropout; reflectivity from the kind of
// surface hit and the incidence angle. Random draws come from a generator seeded by
// params.seed, so a run is repeatable.
//
// Failure: ok() is false when Embree failed (error() says why); advance() then produces
// packets without returns. Nothing throws after construction.
// Thread-safety: one thread drives an instance.

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "porter/core/geometry.hpp"
#include "porter/core/kinematics.hpp"
#include "porter/core/robot_model.hpp"
#include "porter/livox/packet.hpp"
#include "porter/livox_sim/ray_scene.hpp"
#include "porter/livox_sim/scan_pattern.hpp"
#include "porter/livox_sim/state_history.hpp"

namespace porter::livox::sim {

struct Mid360SimParams {
  ScanPatternParams pattern;              ///< 200,000 points/s, 360 x (-7..52) deg
  double frame_rate_hz = 10.0;            ///< udp_cnt restarts and frame_cnt counts per frame
  double min_range_m = 0.1;               ///< the MID-360's blind zone
  double max_range_m = 40.0;              ///< 40 m at 10 % reflectivity (spec)
  double range_noise_stddev_m = 0.0;      ///< Gaussian range noise, 1 sigma (spec: 0.02 m)
  double dropout_probability = 0.0;       ///< per point, in [0, 1]
  DataType data_type = DataType::kCartesianHigh;
  TimeType time_type = TimeType::kNoSync;
  std::int64_t sensor_time_at_zero_ns = 0;  ///< sensor clock at simulated time 0
  bool imu_enabled = true;
  double imu_rate_hz = 200.0;
  double gyro_noise_stddev_radps = 0.0;
  double accel_noise_stddev_mps2 = 0.0;
  /// IMU position in the point frame (its axes are the point frame's). The published figure is
  /// (11.0, 23.29, -44.12) mm.
  Eigen::Vector3d p_S_imu_m{0.011, 0.02329, -0.04412};
  /// The sensor's point frame S in the base frame B.
  Eigen::Isometry3d T_B_S = Eigen::Isometry3d::Identity();
  RaySceneParams scene;                   ///< ground plane, tessellation
  double state_sample_period_s = 0.001;   ///< how often the state function is sampled (> 0)
  std::uint64_t seed = 1;
};

/// One datagram and when the sensor sends it.
struct SimPacket {
  enum class Stream : std::uint8_t { points, imu };
  double time_s = 0.0;
  Stream stream = Stream::points;
  std::uint16_t size = 0;
  std::array<std::uint8_t, kMaxPacketSize> bytes{};
};

/// What one ray really hit (for tests and the self-filter's ground truth).
struct SimRay {
  double t_s = 0.0;                  ///< time of the point
  std::uint64_t point_index = 0;     ///< n of the scan pattern
  Eigen::Vector3f origin_W = Eigen::Vector3f::Zero();
  Eigen::Vector3f hit_W = Eigen::Vector3f::Zero();  ///< noiseless hit point (origin when none)
  Eigen::Vector3f point_S = Eigen::Vector3f::Zero();  ///< what was sent (before rounding); 0 = no return
  HitKind kind = HitKind::none;      ///< what the ray hit, whether or not the point was dropped
  std::int16_t index = -1;           ///< obstacle index or planning link (see RayHit)
  bool returned = false;             ///< the point carries a return
};

/// The robot's configuration at simulated time t, s.
using StateFunction = std::function<RobotConfiguration(double t_s)>;

struct SimStats {
  std::uint64_t point_packets = 0;
  std::uint64_t imu_packets = 0;
  std::uint64_t rays = 0;
  std::uint64_t returns = 0;
  std::array<std::uint64_t, 5> hits_by_kind{};  ///< indexed by HitKind
};

class SimulatedMid360 {
 public:
  /// `robot` may carry an attached payload (attach_payload); `obstacles_W` are the world's.
  SimulatedMid360(const Mid360SimParams& params, const RobotModel& robot,
                  const std::vector<CollisionShape>& obstacles_W, StateFunction state);

  /// Replaces the world's obstacles (rebuilds the world's ray-casting scene).
  void set_obstacles(const std::vector<CollisionShape>& obstacles_W);
  /// Replaces the robot (e.g. a payload attached or released).
  void set_robot(const RobotModel& robot);
  /// The sensor clock at simulated time 0, ns (params.sensor_time_at_zero_ns): a host that
  /// learns its wall-clock origin only when it starts running sets it before the first
  /// advance().
  void set_sensor_time_at_zero_ns(std::int64_t ns) { params_.sensor_time_at_zero_ns = ns; }

  /// Appends, in time order, every packet whose send time lies in (t0_s, t1_s] and that no
  /// earlier call produced; packets of an interval no call covered are skipped (the sensor
  /// was not simulated then). `rays`, when given, receives one SimRay per point produced.
  void advance(double t0_s, double t1_s, std::vector<SimPacket>& out,
               std::vector<SimRay>* rays = nullptr);

  /// Pose of the sensor frame in the world at time t (inside the sampled history).
  Eigen::Isometry3d T_W_S(double t_s) const;

  const Mid360SimParams& params() const { return params_; }
  const SimStats& stats() const { return stats_; }
  const RayScene& scene() const { return scene_; }
  bool ok() const { return scene_.ok(); }
  const std::string& error() const { return scene_.error(); }

  /// Send time of point packet j (the time of its last point), s.
  double packet_time_s(std::uint64_t j) const;
  /// Time of IMU sample k, s.
  double imu_time_s(std::uint64_t k) const { return static_cast<double>(k) / params_.imu_rate_hz; }

 private:
  void sample_state(std::int64_t t0_ns, std::int64_t t1_ns);
  void make_point_packet(std::uint64_t j, SimPacket& out, std::vector<SimRay>* rays);
  void make_imu_packet(std::uint64_t k, SimPacket& out);
  std::uint64_t sensor_ns(double t_s) const;

  Mid360SimParams params_;
  RobotModel robot_;
  ScanPattern pattern_;
  RayScene scene_;
  StateFunction state_;
  StateHistory history_;
  KinematicsWorkspace ws_;
  std::mt19937_64 rng_;
  std::uint64_t next_packet_ = 0;
  std::uint64_t next_imu_ = 0;
  std::int64_t sampled_until_ns_ = 0;
  bool sampled_any_ = false;
  std::int64_t current_frame_ = -1;
  std::uint16_t udp_cnt_ = 0;
  std::uint16_t imu_udp_cnt_ = 0;
  SimStats stats_;
};

}  // namespace porter::livox::sim
