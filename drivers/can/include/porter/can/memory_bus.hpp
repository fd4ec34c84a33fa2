#pragma once
// In-memory CAN buses for unit tests: every endpoint opened on the same name is a node on the
// same bus. A frame sent by one endpoint is queued for every other endpoint of that name, in
// send order; the sender does not receive its own frames, as on a real bus.
//
//   auto driver = MemoryBus::open("base");
//   auto firmware = MemoryBus::open("base");
//   driver->send(frame);  firmware->receive(out, 0) == CanStatus::ok
//
// Each endpoint's queue is bounded (default 4096 frames); when full, the oldest frame is dropped
// and counted (dropped()), like a controller's receive FIFO overflowing.
//
// Thread-safety: endpoints may be used from different threads; one endpoint follows the CanBus
// contract (one sender thread and one receiver thread at a time).

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

#include "porter/can/can_bus.hpp"

namespace porter::can {

class MemoryBus final : public CanBus {
 public:
  /// A new endpoint on the bus `name` (created on first use, shared process-wide).
  static std::unique_ptr<MemoryBus> open(const std::string& name,
                                         std::size_t queue_capacity = 4096);
  ~MemoryBus() override;

  CanStatus send(const CanFrame& frame) override;
  CanStatus receive(CanFrame& frame, int timeout_ms) override;
  std::string describe() const override;
  std::string last_error() const override;
  bool is_open() const override;

  /// Cuts this endpoint off the bus (a dropped cable, for fault tests): sends fail with
  /// io_error and nothing is received until reconnect().
  void disconnect();
  void reconnect();

  /// Frames this endpoint lost because its queue was full.
  std::uint64_t dropped() const;

  struct Shared;  // the bus: its endpoints and their queues (defined in memory_bus.cpp)
  struct Endpoint;

 private:
  MemoryBus(std::shared_ptr<Shared> bus, std::shared_ptr<Endpoint> endpoint, std::string name);
  std::shared_ptr<Shared> bus_;
  std::shared_ptr<Endpoint> endpoint_;
  std::string name_;
};

}  // namespace porter::can
