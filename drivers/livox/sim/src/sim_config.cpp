#include "porter/livox_sim/sim_config.hpp"

#include <cmath>

#include <urdf_parser/urdf_parser.h>

#include "porter/core/load_error.hpp"

namespace porter::livox::sim {
namespace {

constexpr double kTwoPi = 6.283185307179586;

Eigen::Isometry3d to_eigen(const urdf::Pose& p) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(p.position.x, p.position.y, p.position.z);
  T.linear() = Eigen::Quaterniond(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z)
                   .normalized()
                   .toRotationMatrix();
  return T;
}

}  // namespace

Eigen::Isometry3d fixed_link_pose(const std::string& robot_yaml_path, const std::string& link) {
  const yaml::Reader robot = yaml::Reader::load_file(robot_yaml_path);
  const std::string urdf_path = yaml::resolve_path(robot_yaml_path, robot.get("urdf").as_string());
  const std::string base = robot.get("base_link").as_string();
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDFFile(urdf_path);
  if (!model) throw LoadError(urdf_path, "", "not a readable URDF");
  urdf::LinkConstSharedPtr l = model->getLink(link);
  if (!l) throw LoadError(urdf_path, "link '" + link + "'", "no such link");
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  while (l->name != base) {
    const urdf::JointSharedPtr& j = l->parent_joint;
    if (!j) throw LoadError(urdf_path, "link '" + link + "'", "not below base link '" + base + "'");
    if (j->type != urdf::Joint::FIXED) {
      throw LoadError(urdf_path, "joint '" + j->name + "'",
                      "the sensor mount must hang off the base through fixed joints only");
    }
    T = to_eigen(j->parent_to_joint_origin_transform) * T;
    l = l->getParent();
    if (!l) throw LoadError(urdf_path, "link '" + link + "'", "not below base link '" + base + "'");
  }
  return T;
}

Mid360SimParams load_mid360_sim_params(const yaml::Reader& s, const std::string& robot_yaml_path) {
  s.expect_keys({"point_rate_hz", "rotation_hz", "frame_rate_hz", "elevation_deg", "min_range_m",
                 "max_range_m", "range_noise_stddev_m", "dropout_probability", "data_type",
                 "time_type", "imu", "mount", "ground_plane", "tessellation_tolerance_m",
                 "state_sample_period_s", "seed"});
  Mid360SimParams p;
  // Rates bound the points and packets built per frame and per simulation step (the MID-360:
  // 200,000 points/s, 10 Hz frames; 2e6 points/s is ten times the sensor).
  p.pattern.point_rate_hz = s.get("point_rate_hz").as_in(1e3, 2e6, "points/s");
  p.pattern.rotation_hz = s.get("rotation_hz").as_in(0.1, 100.0, "Hz");
  p.frame_rate_hz = s.get("frame_rate_hz").as_in(0.1, 100.0, "Hz");
  const yaml::Reader el = s.get("elevation_deg");
  const auto e = el.as_doubles(2);
  if (!(e[0] < e[1]) || e[0] < -90.0 || e[1] > 90.0) {
    el.fail("expected [min, max] with -90 <= min < max <= 90");
  }
  p.pattern.elevation_min_deg = e[0];
  p.pattern.elevation_max_deg = e[1];
  // Ranges within 1 km (the MID-360 reaches 70 m): the ray caster's march is bounded by it.
  p.min_range_m = s.get("min_range_m").as_in(0.0, 1000.0, "m");
  const yaml::Reader max_r = s.get("max_range_m");
  p.max_range_m = max_r.as_in(0.0, 1000.0, "m", true);
  if (!(p.max_range_m > p.min_range_m)) max_r.fail("must exceed min_range_m");
  p.range_noise_stddev_m = s.get("range_noise_stddev_m").as_in(0.0, 10.0, "m");
  p.dropout_probability = s.get("dropout_probability").as_in(0.0, 1.0);

  const yaml::Reader dt = s.get("data_type");
  const std::string data_type = dt.as_string();
  if (data_type == "cartesian_high") p.data_type = DataType::kCartesianHigh;
  else if (data_type == "cartesian_low") p.data_type = DataType::kCartesianLow;
  else if (data_type == "spherical") p.data_type = DataType::kSpherical;
  else dt.fail("expected cartesian_high, cartesian_low or spherical, got '" + data_type + "'");
  const yaml::Reader tt = s.get("time_type");
  const std::string time_type = tt.as_string();
  if (time_type == "no_sync") p.time_type = TimeType::kNoSync;
  else if (time_type == "ptp") p.time_type = TimeType::kPtp;
  else if (time_type == "gps") p.time_type = TimeType::kGps;
  else tt.fail("expected no_sync, ptp or gps, got '" + time_type + "'");

  const yaml::Reader imu = s.get("imu");
  imu.expect_keys({"enabled", "rate_hz", "gyro_noise_stddev_radps", "accel_noise_stddev_mps2",
                   "position_m"});
  p.imu_enabled = imu.get("enabled").as_bool();
  p.imu_rate_hz = imu.get("rate_hz").as_in(1.0, 1000.0, "Hz");
  p.gyro_noise_stddev_radps = imu.get("gyro_noise_stddev_radps").as_in(0.0, 100.0, "rad/s");
  p.accel_noise_stddev_mps2 = imu.get("accel_noise_stddev_mps2").as_in(0.0, 1000.0, "m/s^2");
  p.p_S_imu_m = imu.get("position_m").as_vec3();
  // A sensor's parts and its mount lie within metres of the link that carries it.
  if (!(p.p_S_imu_m.cwiseAbs().maxCoeff() <= 10.0)) imu.get("position_m").fail("must be within 10 m of the sensor");

  const yaml::Reader mount = s.get("mount");
  mount.expect_keys({"link", "xyz", "rpy"});
  const std::string link = mount.get("link").as_string();
  Eigen::Isometry3d T_link_S = Eigen::Isometry3d::Identity();
  T_link_S.translation() = mount.get("xyz").as_vec3();
  if (!(T_link_S.translation().cwiseAbs().maxCoeff() <= 10.0)) mount.get("xyz").fail("must be within 10 m of the link");
  const Eigen::Vector3d rpy = mount.get("rpy").as_vec3();
  if (!(rpy.cwiseAbs().maxCoeff() <= kTwoPi)) mount.get("rpy").fail("angles must be within [-2 pi, 2 pi] rad");
  T_link_S.linear() = yaml::rpy_to_matrix(rpy[0], rpy[1], rpy[2]);
  try {
    p.T_B_S = fixed_link_pose(robot_yaml_path, link) * T_link_S;
  } catch (const LoadError& err) {
    mount.get("link").fail(err.what());
  }

  p.scene.ground_plane = s.get("ground_plane").as_bool();
  // Below 10 um a cylinder's tessellation grows without need; above 10 cm shapes lose their form.
  p.scene.tessellation_tolerance_m = s.get("tessellation_tolerance_m").as_in(1e-5, 0.1, "m");
  p.state_sample_period_s = s.get("state_sample_period_s").as_in(1e-4, 0.1, "s");
  const int seed = s.get("seed").as_int();
  if (seed < 0) s.get("seed").fail("must not be negative");
  p.seed = static_cast<std::uint64_t>(seed);
  return p;
}

}  // namespace porter::livox::sim
