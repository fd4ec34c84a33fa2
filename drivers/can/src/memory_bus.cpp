#include "porter/can/memory_bus.hpp"

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <map>
#include <mutex>
#include <vector>

namespace porter::can {

struct MemoryBus::Endpoint {
  std::deque<CanFrame> queue;
  std::size_t capacity = 0;
  std::uint64_t dropped = 0;
  bool connected = true;
};

struct MemoryBus::Shared {
  std::mutex mutex;
  std::condition_variable arrived;
  std::vector<std::weak_ptr<Endpoint>> endpoints;
};

namespace {
std::mutex& registry_mutex() {
  static std::mutex m;
  return m;
}
std::map<std::string, std::weak_ptr<MemoryBus::Shared>>& registry() {
  static std::map<std::string, std::weak_ptr<MemoryBus::Shared>> r;
  return r;
}
}  // namespace

std::unique_ptr<MemoryBus> MemoryBus::open(const std::string& name, std::size_t queue_capacity) {
  std::shared_ptr<Shared> bus;
  {
    std::lock_guard<std::mutex> lock(registry_mutex());
    bus = registry()[name].lock();
    if (!bus) {
      bus = std::make_shared<Shared>();
      registry()[name] = bus;
    }
  }
  auto endpoint = std::make_shared<Endpoint>();
  endpoint->capacity = std::max<std::size_t>(1, queue_capacity);
  {
    std::lock_guard<std::mutex> lock(bus->mutex);
    bus->endpoints.push_back(endpoint);
  }
  return std::unique_ptr<MemoryBus>(new MemoryBus(std::move(bus), std::move(endpoint), name));
}

MemoryBus::MemoryBus(std::shared_ptr<Shared> bus, std::shared_ptr<Endpoint> endpoint,
                     std::string name)
    : bus_(std::move(bus)), endpoint_(std::move(endpoint)), name_(std::move(name)) {}

MemoryBus::~MemoryBus() {
  std::lock_guard<std::mutex> lock(bus_->mutex);
  auto& eps = bus_->endpoints;
  eps.erase(std::remove_if(eps.begin(), eps.end(),
                           [&](const std::weak_ptr<Endpoint>& w) {
                             auto e = w.lock();
                             return !e || e == endpoint_;
                           }),
            eps.end());
}

CanStatus MemoryBus::send(const CanFrame& frame) {
  if (!frame.valid()) return CanStatus::invalid_frame;
  {
    std::lock_guard<std::mutex> lock(bus_->mutex);
    if (!endpoint_->connected) return CanStatus::io_error;
    for (const auto& weak : bus_->endpoints) {
      auto other = weak.lock();
      if (!other || other == endpoint_ || !other->connected) continue;
      if (other->queue.size() >= other->capacity) {
        other->queue.pop_front();
        ++other->dropped;
      }
      other->queue.push_back(frame);
    }
  }
  bus_->arrived.notify_all();
  return CanStatus::ok;
}

CanStatus MemoryBus::receive(CanFrame& frame, int timeout_ms) {
  std::unique_lock<std::mutex> lock(bus_->mutex);
  auto ready = [&] { return !endpoint_->queue.empty() && endpoint_->connected; };
  if (!ready()) {
    if (timeout_ms == 0) return CanStatus::timeout;
    if (timeout_ms < 0) {
      bus_->arrived.wait(lock, ready);
    } else if (!bus_->arrived.wait_for(lock, std::chrono::milliseconds(timeout_ms), ready)) {
      return CanStatus::timeout;
    }
  }
  frame = endpoint_->queue.front();
  endpoint_->queue.pop_front();
  return CanStatus::ok;
}

std::string MemoryBus::describe() const { return "memory:" + name_; }

std::string MemoryBus::last_error() const {
  std::lock_guard<std::mutex> lock(bus_->mutex);
  return endpoint_->connected ? std::string() : "memory:" + name_ + ": disconnected";
}

bool MemoryBus::is_open() const {
  std::lock_guard<std::mutex> lock(bus_->mutex);
  return endpoint_->connected;
}

void MemoryBus::disconnect() {
  std::lock_guard<std::mutex> lock(bus_->mutex);
  endpoint_->connected = false;
  endpoint_->queue.clear();
}

void MemoryBus::reconnect() {
  {
    std::lock_guard<std::mutex> lock(bus_->mutex);
    endpoint_->connected = true;
  }
  bus_->arrived.notify_all();
}

std::uint64_t MemoryBus::dropped() const {
  std::lock_guard<std::mutex> lock(bus_->mutex);
  return endpoint_->dropped;
}

}  // namespace porter::can
