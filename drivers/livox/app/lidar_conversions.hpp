#pragma once
// porter-lidar's one adapter between its domain types and lcmtypes.

#include <string>

#include "porter/imu_t.hpp"
#include "porter/livox/lidar_stream.hpp"
#include "porter/point_cloud_t.hpp"

namespace porter::livox::app {

/// Cloud -> point_cloud_t. utime is the first point's time truncated to the microsecond; the
/// per-point offsets are counted from utime (so they include the truncated nanoseconds).
void to_message(const Cloud& cloud, const std::string& frame_id, porter::point_cloud_t& msg);

/// IMU sample -> imu_t (acceleration from g to m/s^2 with standard gravity).
void to_message(const ImuMeasurement& imu, const std::string& frame_id, porter::imu_t& msg);

}  // namespace porter::livox::app
