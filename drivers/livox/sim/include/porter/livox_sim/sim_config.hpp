#pragma once
// YAML for the simulated MID-360 (part of porter::livox_sim_io; the simulation library itself
// reads no files). The `sensor` map of config/drivers/porter_lidar_sim.yaml, every key required:
//
//   point_rate_hz: 200000          # > 0
//   rotation_hz: 10.0              # azimuth turns per second, > 0
//   frame_rate_hz: 10.0            # > 0
//   elevation_deg: [-7.0, 52.0]    # min < max, within [-90, 90]
//   min_range_m: 0.1               # >= 0
//   max_range_m: 40.0              # > min_range_m
//   range_noise_stddev_m: 0.0      # >= 0
//   dropout_probability: 0.0       # [0, 1]
//   data_type: cartesian_high      # cartesian_high | cartesian_low | spherical
//   time_type: no_sync             # no_sync | ptp | gps
//   imu: {enabled: true, rate_hz: 200.0, gyro_noise_stddev_radps: 0.0,
//         accel_noise_stddev_mps2: 0.0, position_m: [0.011, 0.02329, -0.04412]}
//   mount: {link: lidar_mast, xyz: [0.0, 0.0, 0.2875], rpy: [0.0, 0.0, 0.0]}
//   ground_plane: true
//   tessellation_tolerance_m: 0.0005   # > 0
//   state_sample_period_s: 0.001       # > 0
//   seed: 1                            # >= 0
//
// mount places the sensor's point frame relative to a link of the robot's URDF; the link must
// hang off the base link through fixed joints only (a mast), and the result is T_B_S. The
// robot model merges such links into the base, so the URDF is read again here (urdfdom).
//
// Failure: LoadError naming the file and the key.

#include <string>

#include <Eigen/Geometry>

#include "porter/core/yaml_reader.hpp"
#include "porter/livox_sim/simulated_mid360.hpp"

namespace porter::livox::sim {

/// Parses the `sensor` map. robot_yaml_path: the robot config whose URDF holds mount.link.
Mid360SimParams load_mid360_sim_params(const yaml::Reader& sensor,
                                       const std::string& robot_yaml_path);

/// Pose of URDF link `link` in the robot's base link frame; throws LoadError when the link is
/// missing or reached from the base through a joint that is not fixed.
Eigen::Isometry3d fixed_link_pose(const std::string& robot_yaml_path, const std::string& link);

}  // namespace porter::livox::sim
