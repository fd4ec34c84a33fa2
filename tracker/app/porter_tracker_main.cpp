// porter-tracker: the 100 Hz trajectory tracker. Reads ROBOT_STATE, TRAJECTORY and ESTOP;
// publishes BASE_CMD and ARM_CMD every period, TRACKER_STATUS at status_rate_hz (and on every
// state change) and HEARTBEAT at 1 Hz. The logic is porter::tracker::Tracker; this file wires it
// to LCM, runs the fixed-rate loop and logs.
//
// Three threads (loop_io.hpp): an LCM receive thread decodes and converts the inputs and queues
// them; the timed thread wakes on absolute deadlines, applies the queued inputs, steps the
// tracker and sends BASE_CMD and ARM_CMD itself on an LCM instance of its own (send only, so it
// shares no lock with the receive side); a publisher thread sends TRACKER_STATUS and HEARTBEAT
// and writes the log lines the timed thread queues. The timed thread never waits for another
// thread, never reads a socket and never writes the log.
//
// usage: porter-tracker [--config FILE] [--lcm-url URL] [--stats-out FILE]
//   --config FILE     tracker config (default: the shipped config/tracker/porter_tracker.yaml)
//   --lcm-url URL     LCM URL (default: $LCM_DEFAULT_URL, else LCM's default)
//   --stats-out FILE  at exit, write the loop's timing statistics there as JSON
// exit codes: 0 stopped by SIGINT/SIGTERM, 2 bad arguments, 3 bad config, 4 LCM unavailable.

#include <poll.h>
#include <sched.h>
#include <semaphore.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <exception>
#include <fstream>
#include <string>
#include <thread>

#include "loop_io.hpp"
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
namespace app = porter::tracker_app;
using porter::tracker::TrackerState;

namespace {
constexpr std::size_t kInputSlots = 128;   // > 1 s of inputs at 100 Hz ROBOT_STATE
constexpr std::size_t kReportSlots = 16;   // reports the publisher may lag behind

// Waits for `sem` at most 100 ms (so a stop is seen).
void wait_briefly(sem_t& sem) {
  timespec deadline{};
  clock_gettime(CLOCK_MONOTONIC, &deadline);
  deadline.tv_nsec += 100'000'000;
  if (deadline.tv_nsec >= 1'000'000'000) {
    deadline.tv_nsec -= 1'000'000'000;
    ++deadline.tv_sec;
  }
  while (sem_clockwait(&sem, CLOCK_MONOTONIC, &deadline) != 0 && errno == EINTR) {
  }
}
}  // namespace

