#include "porter/runtime/heartbeat.hpp"

#include <unistd.h>

#include "porter/runtime/clock.hpp"

namespace porter::runtime {
namespace {
std::string host_name() {
  char name[256] = {0};
  if (::gethostname(name, sizeof name - 1) != 0) return "unknown";
  return name;
}
}  // namespace

Heartbeat::Heartbeat(LcmBus& bus, std::string process, double period_s)
    : bus_(bus),
      process_(std::move(process)),
      host_(host_name()),
      start_utime_(wall_utime()),
      period_ns_(static_cast<std::int64_t>(period_s * 1e9)) {}

bool Heartbeat::update(HeartbeatHealth health, const std::string& status, double loop_rate_hz,
                       std::int64_t loop_overruns) {
  const std::int64_t now = mono_ns();
  if (!first_ && health == last_health_ && now - last_ns_ < period_ns_) return false;
  porter::process_heartbeat_t msg;
  msg.utime = wall_utime();
  msg.process = process_;
  msg.host = host_;
  msg.pid = static_cast<std::int32_t>(::getpid());
  msg.start_utime = start_utime_;
  msg.health = static_cast<std::int8_t>(health);
  msg.status = status;
  msg.loop_rate_hz = loop_rate_hz;
  msg.loop_overruns = loop_overruns;
  msg.dropped_datagrams = static_cast<std::int64_t>(LcmBus::process_decode_failures());
  first_ = false;
  last_ns_ = now;
  last_health_ = health;
  if (!bus_.publish(channels::kHeartbeat, msg)) return false;
  ++published_;
  return true;
}

}  // namespace porter::runtime
