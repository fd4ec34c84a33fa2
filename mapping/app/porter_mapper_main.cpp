// porter-mapper: LIDAR_POINTS + ROBOT_STATE -> MAP_OCTOMAP (OctoMap binary), HEARTBEAT.
//
//   porter-mapper [--config config/mapping/porter_mapper.yaml] [--payload FILE|none]
//
// --payload replaces the config's payload (the self-filter must know what the gripper holds).
//
// Two threads: the main thread receives (LCM) and publishes the heartbeat; a worker integrates
// clouds and publishes maps. Exit codes: 0 after SIGINT/SIGTERM, 1 when LCM cannot be opened,
// 2 on a config or model error.
#include <poll.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <string>
#include <mutex>
#include <thread>

#include "mapper_node.hpp"
#include "mapper_params.hpp"
#include "porter/core/load_error.hpp"
#include "porter/core/payload.hpp"
#include "porter/core/payload_loader.hpp"
#include "porter/core/robot_loader.hpp"
#include "porter/lcm_bus.hpp"
#include "porter/runtime/clock.hpp"
#include "porter/runtime/heartbeat.hpp"
#include "porter/runtime/log.hpp"
#include "porter/runtime/stop.hpp"

namespace rt = porter::runtime;
namespace pm = porter::mapping;

namespace {

std::string ms(double s) { return rt::format_ms(s); }

struct Timing {  // per log period, touched by the worker only
  double filter_max_s = 0, integrate_max_s = 0, encode_max_s = 0, latency_max_s = 0, busy_s = 0;
  std::uint64_t clouds = 0, points = 0;
  std::uint64_t new_surfaces = 0, shadowed = 0;  // voxels (map.new_surface_shadow_m)
};

}  // namespace