int main(int argc, char** argv) {
  rt::init_log(app::kProcessName);
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
  app::TrackerConfig config;
  try {
    config = app::load_tracker_config(config_path);
  } catch (const std::exception& e) {
    rt::log_error(std::string("config: ") + e.what());
    return 3;
  }
  rt::install_stop_handlers();
  porter::LcmBus bus(url);          // receive thread (subscriptions) and publisher thread
  porter::LcmBus command_bus(url);  // timed thread: BASE_CMD and ARM_CMD, never subscribed
  if (!bus.good() || !command_bus.good()) {
    rt::log_error("LCM unavailable at '" + url + "'");
    return 4;
  }
  porter::tracker::Tracker tracker(config.params);
  rt::log_info("config " + config.file + " (robot " + config.robot_file + "), " +
               std::to_string(static_cast<int>(config.rate_hz)) + " Hz, frame " +
               config.params.frame_id);

  // Receive thread -> timed thread. The callbacks run on the receive thread; a full ring (the
  // timed thread stopped draining) holds the receive thread back, nothing is dropped.
  app::SpscRing<app::InputEvent> inputs(kInputSlots);
  auto queue_input = [&](app::InputEvent&& event) {
    app::InputEvent* slot = nullptr;
    while ((slot = inputs.slot_to_fill()) == nullptr && !rt::stop_requested()) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    if (slot == nullptr) return;
    *slot = std::move(event);
    inputs.push_filled();
  };
  std::uint64_t bad_states = 0;
  std::string last_state_error;
  bus.subscribe(porter::channels::kRobotState, [&](const porter::robot_state_t& msg) {
    auto s = app::to_measured_state(msg, config.params.frame_id);
    if (s.state) return queue_input(app::StateInput{*s.state, rt::wall_utime()});
    if (++bad_states == 1 || s.error != last_state_error) rt::log_warn("ignored: " + s.error);
    last_state_error = s.error;
  });
  bus.subscribe(porter::channels::kTrajectory, [&](const porter::minco_trajectory_t& msg) {
    const std::int64_t received = rt::wall_utime();
    auto c = app::to_offer(msg);
    if (!c.offer) return queue_input(app::InvalidTrajectoryInput{msg.plan_id, c.error});
    queue_input(app::TrajectoryInput{std::move(*c.offer), received});
  });
  bus.subscribe(porter::channels::kEstop, [&](const porter::estop_t& msg) {
    queue_input(app::EstopInput{msg.active != 0, msg.source, msg.reason, rt::wall_utime()});
  });

  bool fifo = false;
  if (config.sched_fifo) {
    const std::string why = app::enable_sched_fifo(config.sched_priority);
    fifo = sched_getscheduler(0) == SCHED_FIFO;
    if (why.empty()) {
      rt::log_info("SCHED_FIFO priority " + std::to_string(config.sched_priority) +
                   " (I/O threads " + std::to_string(app::io_priority(config.sched_priority)) +
                   "), memory locked");
    } else {
      rt::log_warn(why + (fifo ? "" : "; running SCHED_OTHER"));
    }
  }
  app::prepare_timed_thread();

  // The I/O threads run just below the timed thread when it is SCHED_FIFO, else as it does. (LCM's
  // own udpm receive thread, started by the first subscribe above, stays SCHED_OTHER as before:
  // it reads every datagram of the multicast group, point clouds included.)
  auto io_thread_setup = [&] {
    if (fifo) app::set_thread_fifo(app::io_priority(config.sched_priority));
  };
  std::thread receiver([&] {
    io_thread_setup();
    pollfd fds[2] = {{bus.fileno(), POLLIN, 0}, {rt::stop_fd(), POLLIN, 0}};
    while (!rt::stop_requested()) {
      if (::poll(fds, 2, 100) > 0 && (fds[0].revents & POLLIN)) bus.handle_pending();
    }
  });

  // Timed thread -> publisher thread.
  app::SpscRing<app::CycleReport> reports(kReportSlots);
  sem_t reports_ready;
  sem_init(&reports_ready, 0, 0);
  std::atomic<bool> loop_done{false};
  rt::Heartbeat heartbeat(bus, app::kProcessName);
  std::thread publisher([&] {
    io_thread_setup();
    for (;;) {
      app::CycleReport* r = reports.front();
      if (r == nullptr) {
        if (loop_done.load()) break;
        wait_briefly(reports_ready);
        continue;
      }
      if (r->send_status) {
        bus.publish(porter::channels::kTrackerStatus,
                    app::make_status(r->out, r->last_refusal, r->figures, r->utime));
      }
      for (const auto& line : r->log) rt::log(line.level, line.text);
      heartbeat.update(r->health,
                       r->health == rt::HeartbeatHealth::ok ? "" : porter::tracker::to_string(r->state),
                       r->loop_rate_hz, r->overruns);
      reports.pop();
    }
  });

  rt::PeriodicLoop loop(1.0 / config.rate_hz);
  app::LoopTiming timing(loop.period_s());
  rt::LatenessStats command_latency(0.05);  // wake-up to BASE_CMD and ARM_CMD sent
  app::CycleReport unqueued;  // filled instead of a slot while the ring is full
  std::uint64_t lost_reports = 0, reported_cycle = 0;
  auto reported_health = rt::HeartbeatHealth::ok;
  const auto status_every = static_cast<std::uint64_t>(config.rate_hz / config.status_rate_hz + 0.5);
  const auto stats_every = std::max<std::uint64_t>(1, static_cast<std::uint64_t>(config.stats_log_period_s * config.rate_hz + 0.5));
  // A report at least every 0.1 s, so the publisher's heartbeat is never more than that late.
  const auto report_every = std::max<std::uint64_t>(1, static_cast<std::uint64_t>(config.rate_hz / 10.0));
  const double start_s = rt::mono_s();
  while (!rt::stop_requested()) {
    loop.wait();
    const std::int64_t wake_ns = rt::mono_ns();
    timing.on_wake(wake_ns);
    app::CycleReport* slot = reports.slot_to_fill();
    app::CycleReport& r = slot != nullptr ? *slot : unqueued;
    r.log.clear();
    // At most one ring's worth per period, so a flood of inputs cannot hold the step back.
    for (std::size_t n = 0; n < inputs.capacity(); ++n) {
      app::InputEvent* e = inputs.front();
      if (e == nullptr) break;
      app::apply_input(tracker, *e, r.log);
      inputs.pop();
    }
    const std::int64_t now = rt::wall_utime();
    const auto& out = tracker.step(now);
    command_bus.publish(porter::channels::kBaseCmd, app::make_base_cmd(out, now));
    command_bus.publish(porter::channels::kArmCmd,
                        app::make_arm_cmd(out, config.arm_speed_pct, now));
    command_latency.add(static_cast<double>(rt::mono_ns() - wake_ns) * 1e-9);

    r.utime = now;
    r.send_status = out.state_changed || loop.cycles() % status_every == 0;
    if (r.send_status) {
      r.out = out;
      r.last_refusal = tracker.last_refusal();
      r.figures = {timing.last_period_s(), timing.period_jitter().max_s(),
                   static_cast<std::int64_t>(loop.overruns())};
    }
    if (out.state_changed) r.log.push_back(app::state_change_line(out));
    const bool ok = out.state != TrackerState::fault && out.state != TrackerState::stale_state;
    r.state = out.state;
    r.health = ok ? rt::HeartbeatHealth::ok : rt::HeartbeatHealth::warn;
    r.loop_rate_hz = loop.measured_rate_hz();
    r.overruns = static_cast<std::int64_t>(loop.overruns());
    if (loop.cycles() % stats_every == 0) {
      r.log.push_back({rt::LogLevel::info, describe(timing, loop)});
    }
    if (r.send_status || !r.log.empty() || r.health != reported_health ||
        loop.cycles() - reported_cycle >= report_every) {
      if (slot == nullptr) {
        ++lost_reports;
      } else {
        reports.push_filled();
        sem_post(&reports_ready);
        reported_health = r.health;
        reported_cycle = loop.cycles();
      }
    }
    timing.on_work_done(rt::mono_ns());
  }
  loop_done = true;
  sem_post(&reports_ready);
  publisher.join();
  receiver.join();
  sem_destroy(&reports_ready);
  // Leave the actuators with a disabled command rather than the last motion command.
  porter::tracker::TrackerOutput stopped;
  stopped.plan_id = tracker.output().plan_id;
  command_bus.publish(porter::channels::kBaseCmd, app::make_base_cmd(stopped, rt::wall_utime()));
  command_bus.publish(porter::channels::kArmCmd,
                      app::make_arm_cmd(stopped, config.arm_speed_pct, rt::wall_utime()));
  if (lost_reports > 0) {
    rt::log_warn(std::to_string(lost_reports) + " status reports lost: the publisher thread was " +
                 std::to_string(kReportSlots) + " reports behind");
  }
  rt::log_info("stopping; " + describe(timing, loop) + "; " +
               app::describe_command_latency(command_latency));
  if (!stats_out.empty()) {
    std::ofstream(stats_out) << app::to_json(timing, loop, command_latency,
                                             rt::mono_s() - start_s, fifo);
  }
  return 0;
}
