#include "porter/livox_sim/simulated_mid360.hpp"

#include <algorithm>
#include <cmath>

#include "porter/livox/encoder.hpp"

namespace porter::livox::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::int64_t to_ns(double t_s) { return static_cast<std::int64_t>(std::llround(t_s * 1e9)); }

Eigen::Isometry3d sensor_pose(const BasePose& base, const Eigen::Isometry3d& T_B_S) {
  return base.T_W_B() * T_B_S;
}

std::uint8_t reflectivity(HitKind kind, float cos_incidence) {
  // Diffuse surfaces of four brightnesses; 255 is kept free (retro-reflectors on the device).
  static constexpr float kBase[5] = {0.0f, 40.0f, 100.0f, 160.0f, 200.0f};
  const float r = kBase[static_cast<int>(kind)] * (0.25f + 0.75f * cos_incidence);
  return static_cast<std::uint8_t>(std::clamp(std::lround(r), 1L, 254L));
}

}  // namespace

SimulatedMid360::SimulatedMid360(const Mid360SimParams& params, const RobotModel& robot,
                                 const std::vector<CollisionShape>& obstacles_W, StateFunction state)
    : params_(params),
      robot_(robot),
      pattern_(params.pattern),
      scene_(params.scene),
      state_(std::move(state)),
      rng_(params.seed) {
  scene_.set_obstacles(obstacles_W);
  scene_.set_robot(robot_);
}

void SimulatedMid360::set_obstacles(const std::vector<CollisionShape>& obstacles_W) {
  scene_.set_obstacles(obstacles_W);
}

void SimulatedMid360::set_robot(const RobotModel& robot) {
  robot_ = robot;
  scene_.set_robot(robot_);
}

double SimulatedMid360::packet_time_s(std::uint64_t j) const {
  return static_cast<double>(j * kPointsPerPacket + kPointsPerPacket - 1) /
         params_.pattern.point_rate_hz;
}

std::uint64_t SimulatedMid360::sensor_ns(double t_s) const {
  const std::int64_t ns = params_.sensor_time_at_zero_ns + to_ns(t_s);
  return ns > 0 ? static_cast<std::uint64_t>(ns) : 0u;
}

Eigen::Isometry3d SimulatedMid360::T_W_S(double t_s) const {
  return sensor_pose(history_.at(to_ns(t_s)).base, params_.T_B_S);
}

void SimulatedMid360::sample_state(std::int64_t t0_ns, std::int64_t t1_ns) {
  if (!state_) return;
  const std::int64_t h = std::max<std::int64_t>(1000, to_ns(params_.state_sample_period_s));
  const std::int64_t from = sampled_any_ ? std::max(t0_ns, sampled_until_ns_) : t0_ns;
  // First grid time strictly after `from`.
  std::int64_t g = (from >= 0 ? from / h + 1 : -((-from) / h)) * h;
  if (g <= from) g += h;
  for (; g <= t1_ns; g += h) history_.add(g, state_(static_cast<double>(g) * 1e-9));
  if (history_.empty() || history_.newest_ns() < t1_ns) {
    history_.add(t1_ns, state_(static_cast<double>(t1_ns) * 1e-9));
  }
  sampled_until_ns_ = t1_ns;
  sampled_any_ = true;
}

