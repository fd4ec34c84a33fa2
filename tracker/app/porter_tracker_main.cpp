// porter-tracker: the 100 Hz trajectory tracker. Reads ROBOT_STATE, TRAJECTORY and ESTOP;
// publishes BASE_CMD and ARM_CMD every period, TRACKER_STATUS at status_rate_hz (and on every
// state change) and HEARTBEAT at 1 Hz. The logic is porter::tracker::Tracker; this file wires it
// to LCM, runs the fixed-rate loop and logs.
//
// usage: porter-tracker [--config FILE] [--lcm-url URL] [--stats-out FILE]
//   --config FILE     tracker config (default: the shipped config/tracker/porter_tracker.yaml)
//   --lcm-url URL     LCM URL (default: $LCM_DEFAULT_URL, else LCM's default)
//   --stats-out FILE  at exit, write the loop's timing statistics there as JSON
// exit codes: 0 stopped by SIGINT/SIGTERM, 2 bad arguments, 3 bad config, 4 LCM unavailable.

#include <sched.h>

#include <cstdio>
#include <exception>
#include <fstream>
#include <string>

#include "loop_timing.hpp"
#include "porter/channels.hpp"
#include "porter/core/load_error.hpp"
#include "porter/lcm_bus.hpp"
#include "porter/runtime/clock.hpp"
#include "porter/runtime/heartbeat.hpp"
#include "porter/runtime/log.hpp"
#include "porter/runtime/periodic.hpp"
#include "porter/runtime/stop.hpp"
#include "tracker_config.hpp"
#include "tracker_messages.hpp"

namespace rt = porter::runtime;
using porter::tracker::TrackerState;

