// porter-arm: the Agilex Piper driver process. Wires ArmDriver (porter/piper/arm_driver.hpp) to
// the arm's CAN bus and to LCM: ARM_CMD and ESTOP in, ARM_STATE (every loop cycle) and
// HEARTBEAT out. On SIGINT/SIGTERM it disables the arm and exits 0 once the arm confirms (or
// the shutdown timeout passes).
//
//   porter-arm [--config config/drivers/porter_arm.yaml]
//
// Exit codes: 0 clean shutdown, 1 LCM unusable, 2 bad arguments or config.
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "arm_messages.hpp"
#include "porter/piper/faults.hpp"
#include "porter/can/can_transport.hpp"
#include "porter/channels.hpp"
#include "porter/core/load_error.hpp"
#include "porter/lcm_bus.hpp"
#include "porter/piper/arm_driver.hpp"
#include "porter/runtime/clock.hpp"
#include "porter/runtime/heartbeat.hpp"
#include "porter/runtime/log.hpp"
#include "porter/runtime/periodic.hpp"
#include "porter/runtime/stop.hpp"
#include "porter_arm_params.hpp"

namespace rt = porter::runtime;
using porter::piper::ArmDriver;

namespace {

constexpr const char* kProcess = "porter-arm";
constexpr int kMaxFramesPerCycle = 4096;  // bounds one cycle's work whatever the bus delivers

void log_events(ArmDriver& driver) {
  for (const porter::piper::ArmEvent& e : driver.take_events()) {
    switch (e.level) {
      case porter::piper::ArmEvent::Level::info: rt::log_info(e.text); break;
      case porter::piper::ArmEvent::Level::warn: rt::log_warn(e.text); break;
      case porter::piper::ArmEvent::Level::error: rt::log_error(e.text); break;
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  rt::init_log(kProcess);
  std::string config = "config/drivers/porter_arm.yaml";
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--config") == 0 && i + 1 < argc) {
      config = argv[++i];
    } else {
      rt::log_error(std::string("unknown argument '") + argv[i] + "'; usage: porter-arm [--config PATH]");
      return 2;
    }
  }
  porter::piper::PorterArmParams params;
  try {
    params = porter::piper::load_porter_arm_params(config);
  } catch (const porter::LoadError& e) {
    rt::log_error(std::string("config: ") + e.what());
    return 2;
  }
  rt::install_stop_handlers();
  char rate[32];
  std::snprintf(rate, sizeof rate, "%g", params.loop_rate_hz);
  rt::log_info("config " + config + ": bus " + params.can_bus + ", loop " + rate + " Hz, joint limits from " +
               params.robot_yaml);

  porter::LcmBus lcm(params.lcm_url);
  if (!lcm.good()) {
    rt::log_error("LCM could not be opened at '" + params.lcm_url + "'");
    return 1;
  }
  ArmDriver driver(params.driver);
  std::string last_reject;
  lcm.subscribe(porter::channels::kArmCmd, [&](const porter::arm_cmd_t& msg) {
    std::string why;
    const auto cmd = porter::piper::to_command(msg, why);
    if (!cmd || !driver.on_command(*cmd, rt::mono_s())) {
      if (why.empty()) why = "non-finite value";
      if (why != last_reject) rt::log_warn("ARM_CMD from '" + msg.source + "' rejected: " + why);
      last_reject = why;
      return;
    }
    last_reject.clear();
  });
  lcm.subscribe(porter::channels::kEstop, [&](const porter::estop_t& msg) {
    driver.on_estop(msg.active, msg.source + ": " + msg.reason, rt::mono_s());
  });
  rt::Heartbeat heartbeat(lcm, kProcess);

  const auto t_open = rt::mono_s();
  std::unique_ptr<porter::can::CanBus> bus = porter::can::open_can_bus(params.can_bus, kProcess);
  if (bus->is_open()) {
    rt::log_info("bus " + bus->describe() + " open (" + rt::format_ms(rt::mono_s() - t_open) + ")");
  } else {
    rt::log_error("bus: " + bus->last_error() + "; retrying every " + rt::format_ms(params.bus_reopen_period_s));
  }
  double next_reopen_s = rt::mono_s() + params.bus_reopen_period_s;

  rt::PeriodicLoop loop(1.0 / params.loop_rate_hz);
  std::vector<porter::can::CanFrame> out;
  porter::can::CanStatus last_rx = porter::can::CanStatus::ok;
  porter::can::CanStatus last_tx = porter::can::CanStatus::ok;
  bool shutting_down = false;
  while (!driver.finished()) {
    loop.wait();
    if (rt::stop_requested() && !shutting_down) {
      shutting_down = true;
      driver.request_shutdown("SIGINT/SIGTERM", rt::mono_s());
    }
    if (!bus->is_open() && rt::mono_s() >= next_reopen_s) {
      bus = porter::can::open_can_bus(params.can_bus, kProcess);
      next_reopen_s = rt::mono_s() + params.bus_reopen_period_s;
      if (bus->is_open()) rt::log_info("bus " + bus->describe() + " reopened");
    }
    porter::can::CanFrame frame;
    for (int n = 0; n < kMaxFramesPerCycle; ++n) {
      const porter::can::CanStatus s = bus->receive(frame, 0);
      if (s == porter::can::CanStatus::ok) {
        driver.on_frame(frame, rt::mono_s());
        continue;
      }
      if (s != porter::can::CanStatus::timeout && s != last_rx) {
        rt::log_warn(std::string("bus receive: ") + porter::can::to_string(s) + ": " + bus->last_error());
      }
      if (s != porter::can::CanStatus::timeout) last_rx = s;
      break;
    }
    lcm.handle_pending();

    const double t = rt::mono_s();
    out.clear();
    driver.step(t, out);
    for (const porter::can::CanFrame& f : out) {
      const porter::can::CanStatus s = bus->send(f);
      if (s != last_tx) {
        if (s == porter::can::CanStatus::ok) rt::log_info("bus send: ok again");
        else rt::log_warn(std::string("bus send: ") + porter::can::to_string(s) + ": " + bus->last_error());
        last_tx = s;
      }
    }

    const porter::piper::ArmDriverStatus status = driver.status(t);
    const porter::piper::ArmFeedback& fb = driver.feedback();
    const std::int64_t utime = porter::piper::arm_state_utime(fb, rt::wall_utime(), rt::mono_s());
    lcm.publish(porter::channels::kArmState, porter::piper::to_arm_state(fb, status, utime));
    log_events(driver);

    rt::HeartbeatHealth health = rt::HeartbeatHealth::ok;
    if (!status.link_ok || status.fault) health = rt::HeartbeatHealth::error;
    else if (status.phase != porter::piper::ArmPhase::active || status.holding) health = rt::HeartbeatHealth::warn;
    std::string text = porter::piper::to_string(status.phase);
    if (status.fault) text += "; faults: " + porter::piper::join_names(status.faults);
    heartbeat.update(health, text, loop.measured_rate_hz(), static_cast<std::int64_t>(loop.overruns()));
  }
  log_events(driver);
  const auto& c = driver.counters();
  rt::log_info("stopped: " + std::to_string(c.frames_received) + " frames received (" +
               std::to_string(c.frames_malformed) + " malformed), " + std::to_string(c.frames_sent) + " sent, " +
               std::to_string(c.commands_accepted) + " commands; loop " + std::to_string(loop.cycles()) +
               " cycles, " + std::to_string(loop.overruns()) + " overruns, p99 wake-up lateness " +
               rt::format_ms(loop.lateness().quantile_s(0.99)));
  return 0;
}