void SimulatedMid360::advance(double t0_s, double t1_s, std::vector<SimPacket>& out,
                              std::vector<SimRay>* rays) {
  if (!(t1_s > t0_s)) return;

  // Skip packets of an interval no call covered.
  const double rate = params_.pattern.point_rate_hz;
  const double j_after_t0 = std::floor((t0_s * rate - (kPointsPerPacket - 1)) / kPointsPerPacket) + 1.0;
  if (j_after_t0 > 0.0) {
    next_packet_ = std::max(next_packet_, static_cast<std::uint64_t>(j_after_t0));
    while (packet_time_s(next_packet_) <= t0_s) ++next_packet_;
  }
  if (params_.imu_enabled) {
    const double k_after_t0 = std::floor(t0_s * params_.imu_rate_hz) + 1.0;
    if (k_after_t0 > 0.0) next_imu_ = std::max(next_imu_, static_cast<std::uint64_t>(k_after_t0));
  }

  // Sub-steps of at most 10 ms keep every time a packet needs inside the 50 ms history.
  const std::size_t first = out.size();
  for (double a = t0_s; a < t1_s;) {
    const double b = std::min(t1_s, a + 0.01);
    sample_state(to_ns(a), to_ns(b));
    while (packet_time_s(next_packet_) <= b) {
      out.emplace_back();
      make_point_packet(next_packet_++, out.back(), rays);
    }
    while (params_.imu_enabled && imu_time_s(next_imu_) <= b) {
      out.emplace_back();
      make_imu_packet(next_imu_++, out.back());
    }
    a = b;
  }
  std::stable_sort(out.begin() + static_cast<std::ptrdiff_t>(first), out.end(),
                   [](const SimPacket& a, const SimPacket& b) { return a.time_s < b.time_s; });
}

void SimulatedMid360::make_point_packet(std::uint64_t j, SimPacket& out, std::vector<SimRay>* rays) {
  const double rate = params_.pattern.point_rate_hz;
  const std::uint64_t n0 = j * kPointsPerPacket;
  const double t_first = static_cast<double>(n0) / rate;
  const double t_last = packet_time_s(j);
  const double t_mid = 0.5 * (t_first + t_last);

  const auto frame = static_cast<std::int64_t>(std::floor(t_first * params_.frame_rate_hz));
  if (frame != current_frame_) {
    current_frame_ = frame;
    udp_cnt_ = 0;
  }

  forward_kinematics(robot_, history_.at(to_ns(t_mid)), ws_);
  scene_.set_link_poses(ws_.T_W_L);
  const RobotConfiguration c_first = history_.at(to_ns(t_first));
  const RobotConfiguration c_last = history_.at(to_ns(t_last));

  std::array<Point, kPointsPerPacket> points;
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const float min_r = static_cast<float>(params_.min_range_m);
  const float max_r = static_cast<float>(params_.max_range_m);
  for (std::size_t i = 0; i < kPointsPerPacket; ++i) {
    const std::uint64_t n = n0 + i;
    const double s = static_cast<double>(i) / (kPointsPerPacket - 1);
    const Eigen::Isometry3d T = sensor_pose(interpolate(c_first, c_last, s).base, params_.T_B_S);
    const Eigen::Vector3d d_S = pattern_.direction(n);
    const Eigen::Vector3f d_W = (T.linear() * d_S).cast<float>();
    const Eigen::Vector3f o_W = T.translation().cast<float>();
    const RayHit hit = scene_.cast(o_W, d_W, min_r, max_r);
    ++stats_.rays;
    ++stats_.hits_by_kind[static_cast<std::size_t>(hit.kind)];

    Point& p = points[i];
    p = Point{};
    bool returned = false;
    if (hit.hit()) {
      double range = hit.distance_m;
      if (params_.range_noise_stddev_m > 0.0) range += params_.range_noise_stddev_m * gauss(rng_);
      const bool dropped =
          params_.dropout_probability > 0.0 && uniform(rng_) < params_.dropout_probability;
      if (!dropped && range >= params_.min_range_m && range <= params_.max_range_m) {
        p.x_m = static_cast<float>(range * d_S.x());
        p.y_m = static_cast<float>(range * d_S.y());
        p.z_m = static_cast<float>(range * d_S.z());
        // A point that would round to the no-return marker is nudged off it.
        if (p.is_no_return()) p.x_m = 1e-3f;
        p.reflectivity = reflectivity(hit.kind, hit.cos_incidence);
        returned = true;
        ++stats_.returns;
      }
    }
    if (rays != nullptr) {
      SimRay r;
      r.t_s = static_cast<double>(n) / rate;
      r.point_index = n;
      r.origin_W = o_W;
      r.hit_W = hit.hit() ? Eigen::Vector3f(o_W + hit.distance_m * d_W) : o_W;
      r.point_S = Eigen::Vector3f(p.x_m, p.y_m, p.z_m);
      r.kind = hit.kind;
      r.index = static_cast<std::int16_t>(hit.index);
      r.returned = returned;
      rays->push_back(r);
    }
  }

  PacketInfo info;
  info.time_interval_100ns =
      static_cast<std::uint16_t>(std::clamp(std::llround((t_last - t_first) * 1e7), 0LL, 65535LL));
  info.udp_cnt = udp_cnt_++;
  info.frame_cnt = static_cast<std::uint8_t>(frame & 0xFF);
  info.time_type = params_.time_type;
  info.timestamp_ns = sensor_ns(t_first);
  out.time_s = t_last;
  out.stream = SimPacket::Stream::points;
  out.size = static_cast<std::uint16_t>(encode_point_packet(
      info, params_.data_type, points.data(), points.size(), out.bytes.data(), out.bytes.size()));
  ++stats_.point_packets;
}

