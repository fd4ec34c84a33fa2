// porter-lidar: the Livox MID-360 driver. Receives the sensor's point and IMU datagrams on UDP,
// publishes LIDAR_POINTS (10 Hz clouds) and LIDAR_IMU (200 Hz), and its health on HEARTBEAT.
//
//   porter-lidar [--config config/drivers/porter_lidar.yaml]
//
// Exit codes: 0 after SIGINT/SIGTERM, 1 when LCM or a socket cannot be opened, 2 on a config
// error.
#include <poll.h>

#include <optional>
#include <string>
#include <vector>

#include "lidar_conversions.hpp"
#include "lidar_params.hpp"
#include "porter/core/load_error.hpp"
#include "porter/lcm_bus.hpp"
#include "porter/livox/udp.hpp"
#include "porter/runtime/clock.hpp"
#include "porter/runtime/heartbeat.hpp"
#include "porter/runtime/log.hpp"
#include "porter/runtime/stop.hpp"

namespace rt = porter::runtime;
using namespace porter::livox;

int main(int argc, char** argv) {
  rt::init_log("porter-lidar");
  std::string config = "config/drivers/porter_lidar.yaml";
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--config" && i + 1 < argc) {
      config = argv[++i];
    } else {
      rt::log_error("usage: porter-lidar [--config FILE]");
      return 2;
    }
  }
  app::LidarParams params;
  try {
    params = app::load_lidar_params(config);
  } catch (const porter::LoadError& e) {
    rt::log_error(std::string("config: ") + e.what());
    return 2;
  }
  rt::install_stop_handlers();
  porter::LcmBus bus(params.lcm_url);
  if (!bus.good()) {
    rt::log_error("cannot open LCM at '" + params.lcm_url + "'");
    return 1;
  }
  std::string error;
  auto point_rx = UdpReceiver::open(params.listen_address, params.point_port,
                                    params.receive_buffer_bytes, error);
  if (!point_rx) {
    rt::log_error(error);
    return 1;
  }
  auto imu_rx = UdpReceiver::open(params.listen_address, params.imu_port,
                                  params.receive_buffer_bytes, error);
  if (!imu_rx) {
    rt::log_error(error);
    return 1;
  }
  rt::log_info("config " + config + "; listening on " + params.listen_address + " points :" +
               std::to_string(point_rx->port()) + ", IMU :" + std::to_string(imu_rx->port()) +
               " (kernel receive buffer " + std::to_string(point_rx->granted_buffer_bytes()) +
               " B); clouds at " + std::to_string(1.0 / params.stream.cloud.period_s) +
               " Hz in frame '" + params.cloud_frame_id + "', CRC check " +
               (params.stream.decode.check_crc ? "on" : "off"));

  std::optional<app::DeviceConfigurator> device;
  if (params.device.configure) {
    device = app::DeviceConfigurator::open(params.device, point_rx->port(), imu_rx->port(), error);
    if (!device) {
      rt::log_error(error);
      return 1;
    }
  }

  LidarStream stream(params.stream);
  rt::Heartbeat heartbeat(bus, "porter-lidar");
  std::vector<Datagram> batch(32);
  std::vector<Cloud> clouds;
  std::vector<ImuMeasurement> imus;
  porter::point_cloud_t cloud_msg;
  porter::imu_t imu_msg;
  std::uint64_t publish_failures = 0;
  std::uint64_t malformed_seen = 0, lost_seen = 0;
  std::int64_t last_fault_ns = 0;  // monotonic time of the last new malformed or lost packet
  std::int64_t last_log_ns = rt::mono_ns();
  LidarStreamCounters at_last_log;
  bool streaming = false;
  double publish_ms_max = 0.0;

  while (!rt::stop_requested()) {
    pollfd fds[4] = {{point_rx->fd(), POLLIN, 0}, {imu_rx->fd(), POLLIN, 0}, {rt::stop_fd(), POLLIN, 0},
                     {device ? device->fd() : -1, POLLIN, 0}};
    ::poll(fds, 4, 100);
    for (UdpReceiver* rx : {&*point_rx, &*imu_rx}) {
      for (;;) {
        const int n = rx->receive(batch);
        if (n < 0) rt::log_warn("receive on :" + std::to_string(rx->port()) + ": " + rx->last_error());
        if (n <= 0) break;
        for (int i = 0; i < n; ++i) {
          stream.handle(batch[i].bytes.data(), batch[i].size, batch[i].truncated,
                        batch[i].receive_utime_ns, clouds, imus);
        }
      }
    }
    const std::int64_t now_wall = rt::wall_utime() * 1000;
    stream.flush_if_idle(now_wall, params.stream_timeout_s, clouds);
    for (const ImuMeasurement& m : imus) {
      app::to_message(m, params.imu_frame_id, imu_msg);
      if (!bus.publish(porter::channels::kLidarImu, imu_msg)) ++publish_failures;
    }
    imus.clear();
    for (const Cloud& c : clouds) {
      const std::int64_t t0 = rt::mono_ns();
      app::to_message(c, params.cloud_frame_id, cloud_msg);
      if (!bus.publish(porter::channels::kLidarPoints, cloud_msg)) ++publish_failures;
      publish_ms_max = std::max(publish_ms_max, (rt::mono_ns() - t0) * 1e-6);
    }
    clouds.clear();

    // Health: waiting for the sensor = warn, silent sensor = error; malformed or lost packets
    // within the last two seconds = warn.
    const LidarStreamCounters& c = stream.counters();
    const std::int64_t last_rx = std::max(stream.last_point_receive_ns(), stream.last_imu_receive_ns());
    const bool silent = last_rx == 0 || now_wall - last_rx > static_cast<std::int64_t>(params.stream_timeout_s * 1e9);
    if (device) device->step(rt::mono_ns(), !silent);
    if (!silent && !streaming) rt::log_info("sensor stream started");
    if (silent && streaming) rt::log_warn("sensor stream stopped (no packet for " + std::to_string(params.stream_timeout_s) + " s)");
    streaming = !silent;
    const std::uint64_t lost = c.lost_point_packets + c.lost_imu_packets;
    if (c.decode.malformed() != malformed_seen || lost != lost_seen) {
      malformed_seen = c.decode.malformed();
      lost_seen = lost;
      last_fault_ns = rt::mono_ns();
    }
    auto health = rt::HeartbeatHealth::ok;
    std::string status = stream.summary();
    if (publish_failures > 0) status += ", publish failures " + std::to_string(publish_failures);
    if (last_rx == 0) {
      health = rt::HeartbeatHealth::warn;
      status = "waiting for the sensor; " + status;
    } else if (silent) {
      health = rt::HeartbeatHealth::error;
      status = "no packets; " + status;
    } else if (last_fault_ns != 0 && rt::mono_ns() - last_fault_ns < 2000000000LL) {
      health = rt::HeartbeatHealth::warn;
    }
    heartbeat.update(health, status);

    const std::int64_t now = rt::mono_ns();
    const double dt_s = (now - last_log_ns) * 1e-9;
    if (dt_s >= params.status_log_period_s) {
      const auto rate = [&](std::uint64_t a, std::uint64_t b) { return std::to_string(static_cast<long>((a - b) / dt_s)); };
      rt::log_info("clouds " + rate(c.clouds, at_last_log.clouds) + "/s, points " +
                   rate(c.points, at_last_log.points) + "/s, point packets " +
                   rate(c.point_packets, at_last_log.point_packets) + "/s, IMU " +
                   rate(c.imu_packets, at_last_log.imu_packets) + "/s; publish max " +
                   rt::format_ms(publish_ms_max * 1e-3) + "; " + status);
      at_last_log = c;
      last_log_ns = now;
      publish_ms_max = 0.0;
    }
  }
  const LidarStreamCounters& total = stream.counters();
  rt::log_info("stopping: " + std::to_string(total.point_packets) + " point packets, " +
               std::to_string(total.imu_packets) + " IMU packets, " + std::to_string(total.clouds) +
               " clouds, " + std::to_string(total.points) + " points; " + stream.summary());
  return 0;
}