int main(int argc, char** argv) {
  rt::init_log("porter-mapper");
  std::string config_path = PORTER_DEFAULT_MAPPER_CONFIG;
  std::string payload_override;  // --payload: the payload carried this run (self-filter), "none" = none
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--config" && i + 1 < argc) {
      config_path = argv[++i];
    } else if (arg == "--payload" && i + 1 < argc) {
      payload_override = argv[++i];
    } else {
      rt::log_error("usage: porter-mapper [--config FILE] [--payload FILE|none]");
      return 2;
    }
  }
  pm::app::MapperConfig cfg;
  porter::RobotModel robot;
  const double t_load = rt::mono_s();
  try {
    cfg = pm::app::load_mapper_config(config_path);
    if (!payload_override.empty()) cfg.payload_yaml = payload_override == "none" ? "" : payload_override;
    robot = porter::load_robot_model(cfg.robot_yaml);
    if (!cfg.payload_yaml.empty()) robot = porter::attach_payload(robot, porter::load_payload(cfg.payload_yaml));
  } catch (const porter::LoadError& e) {
    rt::log_error(std::string("config: ") + e.what());
    return 2;
  }
  rt::install_stop_handlers();
  porter::LcmBus bus(cfg.lcm_url);
  if (!bus.good()) {
    rt::log_error("cannot open LCM at '" + cfg.lcm_url + "'");
    return 1;
  }
  pm::app::MapperNode node(cfg, robot);
  const pm::MapperParams& p = cfg.mapper;
  const pm::SelfFilter* self = node.mapper().self_filter();
  rt::log_info("config " + config_path + "; robot " + robot.name + (robot.payload_name.empty() ? "" : " with payload " + robot.payload_name) +
               "; map " + std::to_string(p.map.dims.x()) + "x" + std::to_string(p.map.dims.y()) + "x" +
               std::to_string(p.map.dims.z()) + " voxels of " + std::to_string(p.map.resolution_m) + " m; range " +
               std::to_string(p.min_range_m) + ".." + std::to_string(p.max_range_m) + " m; self-filter " +
               (self ? "margin " + std::to_string(p.self.margin_m) + " m, " + std::to_string(self->cells()) + " cells" : std::string("off")) +
               "; maps at " + std::to_string(cfg.publish_rate_hz) + " Hz; ready in " + ms(rt::mono_s() - t_load));

  // LCM drops a complete message, uncounted, when its subscription already holds this many
  // undelivered ones; the heartbeat could only count such a cloud as lost upstream, and which
  // clouds it hits depends on when this thread gets the CPU. The node's queue
  // (queue.max_clouds) is where clouds are dropped, and counted: these queues hold every burst
  // seen (porter-sim catching up on a loaded machine sends up to 26 clouds within 0.3 s and
  // seconds of states at once; the LCM queue of 4 clouds lost 3 clouds of such a burst in a
  // replay, docs/stack.md "Replay"). A cloud is ~0.4 MB: 100 of them ~40 MB at most.
  constexpr int kStateReceiveQueue = 5000;
  constexpr int kCloudReceiveQueue = 100;
  bus.subscribe(porter::channels::kRobotState, [&](const porter::robot_state_t& m) { node.on_state(m); },
                kStateReceiveQueue);
  bus.subscribe(porter::channels::kLidarPoints,
                [&](const porter::point_cloud_t& m) { node.on_cloud(m, rt::mono_ns()); }, kCloudReceiveQueue);

  std::atomic<std::uint64_t> publish_failures{0};
  std::mutex timing_mutex;
  Timing timing;
  std::thread worker([&] {
    porter::octomap_t map_msg;
    while (!rt::stop_requested()) {
      pm::app::StepResult r;
      const std::int64_t t0 = rt::mono_ns();
      if (!node.step(t0, 50'000'000, r)) continue;
      const std::int64_t t1 = rt::mono_ns();
      double encode_s = 0.0, latency_s = 0.0;
      if (r.map_due) {
        node.make_map(map_msg);
        if (!bus.publish(porter::channels::kMapOctomap, map_msg)) ++publish_failures;
        const std::int64_t t2 = rt::mono_ns();
        encode_s = (t2 - t1) * 1e-9;
        latency_s = (t2 - r.received_ns) * 1e-9;
      }
      std::lock_guard<std::mutex> lock(timing_mutex);
      timing.filter_max_s = std::max(timing.filter_max_s, r.report.filter.filter_s);
      timing.integrate_max_s = std::max(timing.integrate_max_s, r.report.integrate_s);
      timing.encode_max_s = std::max(timing.encode_max_s, encode_s);
      timing.latency_max_s = std::max(timing.latency_max_s, latency_s);
      timing.busy_s += (rt::mono_ns() - t0) * 1e-9;
      ++timing.clouds;
      timing.points += r.report.filter.points_in;
      timing.new_surfaces += r.report.integrate.new_surfaces;
      timing.shadowed += r.report.integrate.shadowed;
    }
  });

  rt::Heartbeat heartbeat(bus, "porter-mapper");
  double last_log = rt::mono_s();
  std::uint64_t busy_seen = 0, dropped_seen = 0, no_state_seen = 0;
  double last_no_state_s = -1e9;  // when a cloud was last dropped for want of a covering state
  while (!rt::stop_requested()) {
    pollfd fds[2] = {{bus.fileno(), POLLIN, 0}, {rt::stop_fd(), POLLIN, 0}};
    ::poll(fds, 2, 100);
    if (fds[0].revents & POLLIN) bus.handle_pending();  // every message waiting, then the status
    const pm::app::MapperCounters c = node.counters();
    std::string status = "clouds " + std::to_string(c.clouds_processed) + "/" + std::to_string(c.clouds_received) +
                         ", arrived while busy " + std::to_string(c.arrived_while_busy) + ", dropped " +
                         std::to_string(c.dropped_queue_full) + ", lost upstream " + std::to_string(c.lost_upstream) +
                         ", rejected " + std::to_string(c.rejected) + ", dropped without state " +
                         std::to_string(c.dropped_no_state) + ", states without arm " +
                         std::to_string(c.states_without_arm) + ", maps " + std::to_string(c.maps);
    if (publish_failures > 0) status += ", publish failures " + std::to_string(publish_failures.load());
    auto health = rt::HeartbeatHealth::ok;
    if (c.clouds_received == 0 || c.states_received == 0) health = rt::HeartbeatHealth::warn;
    if (c.dropped_no_state != no_state_seen) {
      rt::log_warn("clouds dropped without a ROBOT_STATE covering them (base and arm) by " + ms(cfg.state_wait_s) +
                   " (state time) after their last point, or with the queue full waiting for one: " + std::to_string(c.dropped_no_state) + " (ROBOT_STATEs without arm: " +
                   std::to_string(c.states_without_arm) + ")");
      no_state_seen = c.dropped_no_state;
      last_no_state_s = rt::mono_s();
    }
    // A drop for want of state warns for one status period (the first clouds of a run come
    // before porter-state has the arm); queue drops and rejections warn for good.
    const bool recent_no_state = rt::mono_s() - last_no_state_s < cfg.status_log_period_s;
    if (c.dropped_queue_full > 0 || c.rejected > 0 || recent_no_state) health = rt::HeartbeatHealth::warn;
    heartbeat.update(health, status);
    if (c.arrived_while_busy != busy_seen || c.dropped_queue_full != dropped_seen) {
      rt::log_warn("clouds arrived while busy: " + std::to_string(c.arrived_while_busy) + ", dropped: " +
                   std::to_string(c.dropped_queue_full));
      busy_seen = c.arrived_while_busy;
      dropped_seen = c.dropped_queue_full;
    }
    const double now = rt::mono_s();
    if (now - last_log >= cfg.status_log_period_s) {
      Timing t;
      {
        std::lock_guard<std::mutex> lock(timing_mutex);
        std::swap(t, timing);
      }
      const double dt = now - last_log;
      char line[512];
      std::snprintf(line, sizeof line,
                    "%.1f clouds/s, %.0f points/s, worker busy %.1f %%; max filter %s, integrate %s, map %s, "
                    "cloud-to-map %s; new surfaces %llu voxels, shadowed behind and below them %llu; ",
                    t.clouds / dt, t.points / dt, 100.0 * t.busy_s / dt, ms(t.filter_max_s).c_str(),
                    ms(t.integrate_max_s).c_str(), ms(t.encode_max_s).c_str(), ms(t.latency_max_s).c_str(),
                    static_cast<unsigned long long>(t.new_surfaces), static_cast<unsigned long long>(t.shadowed));
      rt::log_info(std::string(line) + status + (c.last_reject.empty() ? "" : "; last rejected: " + c.last_reject));
      last_log = now;
    }
  }
  worker.join();
  const pm::app::MapperCounters c = node.counters();
  rt::log_info("stopping: " + std::to_string(c.clouds_processed) + " clouds processed of " +
               std::to_string(c.clouds_received) + ", " + std::to_string(c.arrived_while_busy) + " arrived while busy, " +
               std::to_string(c.dropped_queue_full) + " dropped, " + std::to_string(c.dropped_no_state) +
               " dropped without state, " + std::to_string(c.maps) + " maps");
  return 0;
}
