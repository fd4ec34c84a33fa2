#include "porter/can/can_transport.hpp"

#include "porter/can/lcm_can_bus.hpp"
#include "porter/can/memory_bus.hpp"
#include "porter/can/slcan_bus.hpp"
#include "porter/can/socketcan_bus.hpp"
#include "porter/channels.hpp"

namespace porter::can {
namespace {

class FailedBus final : public CanBus {
 public:
  FailedBus(std::string spec, std::string reason)
      : spec_(std::move(spec)), reason_(std::move(reason)) {}
  CanStatus send(const CanFrame&) override { return CanStatus::closed; }
  CanStatus receive(CanFrame&, int) override { return CanStatus::closed; }
  std::string describe() const override { return spec_; }
  std::string last_error() const override { return reason_; }
  bool is_open() const override { return false; }

 private:
  std::string spec_, reason_;
};

std::unique_ptr<CanBus> open_lcm(const std::string& spec, const std::string& rest,
                                 const std::string& node_name) {
  const auto at = rest.find('@');
  const std::string channel = rest.substr(0, at);
  const std::string url = at == std::string::npos ? std::string() : rest.substr(at + 1);
  const channels::ChannelInfo* info = channels::find(channel);
  if (info == nullptr || info->type_name != "can_frame_t") {
    return make_failed_bus(spec, "CAN bus '" + spec + "': '" + channel +
                                     "' is not a CAN channel of the registry (CAN_BASE, CAN_ARM)");
  }
  auto bus = std::make_unique<LcmCanBus>(*info, url, node_name);
  return bus;
}

std::unique_ptr<CanBus> open_slcan(const std::string& spec, const std::string& rest) {
  SlcanOptions options;
  std::string error;
  if (!parse_slcan_target(rest, options, error)) {
    return make_failed_bus(spec, "CAN bus '" + spec + "': " + error);
  }
  return SlcanBus::open(options, spec);
}

}  // namespace

std::string with_lcm_url(const std::string& spec, const std::string& url) {
  if (url.empty() || spec.rfind("lcm:", 0) != 0 || spec.find('@') != std::string::npos) {
    return spec;
  }
  return spec + "@" + url;
}

std::unique_ptr<CanBus> make_failed_bus(const std::string& spec, const std::string& reason) {
  return std::make_unique<FailedBus>(spec, reason);
}

std::unique_ptr<CanBus> open_can_bus(const std::string& spec, const std::string& node_name) {
  const auto colon = spec.find(':');
  const std::string kind = spec.substr(0, colon);
  const std::string rest = colon == std::string::npos ? std::string() : spec.substr(colon + 1);
  if (colon == std::string::npos || rest.empty()) {
    return make_failed_bus(spec, "CAN bus '" + spec +
                                     "': expected TRANSPORT:TARGET (socketcan:IFACE, slcan:DEVICE@BITRATE, "
                                     "lcm:CHANNEL[@URL], memory:NAME)");
  }
  if (kind == "memory") return MemoryBus::open(rest);
  if (kind == "lcm") return open_lcm(spec, rest, node_name);
  if (kind == "socketcan") return SocketCanBus::open(rest);
  if (kind == "slcan") return open_slcan(spec, rest);
  return make_failed_bus(spec, "CAN bus '" + spec + "': unknown transport '" + kind +
                                   "' (expected socketcan, slcan, lcm or memory)");
}

}  // namespace porter::can
