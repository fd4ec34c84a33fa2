// porter-planner: the planner daemon. Reads PLAN_GOAL, ROBOT_STATE, MAP_OCTOMAP, PAYLOAD;
// publishes TRAJECTORY, PLANNER_STATUS and HEARTBEAT (1 Hz). Plans on a worker thread
// (planner_node.hpp); this file loads the config, opens LCM and handles messages until stopped.
//
// usage: porter-planner [--config FILE] [--lcm-url URL] [--payload ID] [--clock wall|messages]
//   --config FILE  planner daemon config (default: config/planner/porter_planner.yaml of the
//                  config directory found at run time, porter/pipeline/config_dir.hpp)
//   --lcm-url URL  LCM URL (default: $LCM_DEFAULT_URL, else LCM's default)
//   --payload ID   the payload carried at start: a key of the config's payloads, or none
//                  (default: the config's payload)
//   --clock C      wall (default): now is the wall clock; messages: now follows ROBOT_STATE's
//                  stamps (message_clock.hpp), for a recorded log played back (scripts/replay)
// exit codes: 0 stopped by SIGINT/SIGTERM, 2 bad arguments, 3 bad config, 4 LCM unavailable.

#include <cstdio>
#include <exception>
#include <functional>
#include <string>

#include "message_clock.hpp"
#include "planner_config.hpp"
#include "planner_node.hpp"
#include "porter/channels.hpp"
#include "porter/lcm_bus.hpp"
#include "porter/pipeline/config_dir.hpp"
#include "porter/runtime/clock.hpp"
#include "porter/runtime/heartbeat.hpp"
#include "porter/runtime/log.hpp"
#include "porter/runtime/stop.hpp"

namespace rt = porter::runtime;

int main(int argc, char** argv) {
  rt::init_log(porter::planner_app::kProcessName);
  std::string config_path, url, payload, clock = "wall";
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if ((a == "--config" || a == "--lcm-url" || a == "--payload" || a == "--clock") && i + 1 < argc) {
      (a == "--config" ? config_path : a == "--lcm-url" ? url : a == "--payload" ? payload : clock) = argv[++i];
    } else {
      clock.clear();
      break;
    }
  }
  if (clock != "wall" && clock != "messages") {
    std::fprintf(stderr, "usage: porter-planner [--config FILE] [--lcm-url URL] [--payload ID] [--clock wall|messages]\n");
    return 2;
  }
  if (config_path.empty()) {
    const std::string dir = porter::pipeline::find_config_dir();
    if (dir.empty()) {
      rt::log_error("cannot find the config directory (./config, or config/ above the executable): give --config");
      return 3;
    }
    config_path = dir + "/planner/porter_planner.yaml";
  }
  rt::install_stop_handlers();
  porter::planner_app::PlannerConfig config;
  try {
    config = porter::planner_app::load_planner_config(config_path);
  } catch (const std::exception& e) {
    rt::log_error(std::string("config: ") + e.what());
    return 3;
  }
  if (!payload.empty()) {
    if (payload != "none" && config.payloads.count(payload) == 0) {
      rt::log_error("--payload " + payload + ": not a payload of " + config.file);
      return 2;
    }
    config.payload_id = payload;
  }
  porter::LcmBus bus(url);
  if (!bus.good()) {
    rt::log_error("LCM unavailable at '" + url + "'");
    return 4;
  }
  rt::log_info("config " + config.file + " (robot " + config.robot_file + ", settings " + config.settings_dir +
               "), map resolution " + std::to_string(config.map.resolution_m) + " m, hand-off lead " +
               rt::format_ms(config.loop.handoff.lead_s));
  // Subscribed before the node so a state's stamp is taken before the node reads the clock.
  porter::planner_app::MessageClock message_clock;
  std::function<std::int64_t()> now = rt::wall_utime;
  if (clock == "messages") {
    bus.subscribe(porter::channels::kRobotState, [&](const porter::robot_state_t& m) { message_clock.observe(m.utime); });
    now = [&message_clock] { return message_clock.now(); };
    rt::log_info("clock: ROBOT_STATE stamps (played back log)");
  }
  std::unique_ptr<porter::planner_app::PlannerNode> node;
  try {
    node = std::make_unique<porter::planner_app::PlannerNode>(bus, config, now);
  } catch (const std::exception& e) {
    rt::log_error(std::string("planner: ") + e.what());
    return 3;
  }
  node->start();
  rt::Heartbeat heartbeat(bus, porter::planner_app::kProcessName);
  while (!rt::stop_requested()) {
    bus.handle_timeout(100);
    heartbeat.update(rt::HeartbeatHealth::ok, node->idle() ? "idle" : "planning");
  }
  node->stop();
  const auto s = node->stats();
  rt::log_info("stopping; " + std::to_string(s.maps_received) + " maps (" + std::to_string(s.maps_dropped) +
               " superseded, " + std::to_string(s.maps_refused) + " refused), " + std::to_string(s.goals_received) +
               " goals, " + std::to_string(s.trajectories) + " trajectories published");
  return 0;
}
