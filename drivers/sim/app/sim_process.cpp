#include "sim_process.hpp"

#include <sys/resource.h>

#include <cstdio>

#include "porter/can/can_transport.hpp"
#include "porter/channels.hpp"
#include "porter/core/payload.hpp"
#include "porter/core/payload_loader.hpp"
#include "porter/core/robot_loader.hpp"
#include "porter/core/scene_loader.hpp"
#include "porter/runtime/clock.hpp"
#include "porter/runtime/heartbeat.hpp"
#include "porter/runtime/log.hpp"
#include "porter/runtime/periodic.hpp"
#include "porter/sim/pose_sensors.hpp"
#include "sim_devices.hpp"
#include "sim_messages.hpp"

namespace porter::sim {
namespace {

using runtime::log_info;
using runtime::log_warn;

// CPU time of the whole process (every thread, user + system), s: what the steps cost whatever
// else the machine runs (wall-clock step times include preemption).
double process_cpu_s() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

World build_world(const SimConfig& c) {
  SceneLoadOptions options;
  options.seed = c.scene_seed;
  Scene scene = load_scene(c.scene_path, options);
  RobotModel robot = load_robot_model(c.robot_path);
  const std::string payload = c.payload_path == "scene" ? scene.payload_file : c.payload_path;
  if (!payload.empty()) robot = attach_payload(robot, load_payload(payload));
  if (c.arm_joints_rad) scene.start.q_rad = *c.arm_joints_rad;
  return World(std::move(scene), std::move(robot), c.history_s);
}

}  // namespace

SimProcess::SimProcess(const SimConfig& config, LcmBus& lcm) : config_(config), lcm_(lcm) {
  sim_ = std::make_unique<Simulator>(build_world(config_), SimParams{config_.step_s});
  World& world = sim_->world();
  bool base_moved = false;
  bool arm_moved = false;
  for (const BusConfig& bus : config_.buses) {
    const std::string spec = can::with_lcm_url(bus.can, config_.lcm_url);
    auto endpoint = can::open_can_bus(spec, "porter-sim");
    if (!endpoint->is_open()) {
      error_ = "bus '" + bus.name + "': " + endpoint->last_error();
      return;
    }
    sim_->add_bus(bus.name, endpoint.get());
    endpoints_.push_back(std::move(endpoint));
    for (const std::string& kind : bus.devices) {
      HostedDevice device = make_device(kind, config_, world.robot(), world.scene());
      if (!device.node) {
        error_ = "bus '" + bus.name + "': cannot build device '" + kind + "'";
        return;
      }
      if (device.base_source) {
        sim_->set_base_source(std::move(device.base_source));
        base_moved = true;
      }
      if (device.joint_source) {
        sim_->set_joint_source(std::move(device.joint_source));
        arm_moved = true;
      }
      sim_->add_node(bus.name, std::move(device.node));
    }
  }
  if (!base_moved) {
    sim_->set_base_source(std::make_unique<FixedBaseSource>(world.scene().start.base));
  }
  if (!arm_moved) {
    sim_->set_joint_source(std::make_unique<FixedJointSource>(world.scene().start.q_rad));
  }
  LcmBus& out = lcm_;
  const World* w = &sim_->world();
  sim_->add_sensor(std::make_unique<TruthSensor>(config_.truth_rate_hz, [&out, w](const RobotSample& s) {
    out.publish(channels::kSimTruth, to_truth_message(s, w->utime_at(s.t_s)));
  }));
  sim_->add_sensor(std::make_unique<LioPoseSensor>(
      config_.lio_rate_hz, config_.lio_noise, [&out, w](const PoseSample& p) {
        out.publish(channels::kLioPose, to_lio_message(p, w->utime_at(p.t_s)));
      }));
  if (config_.lidar.enabled) {
    std::string error;
    lidar_sender_ = livox::sim::RealtimeSender::open(config_.lidar.network, error);
    if (!lidar_sender_) {
      error_ = "lidar: " + error;
      return;
    }
    const double build0 = runtime::mono_s();
    livox::sim::RealtimeSender* sender = &*lidar_sender_;
    auto lidar = std::make_unique<LidarSensor>(
        config_.lidar.sensor, world,
        [sender](const std::vector<livox::sim::SimPacket>& packets) { sender->send(packets); });
    if (!lidar->ok()) {
      error_ = "lidar: " + lidar->error();
      return;
    }
    lidar_ = lidar.get();
    sim_->add_sensor(std::move(lidar));
    const livox::sim::Mid360SimParams& p = config_.lidar.sensor;
    char buf[160];
    std::snprintf(buf, sizeof buf, "%.0f points/s, %.0f Hz frames, %.0f..%.0f deg, range %.2f..%.1f m",
                  p.pattern.point_rate_hz, p.frame_rate_hz, p.pattern.elevation_min_deg,
                  p.pattern.elevation_max_deg, p.min_range_m, p.max_range_m);
    log_info(std::string("lidar: simulated MID-360, ") + buf + "; " +
             std::to_string(lidar_->lidar().scene().world_triangles()) + " world and " +
             std::to_string(lidar_->lidar().scene().robot_triangles()) +
             " robot triangles, built in " + runtime::format_ms(runtime::mono_s() - build0) +
             "; packets to " + config_.lidar.network.destination + " points :" +
             std::to_string(config_.lidar.network.point_port) + ", IMU :" +
             std::to_string(config_.lidar.network.imu_port));
  }
  log_info("world: scene '" + world.scene().name + "' (" +
           std::to_string(world.obstacles().size()) + " obstacles), robot '" +
           world.robot().name + "'" +
           (world.robot().payload_name.empty() ? std::string(", no payload")
                                               : ", payload '" + world.robot().payload_name + "'") +
           (arm_moved ? std::string() : "; the arm is held at fixed angles (no arm device)"));
}

int SimProcess::run(const std::function<bool()>& stop) {
  const auto sub = lcm_.subscribe(channels::kSimCommand, [this](const porter::sim_command_t& m) {
    SimCommand command;
    SimResult result = to_sim_command(m, command);
    if (result.ok) result = sim_->apply(command);
    const std::string head = "SIM_COMMAND #" + std::to_string(m.command_id) + " from '" +
                             m.source + "': ";
    if (result.ok) {
      log_info(head + result.message);
    } else {
      log_warn(head + "refused: " + result.message);
    }
  });
  if (sub == 0) log_warn("subscribing to SIM_COMMAND failed: faults on demand are unavailable");

  runtime::Heartbeat heartbeat(lcm_, runtime::process_name());
  runtime::PeriodicLoop loop(config_.step_s);
  const double t0 = runtime::mono_s();
  sim_->world().set_utime_origin(runtime::wall_utime() -
                                 static_cast<std::int64_t>(sim_->time_s() * 1e6));
  const double sim_t0 = sim_->time_s();
  double busy_total = 0.0;
  double window_wall0 = t0, window_sim0 = sim_t0, window_busy = 0.0, window_max = 0.0;
  std::uint64_t window_steps = 0;
  std::uint64_t window_rays = lidar_ ? lidar_->stats().rays : 0;
  const double cpu_t0 = process_cpu_s();
  double window_cpu0 = cpu_t0;
  log_info("running in real time: step " + runtime::format_ms(config_.step_s));
  while (!stop()) {
    loop.wait();
    lcm_.handle_pending();
    const double begin = runtime::mono_s();
    sim_->step_to(sim_t0 + (begin - t0));
    const double cost = runtime::mono_s() - begin;
    busy_total += cost;
    window_busy += cost;
    window_max = std::max(window_max, cost);
    ++window_steps;
    heartbeat.update(runtime::HeartbeatHealth::ok, "", loop.measured_rate_hz(),
                     static_cast<std::int64_t>(loop.overruns()));
    const double now = runtime::mono_s();
    if (now - window_wall0 >= config_.status_period_s) {
      const double wall = now - window_wall0;
      char buf[256];
      std::snprintf(buf, sizeof buf,
                    "sim time %.1f s, real-time factor %.4f, process CPU %.1f %% of one core, "
                    "stepping took %.1f %% of wall time (mean %.1f us, max %.2f ms per step), "
                    "loop overruns %llu",
                    sim_->time_s(), (sim_->time_s() - window_sim0) / wall,
                    100.0 * (process_cpu_s() - window_cpu0) / wall, 100.0 * window_busy / wall, 1e6 * window_busy / std::max<double>(1, window_steps),
                    1e3 * window_max, static_cast<unsigned long long>(loop.overruns()));
      std::string line = buf;
      for (const std::string& name : sim_->bus_names()) {
        const BusStats* s = sim_->bus_stats(name);
        line += "; bus " + name + ": in " + std::to_string(s->frames_in) + ", out " +
                std::to_string(s->frames_out) + ", dropped " + std::to_string(s->frames_dropped) +
                ", send failures " + std::to_string(s->send_failures);
      }
      if (lidar_) {
        const std::uint64_t rays = lidar_->stats().rays;
        std::snprintf(buf, sizeof buf,
                      "; lidar: %.0f rays/s, %llu packets sent, %llu not delivered, %llu "
                      "obstacle rebuilds",
                      static_cast<double>(rays - window_rays) / wall,
                      static_cast<unsigned long long>(lidar_sender_->sent()),
                      static_cast<unsigned long long>(lidar_sender_->send_failures()),
                      static_cast<unsigned long long>(lidar_->rebuilds()));
        line += buf;
        // A refused datagram (nobody listening yet) counts as not delivered without an error.
        if (!lidar_sender_->last_error().empty()) line += " (last error: " + lidar_sender_->last_error() + ")";
        window_rays = rays;
      }
      log_info(line);
      window_wall0 = now;
      window_cpu0 = process_cpu_s();
      window_sim0 = sim_->time_s();
      window_busy = 0.0;
      window_max = 0.0;
      window_steps = 0;
    }
  }
  const double wall = runtime::mono_s() - t0;
  rtf_ = wall > 0 ? (sim_->time_s() - sim_t0) / wall : 0.0;
  busy_ = wall > 0 ? busy_total / wall : 0.0;
  cpu_ = wall > 0 ? (process_cpu_s() - cpu_t0) / wall : 0.0;
  if (sub != 0) lcm_.unsubscribe(sub);
  return 0;
}

}  // namespace porter::sim
