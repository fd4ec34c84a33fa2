#include "base_node.hpp"

#include <chrono>
#include <cstdio>
#include <cstring>

#include <pthread.h>
#include <sched.h>
#include <string>
#include <vector>

#include "base_messages.hpp"
#include "porter/channels.hpp"
#include "porter/runtime/clock.hpp"
#include "porter/runtime/heartbeat.hpp"
#include "porter/runtime/log.hpp"

namespace porter::scout_mini {
namespace {

using runtime::log_error;
using runtime::log_info;
using runtime::log_warn;

// One log line per kind of trouble per period, with the number of repeats it stood for.
class RateLimitedLog {
 public:
  explicit RateLimitedLog(double period_s) : period_s_(period_s) {}
  void warn(const std::string& text) {
    const double now = runtime::mono_s();
    ++count_;
    if (now - last_s_ < period_s_) return;
    log_warn(count_ > 1 ? text + " (" + std::to_string(count_) + " times since the last line)"
                        : text);
    count_ = 0;
    last_s_ = now;
  }

 private:
  double period_s_;
  double last_s_ = -1e300;
  std::uint64_t count_ = 0;
};

std::string format(const char* fmt, double a, double b, double c, double d) {
  char buf[256];
  std::snprintf(buf, sizeof buf, fmt, a, b, c, d);
  return buf;
}

}  // namespace

BaseNode::BaseNode(const BaseNodeConfig& config, std::unique_ptr<can::CanBus> bus, LcmBus& lcm)
    : config_(config), bus_(std::move(bus)), lcm_(lcm), driver_(config.driver) {}

BaseNode::~BaseNode() {
  rx_stop_ = true;
  if (rx_thread_.joinable()) rx_thread_.join();
  if (lcm_thread_.joinable()) lcm_thread_.join();
}

void BaseNode::lcm_loop() {
  RateLimitedLog lcm_log(5.0);
  while (!rx_stop_.load()) {
    if (lcm_.handle_timeout(50) < 0) {
      lcm_log.warn("LCM handle failed");
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  }
}

void BaseNode::receive_loop() {
  RateLimitedLog controller(5.0);
  RateLimitedLog transport(5.0);
  can::CanFrame frame;
  while (!rx_stop_.load()) {
    const can::CanStatus status = bus_->receive(frame, 20);
    switch (status) {
      case can::CanStatus::ok: {
        std::lock_guard<std::mutex> lock(mutex_);
        driver_.on_frame(frame, runtime::mono_s());
        break;
      }
      case can::CanStatus::timeout:
        break;
      case can::CanStatus::error_frame:
      case can::CanStatus::bus_off:
        controller.warn(std::string("CAN controller: ") + can::to_string(status) + ": " +
                        bus_->last_error());
        break;
      case can::CanStatus::closed:
        bus_closed_ = true;
        return;
      default:
        transport.warn(std::string("CAN receive: ") + can::to_string(status) + ": " +
                       bus_->last_error());
        break;
    }
  }
}

int BaseNode::run(const std::function<bool()>& stop) {
  if (!bus_ || !bus_->is_open()) {
    log_error("CAN bus is not open: " + (bus_ ? bus_->last_error() : std::string("none")));
    return 1;
  }
  const auto cmd_sub = lcm_.subscribe(channels::kBaseCmd, [this](const porter::base_cmd_t& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    driver_.on_command(to_command(msg), runtime::mono_s());
  });
  const auto estop_sub = lcm_.subscribe(channels::kEstop, [this](const porter::estop_t& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    driver_.on_estop(msg.active, msg.source + ": " + msg.reason, runtime::mono_s());
  });
  if (cmd_sub == 0 || estop_sub == 0) {
    log_error("subscribing to BASE_CMD / ESTOP failed (LCM not usable)");
    return 1;
  }
  rx_stop_ = false;
  rx_thread_ = std::thread([this] { receive_loop(); });
  lcm_thread_ = std::thread([this] { lcm_loop(); });
  if (config_.realtime_priority > 0) {
    sched_param param{};
    param.sched_priority = config_.realtime_priority;
    const int err = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
    if (err == 0) {
      log_info("command loop at SCHED_FIFO priority " + std::to_string(config_.realtime_priority));
    } else {
      log_warn("cannot run the command loop at SCHED_FIFO priority " +
               std::to_string(config_.realtime_priority) + ": " + std::strerror(err) +
               " (needs CAP_SYS_NICE or an rtprio limit); running at normal priority");
    }
  }

  runtime::Heartbeat heartbeat(lcm_, runtime::process_name());
  runtime::PeriodicLoop loop(config_.driver.command_period_s);
  RateLimitedLog send_log(5.0);
  std::vector<can::CanFrame> frames;
  std::vector<DriverEvent> events;
  double last_stats_s = runtime::mono_s();
  std::uint64_t sent = 0;
  std::uint64_t send_failures = 0;
  int exit_code = 0;
  log_info("running: 0x111 every " + runtime::format_ms(config_.driver.command_period_s) +
           " on " + bus_->describe() + ", BASE_CMD stale after " +
           runtime::format_ms(config_.driver.command_stale_s));

  while (!stop()) {
    loop.wait();
    if (bus_closed_.load()) {
      log_error("CAN bus closed: " + bus_->last_error() + "; exiting so a supervisor restarts "
                "porter-base");
      exit_code = 1;
      break;
    }
    frames.clear();
    BaseFeedback feedback;
    std::string problem;
    std::uint64_t decoded = 0;
    std::uint64_t malformed = 0;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      driver_.tick(runtime::mono_s(), frames);
      events = driver_.take_events();
      feedback = driver_.feedback();
      problem = driver_.problem();
      decoded = driver_.frames_decoded();
      malformed = driver_.frames_malformed();
    }
    for (const can::CanFrame& f : frames) {
      const can::CanStatus st = bus_->send(f);
      if (st == can::CanStatus::ok) {
        ++sent;
      } else {
        ++send_failures;
        send_log.warn(std::string("CAN send of ") + can::to_string(f) + " failed: " +
                      can::to_string(st) + ": " + bus_->last_error());
      }
    }
    for (const DriverEvent& e : events) {
      if (e.level == EventLevel::error) {
        log_error(e.message);
      } else if (e.level == EventLevel::warn) {
        log_warn(e.message);
      } else {
        log_info(e.message);
      }
    }
    const std::int64_t utime =
        feedback.feedback_utime != 0 ? feedback.feedback_utime : runtime::wall_utime();
    lcm_.publish(channels::kBaseState, to_base_state(feedback, utime));
    const runtime::HeartbeatHealth health =
        (feedback.refused_v1 || !feedback.link_ok) ? runtime::HeartbeatHealth::error
        : problem.empty()                          ? runtime::HeartbeatHealth::ok
                                                   : runtime::HeartbeatHealth::warn;
    heartbeat.update(health, problem, loop.measured_rate_hz(),
                     static_cast<std::int64_t>(loop.overruns()));
    const double now = runtime::mono_s();
    if (now - last_stats_s >= config_.stats_period_s) {
      const auto& late = loop.lateness();
      log_info(format("command loop: %.1f Hz, wake-up lateness mean %.3f ms, p99 %.3f ms, "
                      "max %.3f ms",
                      loop.measured_rate_hz(), late.mean_s() * 1e3, late.quantile_s(0.99) * 1e3,
                      late.max_s() * 1e3) +
               "; overruns " + std::to_string(loop.overruns()) + ", frames sent " +
               std::to_string(sent) + ", send failures " + std::to_string(send_failures) +
               ", feedback decoded " + std::to_string(decoded) + ", malformed " +
               std::to_string(malformed));
      last_stats_s = now;
    }
  }
  lateness_ = loop.lateness();
  cycles_ = loop.cycles();

  frames.clear();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    driver_.stop_frames(frames);
  }
  for (const can::CanFrame& f : frames) bus_->send(f);
  if (!frames.empty()) log_info("stopping: sent a zero 0x111");
  rx_stop_ = true;
  if (rx_thread_.joinable()) rx_thread_.join();
  if (lcm_thread_.joinable()) lcm_thread_.join();
  lcm_.unsubscribe(cmd_sub);
  lcm_.unsubscribe(estop_sub);
  return exit_code;
}

}  // namespace porter::scout_mini
