#pragma once
// A CAN bus carried over LCM: every node publishes its frames as can_frame_t on one channel
// (CAN_BASE or CAN_ARM) and receives everyone else's (frames whose `sender` is this node's name
// are skipped). Simulated runs use it so lcm-spy shows and lcm-logger records the raw frames.
//
// Thread-safety: per the CanBus contract; send() publishes (LCM's publish is thread-safe) while
// receive() runs the LCM handler on the receiving thread.

#include <cstdint>
#include <deque>
#include <memory>
#include <string>

#include "porter/can/can_bus.hpp"
#include "porter/channels.hpp"
#include "porter/lcm_bus.hpp"

namespace porter::can {

class LcmCanBus final : public CanBus {
 public:
  /// `channel` must be a registry channel carrying can_frame_t; `url` "" = $LCM_DEFAULT_URL.
  LcmCanBus(const channels::ChannelInfo& channel, const std::string& url, std::string node_name,
            std::size_t queue_capacity = 4096);

  CanStatus send(const CanFrame& frame) override;
  CanStatus receive(CanFrame& frame, int timeout_ms) override;
  std::string describe() const override { return describe_; }
  std::string last_error() const override { return error_; }
  bool is_open() const override { return bus_.good() && subscribed_; }

  /// Received messages that were not valid CAN frames (bad dlc, ID out of range), dropped.
  std::uint64_t malformed() const { return malformed_; }
  /// Frames lost because the receive queue was full.
  std::uint64_t dropped() const { return dropped_; }

 private:
  void on_frame(const porter::can_frame_t& msg);

  channels::Channel<porter::can_frame_t> channel_;
  std::string node_name_;
  std::string bus_name_;
  std::string describe_;
  LcmBus bus_;
  bool subscribed_ = false;
  std::deque<CanFrame> queue_;
  std::size_t capacity_;
  std::uint64_t malformed_ = 0;
  std::uint64_t dropped_ = 0;
  std::string error_;
};

}  // namespace porter::can
