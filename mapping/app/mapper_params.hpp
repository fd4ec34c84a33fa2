#pragma once
// porter-mapper's configuration (config/mapping/porter_mapper.yaml) and its strict loader:
// every key is required; an unknown key, a wrong type or an out-of-range value is a LoadError
// naming the file and the key.

#include <string>

#include "porter/mapping/mapper.hpp"

namespace porter::mapping::app {

struct MapperConfig {
  std::string file;
  std::string lcm_url;                ///< "" = $LCM_DEFAULT_URL or LCM's default
  std::string robot_yaml;             ///< resolved path
  std::string payload_yaml;           ///< resolved path, "" = no payload
  std::string cloud_frame_id = "lidar";  ///< clouds in another frame are rejected
  std::string map_frame_id = "world";
  double publish_rate_hz = 2.0;       ///< MAP_OCTOMAP at most this often
  double state_wait_s = 0.05;         ///< the covering ROBOT_STATE may come this long (state time) after a scan's end
  double state_history_s = 2.0;
  int max_queued_clouds = 1;          ///< clouds waiting while one is processed
  double status_log_period_s = 10.0;
  MapperParams mapper;
};

MapperConfig load_mapper_config(const std::string& path);

}  // namespace porter::mapping::app
