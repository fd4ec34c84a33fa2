#include "porter/can/lcm_can_bus.hpp"

#include <algorithm>
#include <cctype>
#include <chrono>

namespace porter::can {
namespace {

std::int64_t now_utime() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// Channel CAN_XYZ -> bus name "xyz": the can_frame_t.bus field, for humans reading lcm-spy.
std::string bus_name_of(std::string_view channel) {
  std::string name(channel);
  if (name.rfind("CAN_", 0) == 0) name = name.substr(4);
  std::transform(name.begin(), name.end(), name.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return name;
}

}  // namespace

LcmCanBus::LcmCanBus(const channels::ChannelInfo& channel, const std::string& url,
                     std::string node_name, std::size_t queue_capacity)
    : channel_(channel.name, channel.type_name, channel.rate_hz, channel.owner,
               channel.description),
      node_name_(std::move(node_name)),
      bus_name_(bus_name_of(channel.name)),
      describe_("lcm:" + std::string(channel.name) + (url.empty() ? "" : "@" + url)),
      bus_(url),
      capacity_(std::max<std::size_t>(1, queue_capacity)) {
  if (!bus_.good()) {
    error_ = describe_ + ": LCM could not be opened" + (url.empty() ? "" : " at '" + url + "'");
    return;
  }
  subscribed_ = bus_.subscribe(channel_, [this](const porter::can_frame_t& m) { on_frame(m); },
                               static_cast<int>(std::min<std::size_t>(capacity_, 100000))) != 0;
  if (!subscribed_) error_ = describe_ + ": subscribing to the channel failed";
}

void LcmCanBus::on_frame(const porter::can_frame_t& msg) {
  if (msg.sender == node_name_) return;
  CanFrame frame;
  frame.extended = msg.extended;
  frame.rtr = msg.rtr;
  const std::uint32_t max_id = frame.extended ? 0x1FFFFFFFu : 0x7FFu;
  const bool id_ok = msg.id >= 0 && static_cast<std::uint32_t>(msg.id) <= max_id;
  if (!id_ok || msg.dlc < 0 || msg.dlc > 8 ||
      msg.data.size() != static_cast<std::size_t>(msg.dlc)) {
    ++malformed_;
    error_ = describe_ + ": dropped a malformed frame from '" + msg.sender + "'";
    return;
  }
  frame.id = static_cast<std::uint32_t>(msg.id);
  frame.dlc = static_cast<std::uint8_t>(msg.dlc);
  std::copy(msg.data.begin(), msg.data.end(), frame.data.begin());
  frame.utime = msg.utime;
  if (queue_.size() >= capacity_) {
    queue_.pop_front();
    ++dropped_;
  }
  queue_.push_back(frame);
}

CanStatus LcmCanBus::send(const CanFrame& frame) {
  if (!is_open()) return CanStatus::closed;
  if (!frame.valid()) return CanStatus::invalid_frame;
  porter::can_frame_t msg;
  msg.utime = frame.utime != 0 ? frame.utime : now_utime();
  msg.bus = bus_name_;
  msg.sender = node_name_;
  msg.id = static_cast<std::int32_t>(frame.id);
  msg.extended = frame.extended;
  msg.rtr = frame.rtr;
  msg.dlc = static_cast<std::int8_t>(frame.dlc);
  msg.data.assign(frame.data.begin(), frame.data.begin() + frame.dlc);
  if (!bus_.publish(channel_, msg)) {
    error_ = describe_ + ": LCM publish failed";
    return CanStatus::io_error;
  }
  return CanStatus::ok;
}

CanStatus LcmCanBus::receive(CanFrame& frame, int timeout_ms) {
  if (!is_open()) return CanStatus::closed;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(std::max(0, timeout_ms));
  while (queue_.empty()) {
    int wait_ms = -1;
    if (timeout_ms >= 0) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
                            deadline - std::chrono::steady_clock::now())
                            .count();
      if (left <= 0) {
        // Non-blocking passes so a poll (timeout 0) still sees what is already waiting, past
        // this node's own frames (skipped by on_frame) that may come first.
        while (queue_.empty()) {
          const int handled = bus_.handle_timeout(0);
          if (handled < 0) {
            error_ = describe_ + ": LCM handle failed";
            return CanStatus::io_error;
          }
          if (handled == 0) return CanStatus::timeout;
        }
        break;
      }
      wait_ms = static_cast<int>(left);
    }
    const int status = wait_ms < 0 ? bus_.handle() : bus_.handle_timeout(wait_ms);
    if (status < 0) {
      error_ = describe_ + ": LCM handle failed";
      return CanStatus::io_error;
    }
  }
  frame = queue_.front();
  queue_.pop_front();
  return CanStatus::ok;
}

}  // namespace porter::can
