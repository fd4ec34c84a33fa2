// porter-stack-probe: the integration tests' hands and eyes on a running stack.
//
//   porter-stack-probe --lcm-url URL watch OUT.jsonl
//       until SIGINT/SIGTERM, one JSON line per SIM_TRUTH (100 Hz), BASE_CMD, TRACKER_STATUS,
//       PLANNER_STATUS, TRAJECTORY, MAP_OCTOMAP and ESTOP message, each with the receive time
//       ("rx", µs, wall clock) and the message's own fields the tests judge.
//   porter-stack-probe --lcm-url URL add-box NAME CX CY CZ SX SY SZ YAW
//       SIM_COMMAND ADD_BOX (porter-sim adds a box to the world).
//   porter-stack-probe --lcm-url URL estop on|off
//       ESTOP active / released.
// exit codes: 0 done, 2 bad arguments, 4 LCM unavailable.

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "porter/channels.hpp"
#include "porter/lcm_bus.hpp"
#include "porter/runtime/clock.hpp"
#include "porter/runtime/stop.hpp"

namespace rt = porter::runtime;
using nlohmann::json;

namespace {

int usage() {
  std::fprintf(stderr,
               "usage: porter-stack-probe --lcm-url URL watch OUT.jsonl | add-box NAME CX CY CZ SX SY SZ YAW | "
               "estop on|off\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4 || std::string(argv[1]) != "--lcm-url") return usage();
  const std::string url = argv[2], cmd = argv[3];
  porter::LcmBus bus(url);
  if (!bus.good()) {
    std::fprintf(stderr, "porter-stack-probe: LCM unavailable at %s\n", url.c_str());
    return 4;
  }
  if (cmd == "add-box" && argc == 13) {
    porter::sim_command_t m{};
    m.utime = rt::wall_utime();
    m.command_id = 1;
    m.command = porter::sim_command_t::ADD_BOX;
    m.target = argv[4];
    double* v[] = {&m.center_x_m, &m.center_y_m, &m.center_z_m, &m.size_x_m, &m.size_y_m, &m.size_z_m, &m.yaw_rad};
    for (int i = 0; i < 7; ++i) *v[i] = std::atof(argv[5 + i]);
    m.source = "porter-stack-probe";
    bus.publish(porter::channels::kSimCommand, m);
    return 0;
  }
  if (cmd == "estop" && argc == 5) {
    const std::string on = argv[4];
    if (on != "on" && on != "off") return usage();
    porter::estop_t m{};
    m.utime = rt::wall_utime();
    m.active = on == "on";
    m.source = "porter-stack-probe";
    m.reason = "integration test";
    bus.publish(porter::channels::kEstop, m);
    return 0;
  }
  if (cmd != "watch" || argc != 5) return usage();
  std::ofstream out(argv[4]);
  if (!out) {
    std::fprintf(stderr, "porter-stack-probe: cannot write %s\n", argv[4]);
    return 2;
  }
  rt::install_stop_handlers();
  auto line = [&](json j) { out << j.dump() << '\n'; };
  bus.subscribe(porter::channels::kSimTruth, [&](const porter::robot_state_t& m) {
    line({{"ch", std::string(porter::channels::kSimTruth.name())}, {"rx", rt::wall_utime()}, {"utime", m.utime}, {"x", m.x_m}, {"y", m.y_m},
          {"yaw", m.yaw_rad}, {"v", m.v_mps}, {"w", m.omega_radps}, {"q", m.q_rad}});
  }, 200);
  bus.subscribe(porter::channels::kBaseCmd, [&](const porter::base_cmd_t& m) {
    line({{"ch", std::string(porter::channels::kBaseCmd.name())}, {"rx", rt::wall_utime()}, {"utime", m.utime}, {"enabled", m.enabled}, {"v", m.v_mps},
          {"w", m.omega_radps}});
  }, 200);
  bus.subscribe(porter::channels::kTrackerStatus, [&](const porter::tracker_status_t& m) {
    line({{"ch", std::string(porter::channels::kTrackerStatus.name())}, {"rx", rt::wall_utime()}, {"utime", m.utime}, {"state", m.state},
          {"message", m.message}});
  }, 50);
  bus.subscribe(porter::channels::kPlannerStatus, [&](const porter::planner_status_t& m) {
    line({{"ch", std::string(porter::channels::kPlannerStatus.name())}, {"rx", rt::wall_utime()}, {"utime", m.utime}, {"goal_id", m.goal_id},
          {"plan_id", m.plan_id}, {"state", m.state}, {"reason", m.failure_reason}, {"total_s", m.total_time_s}});
  }, 50);
  bus.subscribe(porter::channels::kTrajectory, [&](const porter::minco_trajectory_t& m) {
    double d = 0.0;
    for (double s : m.durations_s) d += s;
    line({{"ch", std::string(porter::channels::kTrajectory.name())}, {"rx", rt::wall_utime()}, {"utime", m.utime}, {"plan_id", m.plan_id},
          {"start_utime", m.start_utime}, {"duration_s", d}});
  }, 20);
  bus.subscribe(porter::channels::kMapOctomap, [&](const porter::octomap_t& m) {
    line({{"ch", std::string(porter::channels::kMapOctomap.name())}, {"rx", rt::wall_utime()}, {"utime", m.utime}, {"map_id", m.map_id},
          {"bytes", m.num_bytes}});
  }, 5);
  bus.subscribe(porter::channels::kEstop, [&](const porter::estop_t& m) {
    line({{"ch", std::string(porter::channels::kEstop.name())}, {"rx", rt::wall_utime()}, {"utime", m.utime}, {"active", m.active}});
  }, 5);
  while (!rt::stop_requested()) {
    bus.handle_timeout(50);
    out.flush();
  }
  return 0;
}
