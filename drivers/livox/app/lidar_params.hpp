#pragma once
// porter-lidar's parameters and their YAML (config/drivers/porter_lidar.yaml; every key is
// required, unknown keys and out-of-range values are LoadErrors naming file and key).

#include <cstdint>
#include <string>

#include "lidar_device.hpp"
#include "porter/livox/lidar_stream.hpp"

namespace porter::livox::app {

struct LidarParams {
  std::string lcm_url;                 ///< "" = $LCM_DEFAULT_URL or LCM's default
  std::string listen_address = "0.0.0.0";
  std::uint16_t point_port = kDefaultPointHostPort;
  std::uint16_t imu_port = kDefaultImuHostPort;
  int receive_buffer_bytes = 4 << 20;
  std::string cloud_frame_id = "lidar";
  std::string imu_frame_id = "lidar_imu";
  double stream_timeout_s = 1.0;       ///< no packet for this long: cloud flushed, health warns
  double status_log_period_s = 10.0;   ///< a log line with rates and counts this often
  LidarStreamParams stream;
  DeviceParams device;
};

LidarParams load_lidar_params(const std::string& path);

}  // namespace porter::livox::app
