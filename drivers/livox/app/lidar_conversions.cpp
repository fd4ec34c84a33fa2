#include "lidar_conversions.hpp"

namespace porter::livox::app {

void to_message(const Cloud& cloud, const std::string& frame_id, porter::point_cloud_t& msg) {
  std::int64_t utime = cloud.start_ns / 1000;
  if (cloud.start_ns < 0 && cloud.start_ns % 1000 != 0) --utime;  // floor
  const auto sub_us = static_cast<std::int32_t>(cloud.start_ns - utime * 1000);
  msg.utime = utime;
  msg.frame_id = frame_id;
  msg.scan_id = cloud.scan_id;
  msg.num_points = static_cast<std::int32_t>(cloud.size());
  msg.x_m = cloud.x_m;
  msg.y_m = cloud.y_m;
  msg.z_m = cloud.z_m;
  msg.intensity = cloud.intensity;
  msg.time_offset_ns.resize(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) msg.time_offset_ns[i] = cloud.time_offset_ns[i] + sub_us;
  msg.line = cloud.line;
  msg.tag = cloud.tag;
}

void to_message(const ImuMeasurement& imu, const std::string& frame_id, porter::imu_t& msg) {
  msg.utime = imu.time_ns / 1000;
  msg.frame_id = frame_id;
  msg.gyro_x_radps = imu.sample.gyro_radps[0];
  msg.gyro_y_radps = imu.sample.gyro_radps[1];
  msg.gyro_z_radps = imu.sample.gyro_radps[2];
  msg.accel_x_mps2 = imu.sample.accel_g[0] * kStandardGravity_mps2;
  msg.accel_y_mps2 = imu.sample.accel_g[1] * kStandardGravity_mps2;
  msg.accel_z_mps2 = imu.sample.accel_g[2] * kStandardGravity_mps2;
}

}  // namespace porter::livox::app
