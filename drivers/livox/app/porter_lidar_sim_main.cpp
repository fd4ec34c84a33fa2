// porter-lidar-sim: a simulated MID-360 on a static or scripted robot, sending real Livox UDP
// packets in real time (for porter-lidar without the hardware or porter-sim).
//
//   porter-lidar-sim [--config config/drivers/porter_lidar_sim.yaml]
//
// Exit codes: 0 after the configured duration or SIGINT/SIGTERM, 1 when a socket or Embree
// cannot be set up, 2 on a config error.
#include <optional>
#include <string>

#include "lidar_sim_params.hpp"
#include "porter/core/load_error.hpp"
#include "porter/livox_sim/command_server.hpp"
#include "porter/livox_sim/realtime_sender.hpp"
#include "porter/livox_sim/scripted_motion.hpp"
#include "porter/runtime/clock.hpp"
#include "porter/runtime/log.hpp"
#include "porter/runtime/periodic.hpp"
#include "porter/runtime/stop.hpp"

namespace rt = porter::runtime;
using namespace porter::livox;

int main(int argc, char** argv) {
  rt::init_log("porter-lidar-sim");
  std::string config = "config/drivers/porter_lidar_sim.yaml";
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--config" && i + 1 < argc) {
      config = argv[++i];
    } else {
      rt::log_error("usage: porter-lidar-sim [--config FILE]");
      return 2;
    }
  }
  app::LidarSimSetup setup;
  try {
    setup = app::load_lidar_sim_setup(config);
  } catch (const porter::LoadError& e) {
    rt::log_error(std::string("config: ") + e.what());
    return 2;
  }
  rt::install_stop_handlers();
  if (setup.sensor.time_type != TimeType::kNoSync) {
    // A synchronised sensor stamps packets with the master clock: here the host's own.
    setup.sensor.sensor_time_at_zero_ns = rt::wall_utime() * 1000;
  }
  const sim::ScriptedMotion motion(setup.waypoints, setup.loop);
  const std::int64_t build_start = rt::mono_ns();
  sim::SimulatedMid360 lidar(setup.sensor, setup.robot, setup.scene.obstacles,
                             [&motion](double t) { return motion.at(t); });
  if (!lidar.ok()) {
    rt::log_error(lidar.error());
    return 1;
  }
  std::string error;
  auto sender = sim::RealtimeSender::open(setup.network, error);
  if (!sender) {
    rt::log_error(error);
    return 1;
  }
  sender->set_sampling(setup.sampling_at_start);
  std::optional<sim::CommandServer> commands;
  if (setup.command_port != 0) {
    commands = sim::CommandServer::open("0.0.0.0", setup.command_port, error);
    if (!commands) {
      rt::log_error(error);
      return 1;
    }
    rt::log_info("answering sensor commands on :" + std::to_string(setup.command_port) +
                 (setup.sampling_at_start ? "" : "; idle until told to sample"));
  }
  rt::log_info("config " + config + "; scene " + setup.scene.name + " (" +
               std::to_string(setup.scene.obstacles.size()) + " obstacles, " +
               std::to_string(lidar.scene().world_triangles()) + " triangles), robot " +
               setup.robot.name + (setup.robot.payload_name.empty() ? "" : " with " + setup.robot.payload_name) +
               " (" + std::to_string(lidar.scene().robot_triangles()) + " triangles), " +
               std::to_string(setup.waypoints.size()) + " waypoint(s); scenes built in " +
               rt::format_ms((rt::mono_ns() - build_start) * 1e-9) + "; sending to " +
               setup.network.destination + " points :" + std::to_string(setup.network.point_port) +
               ", IMU :" + std::to_string(setup.network.imu_port));

  rt::PeriodicLoop loop(setup.step_period_s);
  const std::int64_t start = rt::mono_ns();
  std::int64_t busy_ns = 0, window_busy_ns = 0, window_start = start;
  std::uint64_t window_rays = lidar.stats().rays;
  while (!rt::stop_requested()) {
    loop.wait();
    const std::int64_t now = rt::mono_ns();
    const double t = (now - start) * 1e-9;
    if (setup.duration_s > 0.0 && t >= setup.duration_s) break;
    if (commands && commands->poll(*sender) > 0) rt::log_info("command applied:" + commands->last_applied());
    sender->step(lidar, t);
    const std::int64_t spent = rt::mono_ns() - now;
    busy_ns += spent;
    window_busy_ns += spent;
    if (now - window_start >= 10000000000LL) {
      const double window_s = (now - window_start) * 1e-9;
      const double rays = static_cast<double>(lidar.stats().rays - window_rays);
      rt::log_info("t " + std::to_string(static_cast<long>(t)) + " s: " +
                   std::to_string(static_cast<long>(rays / window_s)) + " rays/s, busy " +
                   std::to_string(100.0 * window_busy_ns * 1e-9 / window_s) + " % of one core, " +
                   std::to_string(sender->sent()) + " packets sent, " +
                   std::to_string(sender->send_failures()) + " send failures, " +
                   std::to_string(loop.overruns()) + " overruns");
      window_start = now;
      window_busy_ns = 0;
      window_rays = lidar.stats().rays;
    }
  }
  const double elapsed = (rt::mono_ns() - start) * 1e-9;
  rt::log_info("stopping after " + std::to_string(elapsed) + " s: " + std::to_string(sender->sent()) +
               " packets, " + std::to_string(lidar.stats().rays) + " rays, busy " +
               std::to_string(100.0 * busy_ns * 1e-9 / std::max(elapsed, 1e-9)) + " % of one core" +
               (sender->send_failures() ? ", last send error: " + sender->last_error() : ""));
  return 0;
}