int main(int argc, char** argv) {
  rt::init_log(porter::tracker_app::kProcessName);
  std::string config_path = PORTER_DEFAULT_TRACKER_CONFIG, url, stats_out;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if ((a == "--config" || a == "--lcm-url" || a == "--stats-out") && i + 1 < argc) {
      (a == "--config" ? config_path : a == "--lcm-url" ? url : stats_out) = argv[++i];
    } else {
      std::fprintf(stderr, "usage: porter-tracker [--config FILE] [--lcm-url URL] "
                           "[--stats-out FILE]\n");
      return 2;
    }
  }
  porter::tracker_app::TrackerConfig config;
  try {
    config = porter::tracker_app::load_tracker_config(config_path);
  } catch (const std::exception& e) {
    rt::log_error(std::string("config: ") + e.what());
    return 3;
  }
  rt::install_stop_handlers();
  porter::LcmBus bus(url);
  if (!bus.good()) {
    rt::log_error("LCM unavailable at '" + url + "'");
    return 4;
  }
  porter::tracker::Tracker tracker(config.params);
  rt::log_info("config " + config.file + " (robot " + config.robot_file + "), " +
               std::to_string(static_cast<int>(config.rate_hz)) + " Hz, frame " +
               config.params.frame_id);

  std::uint64_t bad_states = 0;
  std::string last_state_error;
  bus.subscribe(porter::channels::kRobotState, [&](const porter::robot_state_t& msg) {
    auto s = porter::tracker_app::to_measured_state(msg, config.params.frame_id);
    if (s.state) return tracker.on_state(*s.state, rt::wall_utime());
    if (++bad_states == 1 || s.error != last_state_error) rt::log_warn("ignored: " + s.error);
    last_state_error = s.error;
  });
  bus.subscribe(porter::channels::kTrajectory, [&](const porter::minco_trajectory_t& msg) {
    auto c = porter::tracker_app::to_offer(msg);
    if (!c.offer) {
      tracker.on_invalid_trajectory(msg.plan_id, c.error);
      return rt::log_warn(tracker.last_refusal());
    }
    const double duration = c.offer->trajectory.total_duration_s();
    const double lead_s = static_cast<double>(msg.start_utime - rt::wall_utime()) * 1e-6;
    auto r = tracker.on_trajectory(std::move(*c.offer), rt::wall_utime());
    if (!r.accepted) return rt::log_warn(tracker.last_refusal());
    char b[160];
    std::snprintf(b, sizeof b, "plan %lld accepted: %d pieces, %.2f s, starts in %.3f s",
                  static_cast<long long>(msg.plan_id), msg.num_pieces, duration, lead_s);
    rt::log_info(b);
  });
  bus.subscribe(porter::channels::kEstop, [&](const porter::estop_t& msg) {
    const bool was = tracker.estop_latched();
    tracker.on_estop(msg.active, msg.source + ": " + msg.reason, rt::wall_utime());
    if (was != tracker.estop_latched()) {
      rt::log_warn(std::string(msg.active ? "ESTOP engaged by " : "ESTOP released by ") +
                   msg.source + (msg.reason.empty() ? "" : " (" + msg.reason + ")"));
    }
  });

  bool fifo = false;
  if (config.sched_fifo) {
    const std::string why = porter::tracker_app::enable_sched_fifo(config.sched_priority);
    fifo = sched_getscheduler(0) == SCHED_FIFO;
    if (why.empty()) {
      rt::log_info("SCHED_FIFO priority " + std::to_string(config.sched_priority) +
                   ", memory locked");
    } else {
      rt::log_warn(why + (fifo ? "" : "; running SCHED_OTHER"));
    }
  }

  rt::PeriodicLoop loop(1.0 / config.rate_hz);
  porter::tracker_app::LoopTiming timing(loop.period_s());
  rt::Heartbeat heartbeat(bus, porter::tracker_app::kProcessName);
  const auto status_every = static_cast<std::uint64_t>(config.rate_hz / config.status_rate_hz + 0.5);
  const auto stats_every = static_cast<std::uint64_t>(config.stats_log_period_s * config.rate_hz);
  const double start_s = rt::mono_s();
  while (!rt::stop_requested()) {
    loop.wait();
    timing.on_wake(rt::mono_ns());
    bus.handle_pending();
    const std::int64_t now = rt::wall_utime();
    const auto& out = tracker.step(now);
    bus.publish(porter::channels::kBaseCmd, porter::tracker_app::make_base_cmd(out, now));
    bus.publish(porter::channels::kArmCmd,
                porter::tracker_app::make_arm_cmd(out, config.arm_speed_pct, now));
    if (out.state_changed || loop.cycles() % status_every == 0) {
      porter::tracker_app::LoopFigures figures{timing.last_period_s(),
                                               timing.period_jitter().max_s(),
                                               static_cast<std::int64_t>(loop.overruns())};
      bus.publish(porter::channels::kTrackerStatus,
                  porter::tracker_app::make_status(out, tracker.last_refusal(), figures, now));
    }
    if (out.state_changed) {
      const std::string line = std::string("state ") + porter::tracker::to_string(out.state) +
                               (out.message.empty() ? "" : ": " + out.message) + " (plan " +
                               std::to_string(out.plan_id) + ")";
      out.state == TrackerState::tracking || out.state == TrackerState::finished ||
              out.state == TrackerState::idle
          ? rt::log_info(line)
          : rt::log_warn(line);
    }
    const bool ok = out.state != TrackerState::fault && out.state != TrackerState::stale_state;
    heartbeat.update(ok ? rt::HeartbeatHealth::ok : rt::HeartbeatHealth::warn,
                     ok ? "" : porter::tracker::to_string(out.state), loop.measured_rate_hz(),
                     static_cast<std::int64_t>(loop.overruns()));
    if (loop.cycles() % stats_every == 0) rt::log_info(describe(timing, loop));
    timing.on_work_done(rt::mono_ns());
  }
  // Leave the actuators with a disabled command rather than the last motion command.
  porter::tracker::TrackerOutput stopped;
  stopped.plan_id = tracker.output().plan_id;
  bus.publish(porter::channels::kBaseCmd, porter::tracker_app::make_base_cmd(stopped, rt::wall_utime()));
  bus.publish(porter::channels::kArmCmd,
              porter::tracker_app::make_arm_cmd(stopped, config.arm_speed_pct, rt::wall_utime()));
  rt::log_info("stopping; " + describe(timing, loop));
  if (!stats_out.empty()) {
    std::ofstream(stats_out) << porter::tracker_app::to_json(timing, loop, rt::mono_s() - start_s,
                                                             fifo);
  }
  return 0;
}
