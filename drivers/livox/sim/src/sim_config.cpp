#include "porter/livox_sim/sim_config.hpp"

#include <urdf_parser/urdf_parser.h>

#include "porter/core/load_error.hpp"

namespace porter::livox::sim {
namespace {

Eigen::Isometry3d to_eigen(const urdf::Pose& p) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(p.position.x, p.position.y, p.position.z);
  T.linear() = Eigen::Quaterniond(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z)
                   .normalized()
                   .toRotationMatrix();
  return T;
}

double in_range(const yaml::Reader& r, double lo, double hi) {
  const double v = r.as_double();
  if (v < lo || v > hi) {
    r.fail("must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " +
           std::to_string(v));
  }
  return v;
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
  p.pattern.point_rate_hz = s.get("point_rate_hz").as_positive();
  p.pattern.rotation_hz = s.get("rotation_hz").as_positive();
  p.frame_rate_hz = s.get("frame_rate_hz").as_positive();
  const yaml::Reader el = s.get("elevation_deg");
  const auto e = el.as_doubles(2);
  if (!(e[0] < e[1]) || e[0] < -90.0 || e[1] > 90.0) {
    el.fail("expected [min, max] with -90 <= min < max <= 90");
  }
  p.pattern.elevation_min_deg = e[0];
  p.pattern.elevation_max_deg = e[1];
  p.min_range_m = s.get("min_range_m").as_nonnegative();
  const yaml::Reader max_r = s.get("max_range_m");
  p.max_range_m = max_r.as_positive();
  if (!(p.max_range_m > p.min_range_m)) max_r.fail("must exceed min_range_m");
  p.range_noise_stddev_m = s.get("range_noise_stddev_m").as_nonnegative();
  p.dropout_probability = in_range(s.get("dropout_probability"), 0.0, 1.0);

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
  p.imu_rate_hz = imu.get("rate_hz").as_positive();
  p.gyro_noise_stddev_radps = imu.get("gyro_noise_stddev_radps").as_nonnegative();
  p.accel_noise_stddev_mps2 = imu.get("accel_noise_stddev_mps2").as_nonnegative();
  p.p_S_imu_m = imu.get("position_m").as_vec3();

  const yaml::Reader mount = s.get("mount");
  mount.expect_keys({"link", "xyz", "rpy"});
  const std::string link = mount.get("link").as_string();
  Eigen::Isometry3d T_link_S = Eigen::Isometry3d::Identity();
  T_link_S.translation() = mount.get("xyz").as_vec3();
  const Eigen::Vector3d rpy = mount.get("rpy").as_vec3();
  T_link_S.linear() = yaml::rpy_to_matrix(rpy[0], rpy[1], rpy[2]);
  try {
    p.T_B_S = fixed_link_pose(robot_yaml_path, link) * T_link_S;
  } catch (const LoadError& err) {
    mount.get("link").fail(err.what());
  }

  p.scene.ground_plane = s.get("ground_plane").as_bool();
  p.scene.tessellation_tolerance_m = s.get("tessellation_tolerance_m").as_positive();
  p.state_sample_period_s = s.get("state_sample_period_s").as_positive();
  const int seed = s.get("seed").as_int();
  if (seed < 0) s.get("seed").fail("must not be negative");
  p.seed = static_cast<std::uint64_t>(seed);
  return p;
}

}  // namespace porter::livox::sim
