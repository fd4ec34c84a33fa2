#include "lidar_params.hpp"

#include "porter/core/yaml_reader.hpp"

namespace porter::livox::app {
namespace {

std::uint16_t port(const yaml::Reader& r) {
  const int p = r.as_int();
  if (p < 1 || p > 65535) r.fail("must be a port number in [1, 65535]");
  return static_cast<std::uint16_t>(p);
}

}  // namespace

LidarParams load_lidar_params(const std::string& path) {
  const yaml::Reader root = yaml::Reader::load_file(path);
  root.expect_keys({"lcm_url", "network", "device", "cloud", "imu", "time", "check_crc",
                    "stream_timeout_s", "status_log_period_s"});
  LidarParams p;
  p.lcm_url = root.get("lcm_url").as_string();

  const yaml::Reader net = root.get("network");
  net.expect_keys({"address", "point_port", "imu_port", "receive_buffer_bytes"});
  p.listen_address = net.get("address").as_string();
  p.point_port = port(net.get("point_port"));
  p.imu_port = port(net.get("imu_port"));
  if (p.point_port == p.imu_port) net.get("imu_port").fail("must differ from point_port");
  const yaml::Reader buf = net.get("receive_buffer_bytes");
  p.receive_buffer_bytes = buf.as_int();
  if (p.receive_buffer_bytes < 65536) buf.fail("must be at least 65536");

  const yaml::Reader dev = root.get("device");
  dev.expect_keys({"configure", "lidar_address", "lidar_command_port", "host_address",
                   "host_command_port", "host_push_port", "retry_period_s"});
  p.device.configure = dev.get("configure").as_bool();
  std::array<std::uint8_t, 4> ip{};
  p.device.lidar_address = dev.get("lidar_address").as_string();
  if (!parse_ipv4(p.device.lidar_address, ip)) dev.get("lidar_address").fail("expected an IPv4 address");
  p.device.lidar_command_port = port(dev.get("lidar_command_port"));
  p.device.host_address = dev.get("host_address").as_string();
  if (!parse_ipv4(p.device.host_address, ip)) dev.get("host_address").fail("expected an IPv4 address");
  p.device.host_command_port = port(dev.get("host_command_port"));
  p.device.host_push_port = port(dev.get("host_push_port"));
  p.device.retry_period_s = dev.get("retry_period_s").as_in(0.01, 60.0, "s");

  const yaml::Reader cloud = root.get("cloud");
  cloud.expect_keys({"rate_hz", "frame_id", "extrinsic", "keep_no_return", "max_points"});
  const yaml::Reader rate = cloud.get("rate_hz");
  const double rate_hz = rate.as_positive();
  if (rate_hz < 0.1 || rate_hz > 100.0) rate.fail("must be in [0.1, 100] Hz");
  p.stream.cloud.period_s = 1.0 / rate_hz;
  p.cloud_frame_id = cloud.get("frame_id").as_string();
  if (p.cloud_frame_id.empty()) cloud.get("frame_id").fail("must not be empty");
  p.stream.cloud.T_out_sensor = cloud.get("extrinsic").as_pose();
  p.stream.cloud.keep_no_return = cloud.get("keep_no_return").as_bool();
  const yaml::Reader max_points = cloud.get("max_points");
  const int mp = max_points.as_int();
  if (mp < 1000 || mp > 10000000) max_points.fail("must be in [1000, 10000000]");
  p.stream.cloud.max_points = static_cast<std::size_t>(mp);

  const yaml::Reader imu = root.get("imu");
  imu.expect_keys({"frame_id"});
  p.imu_frame_id = imu.get("frame_id").as_string();
  if (p.imu_frame_id.empty()) imu.get("frame_id").fail("must not be empty");

  const yaml::Reader time = root.get("time");
  time.expect_keys({"host_window_s", "reset_threshold_s", "max_clamp_s"});
  p.stream.host_time.window_s = time.get("host_window_s").as_in(0.0, 60.0, "s");
  p.stream.host_time.reset_threshold_s = time.get("reset_threshold_s").as_in(1e-3, 60.0, "s");
  const yaml::Reader clamp = time.get("max_clamp_s");
  p.stream.host_time.max_clamp_s = clamp.as_nonnegative();
  if (p.stream.host_time.max_clamp_s > 0.01) clamp.fail("must be at most 0.01 s");

  p.stream.decode.check_crc = root.get("check_crc").as_bool();
  p.stream_timeout_s = root.get("stream_timeout_s").as_in(0.01, 60.0, "s");
  p.status_log_period_s = root.get("status_log_period_s").as_in(0.1, 3600.0, "s");
  return p;
}

}  // namespace porter::livox::app
