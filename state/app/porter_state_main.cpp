// porter-state: fuses BASE_STATE, LIO_POSE and ARM_STATE into ROBOT_STATE at rate_hz, with the
// ESTOP state passed through; HEARTBEAT at 1 Hz. The fusion is porter::state::StateFusion; this
// file wires it to LCM and logs what changes (inputs going stale and returning, the pose source,
// LIO jumps, odometry restarts).
//
// usage: porter-state [--config FILE] [--lcm-url URL]
// exit codes: 0 stopped by SIGINT/SIGTERM, 2 bad arguments, 3 bad config, 4 LCM unavailable.

#include <cstdio>
#include <exception>
#include <string>
#include <string_view>

#include "porter/channels.hpp"
#include "porter/lcm_bus.hpp"
#include "porter/runtime/clock.hpp"
#include "porter/runtime/heartbeat.hpp"
#include "porter/runtime/log.hpp"
#include "porter/runtime/periodic.hpp"
#include "porter/runtime/stop.hpp"
#include "state_config.hpp"
#include "state_messages.hpp"

namespace rt = porter::runtime;
namespace st = porter::state;

namespace {

// Logs an input's freshness changes ("BASE_STATE stale" / "BASE_STATE fresh again").
struct Freshness {
  std::string_view name;
  bool known = false;
  bool fresh = false;
  void update(bool now_fresh, bool ever) {
    if (!ever) return;
    if (known && now_fresh == fresh) return;
    if (known || now_fresh) {
      now_fresh ? rt::log_info(std::string(name) + (known ? " fresh again" : " received"))
                : rt::log_warn(std::string(name) + " stale");
    }
    known = true;
    fresh = now_fresh;
  }
};

char buffer[256];

}  // namespace

int main(int argc, char** argv) {
  rt::init_log(porter::state_app::kProcessName);
  std::string config_path = PORTER_DEFAULT_STATE_CONFIG, url;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if ((a == "--config" || a == "--lcm-url") && i + 1 < argc) {
      (a == "--config" ? config_path : url) = argv[++i];
    } else {
      std::fprintf(stderr, "usage: porter-state [--config FILE] [--lcm-url URL]\n");
      return 2;
    }
  }
  porter::state_app::StateConfig config;
  try {
    config = porter::state_app::load_state_config(config_path);
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
  st::StateFusion fusion(config.fusion);
  rt::log_info("config " + config.file + ", " + std::to_string(static_cast<int>(config.rate_hz)) + " Hz, frame " +
               config.frame_id + (config.fusion.use_lio ? ", LIO used when present" : ", no LIO"));

  std::string last_error;
  auto reject = [&](const std::string& error) {
    if (error != last_error) rt::log_warn("ignored: " + error);
    last_error = error;
  };
  bus.subscribe(porter::channels::kBaseState, [&](const porter::base_state_t& msg) {
    auto c = porter::state_app::to_odometry(msg);
    if (!c.value) return reject(c.error);
    const auto u = fusion.on_odometry(*c.value, rt::wall_utime());
    if (u.first) rt::log_info("odometry anchored");
    if (u.reset) rt::log_warn("odometry restarted (pose step or stamp backwards); re-anchored");
  });
  bus.subscribe(porter::channels::kLioPose, [&](const porter::pose_t& msg) {
    auto c = porter::state_app::to_lio(msg, config.frame_id, config.lio_child_frame_id);
    if (!c.value) return reject(c.error);
    const auto u = fusion.on_lio(*c.value, rt::wall_utime());
    if (!u.used) return reject("LIO_POSE: " + u.ignored_reason);
    if (u.jumped) {
      std::snprintf(buffer, sizeof buffer, "LIO pose jumped %.3f m, %.3f rad from the propagated "
                    "pose (taken; %llu jumps so far)", u.jump_m, u.jump_rad,
                    static_cast<unsigned long long>(fusion.counters().lio_jumps));
      rt::log_warn(buffer);
    }
  });
  bus.subscribe(porter::channels::kArmState, [&](const porter::arm_state_t& msg) {
    auto c = porter::state_app::to_arm(msg);
    if (!c.value) return reject(c.error);
    fusion.on_arm(*c.value, rt::wall_utime());
  });
  bus.subscribe(porter::channels::kEstop, [&](const porter::estop_t& msg) {
    fusion.on_estop(msg.active);
  });

  rt::PeriodicLoop loop(1.0 / config.rate_hz);
  rt::Heartbeat heartbeat(bus, porter::state_app::kProcessName);
  Freshness base{porter::channels::kBaseState.name()}, arm{porter::channels::kArmState.name()},
      pose{"pose"};
  st::PoseSource source = st::PoseSource::none;
  bool estop = false;
  const auto stats_every = static_cast<std::uint64_t>(60.0 * config.rate_hz);
  while (!rt::stop_requested()) {
    loop.wait();
    bus.handle_pending();
    const st::FusedState fused = fusion.output(rt::wall_utime());
    bus.publish(porter::channels::kRobotState,
                porter::state_app::make_robot_state(fused, config.frame_id));
    base.update(fused.base_valid, fused.base_utime != 0);
    arm.update(fused.arm_valid, fused.has_arm);
    pose.update(fused.pose_valid, fused.pose_source != st::PoseSource::none);
    if (fused.pose_source != source) {
      rt::log_info(std::string("pose source: ") + st::to_string(fused.pose_source));
      source = fused.pose_source;
    }
    if (fused.estop_active != estop) {
      estop = fused.estop_active;
      estop ? rt::log_warn("e-stop engaged") : rt::log_info("e-stop released");
    }
    const bool ok = fused.base_valid && fused.pose_valid && fused.arm_valid;
    heartbeat.update(ok ? rt::HeartbeatHealth::ok : rt::HeartbeatHealth::warn,
                     ok ? "" : std::string("stale:") + (fused.base_valid ? "" : " base") +
                                   (fused.arm_valid ? "" : " arm") +
                                   (fused.pose_valid ? "" : " pose"),
                     loop.measured_rate_hz(), static_cast<std::int64_t>(loop.overruns()));
    if (loop.cycles() % stats_every == 0) {
      const auto& c = fusion.counters();
      std::snprintf(buffer, sizeof buffer,
                    "inputs: odometry %llu (restarts %llu), LIO %llu (jumps %llu, ignored %llu), "
                    "arm %llu; wake-up lateness p99 %.0f us, overruns %llu",
                    static_cast<unsigned long long>(c.odometry),
                    static_cast<unsigned long long>(c.odometry_resets),
                    static_cast<unsigned long long>(c.lio),
                    static_cast<unsigned long long>(c.lio_jumps),
                    static_cast<unsigned long long>(c.lio_ignored),
                    static_cast<unsigned long long>(c.arm), loop.lateness().quantile_s(0.99) * 1e6,
                    static_cast<unsigned long long>(loop.overruns()));
      rt::log_info(buffer);
    }
  }
  rt::log_info("stopping");
  return 0;
}