void SimulatedMid360::make_imu_packet(std::uint64_t k, SimPacket& out) {
  const double t = imu_time_s(k);
  const std::int64_t tn = to_ns(t);
  const std::int64_t h = std::max<std::int64_t>(1000, to_ns(params_.state_sample_period_s));
  const double h_s = static_cast<double>(h) * 1e-9;
  std::array<RobotConfiguration, 4> c;
  std::array<Eigen::Vector3d, 4> p;
  const Eigen::Vector3d p_B_imu = params_.T_B_S * params_.p_S_imu_m;
  for (int m = 0; m < 4; ++m) {
    c[m] = history_.at(tn - m * h);
    p[m] = c[m].base.T_W_B() * p_B_imu;
  }
  // Second-order backward differences (exact for quadratic motion over the last 3 h).
  const Eigen::Vector3d a_W = (2.0 * p[0] - 5.0 * p[1] + 4.0 * p[2] - p[3]) / (h_s * h_s);
  const double dy01 = std::remainder(c[0].base.yaw_rad - c[1].base.yaw_rad, 2.0 * kPi);
  const double dy12 = std::remainder(c[1].base.yaw_rad - c[2].base.yaw_rad, 2.0 * kPi);
  const double yaw_rate = (3.0 * dy01 - dy12) / (2.0 * h_s);
  const Eigen::Matrix3d R_W_S = sensor_pose(c[0].base, params_.T_B_S).linear();
  Eigen::Vector3d gyro = R_W_S.transpose() * Eigen::Vector3d(0.0, 0.0, yaw_rate);
  Eigen::Vector3d force =
      R_W_S.transpose() * (a_W + Eigen::Vector3d(0.0, 0.0, kStandardGravity_mps2));
  std::normal_distribution<double> gauss(0.0, 1.0);
  if (params_.gyro_noise_stddev_radps > 0.0) {
    for (int i = 0; i < 3; ++i) gyro[i] += params_.gyro_noise_stddev_radps * gauss(rng_);
  }
  if (params_.accel_noise_stddev_mps2 > 0.0) {
    for (int i = 0; i < 3; ++i) force[i] += params_.accel_noise_stddev_mps2 * gauss(rng_);
  }
  ImuSample sample;
  for (int i = 0; i < 3; ++i) {
    sample.gyro_radps[i] = static_cast<float>(gyro[i]);
    sample.accel_g[i] = static_cast<float>(force[i] / kStandardGravity_mps2);
  }
  PacketInfo info;
  info.udp_cnt = imu_udp_cnt_++;
  info.time_type = params_.time_type;
  info.timestamp_ns = sensor_ns(t);
  out.time_s = t;
  out.stream = SimPacket::Stream::imu;
  out.size = static_cast<std::uint16_t>(encode_imu_packet(info, sample, out.bytes.data(), out.bytes.size()));
  ++stats_.imu_packets;
}

}  // namespace porter::livox::sim
