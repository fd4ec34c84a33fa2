#include "porter/sim/simulator.hpp"

#include <cmath>

namespace porter::sim {
namespace {

// Bounded drain per bus and call, so a flooding peer cannot stall the simulation loop.
constexpr int kMaxInboundPerStep = 20000;

SimResult ok(std::string message) { return {true, std::move(message)}; }
SimResult refused(std::string message) { return {false, std::move(message)}; }

std::string hex(std::uint32_t v) {
  static const char* digits = "0123456789ABCDEF";
  std::string s;
  do {
    s.insert(s.begin(), digits[v & 0xF]);
    v >>= 4;
  } while (v != 0);
  return "0x" + s;
}

}  // namespace

const char* to_string(SimCommand::Kind kind) {
  switch (kind) {
    case SimCommand::Kind::drop_bus: return "drop_bus";
    case SimCommand::Kind::restore_bus: return "restore_bus";
    case SimCommand::Kind::stop_stream: return "stop_stream";
    case SimCommand::Kind::resume_stream: return "resume_stream";
    case SimCommand::Kind::raise_error: return "raise_error";
    case SimCommand::Kind::clear_errors: return "clear_errors";
    case SimCommand::Kind::power_cycle: return "power_cycle";
    case SimCommand::Kind::add_box: return "add_box";
    case SimCommand::Kind::remove_obstacle: return "remove_obstacle";
  }
  return "unknown";
}

Simulator::Simulator(World world, SimParams params) : world_(std::move(world)), params_(params) {
  if (!(params_.step_s > 0) || !std::isfinite(params_.step_s)) params_.step_s = 0.001;
}

Simulator::Bus* Simulator::find_bus(const std::string& name) {
  for (Bus& b : buses_) {
    if (b.name == name) return &b;
  }
  return nullptr;
}

bool Simulator::add_bus(const std::string& name, can::CanBus* endpoint) {
  if (name.empty() || find_bus(name) != nullptr) return false;
  Bus bus;
  bus.name = name;
  bus.endpoint = endpoint;
  buses_.push_back(std::move(bus));
  return true;
}

can::SimulatedNode* Simulator::add_node(const std::string& bus_name,
                                        std::unique_ptr<can::SimulatedNode> node) {
  Bus* bus = find_bus(bus_name);
  if (bus == nullptr || node == nullptr || this->node(node->name()) != nullptr) return nullptr;
  bus->nodes.push_back(std::move(node));
  return bus->nodes.back().get();
}

can::SimulatedNode* Simulator::node(const std::string& device) const {
  for (const Bus& b : buses_) {
    for (const auto& n : b.nodes) {
      if (n->name() == device) return n.get();
    }
  }
  return nullptr;
}

std::vector<std::string> Simulator::bus_names() const {
  std::vector<std::string> names;
  for (const Bus& b : buses_) names.push_back(b.name);
  return names;
}

const BusStats* Simulator::bus_stats(const std::string& name) const {
  for (const Bus& b : buses_) {
    if (b.name == name) return &b.stats;
  }
  return nullptr;
}

bool Simulator::inject(const std::string& bus_name, const can::CanFrame& frame) {
  Bus* bus = find_bus(bus_name);
  if (bus == nullptr) return false;
  if (bus->dropped) {
    ++bus->stats.frames_dropped;
    return true;
  }
  if (tap_) tap_(bus->name, frame, false);
  for (auto& n : bus->nodes) n->receive(frame, t_s_);
  return true;
}

void Simulator::deliver_inbound() {
  for (Bus& bus : buses_) {
    if (bus.endpoint == nullptr) continue;
    can::CanFrame frame;
    for (int i = 0; i < kMaxInboundPerStep; ++i) {
      const can::CanStatus status = bus.endpoint->receive(frame, 0);
      if (status == can::CanStatus::error_frame || status == can::CanStatus::bus_off) continue;
      if (status != can::CanStatus::ok) break;  // timeout, closed, transport error
      ++bus.stats.frames_in;
      if (bus.dropped) {
        ++bus.stats.frames_dropped;
        continue;
      }
      if (tap_) tap_(bus.name, frame, false);
      for (auto& n : bus.nodes) n->receive(frame, t_s_);
    }
  }
}

void Simulator::record_truth(double t_s) {
  RobotSample sample;
  sample.t_s = t_s;
  if (base_source_) {
    const BaseTruth b = base_source_->base_truth();
    sample.config.base = b.pose_W;
    sample.v_mps = b.v_mps;
    sample.omega_radps = b.omega_radps;
  } else {
    sample.config.base = world_.scene().start.base;
  }
  if (joint_source_) {
    const JointTruth j = joint_source_->joint_truth();
    sample.config.q_rad = j.q_rad;
    sample.qd_radps = j.qd_radps;
  } else {
    sample.config.q_rad = world_.scene().start.q_rad;
  }
  world_.record(sample);
}

void Simulator::substep(double t1) {
  const double t0 = t_s_;
  for (Bus& bus : buses_) {
    for (std::size_t i = 0; i < bus.nodes.size(); ++i) {
      scratch_.clear();
      bus.nodes[i]->advance(t1, scratch_);
      for (const can::CanFrame& f : scratch_) {
        if (bus.dropped) {
          ++bus.stats.frames_dropped;
          continue;
        }
        if (tap_) tap_(bus.name, f, true);
        for (std::size_t j = 0; j < bus.nodes.size(); ++j) {
          if (j != i) bus.nodes[j]->receive(f, t1);
        }
        if (bus.endpoint != nullptr) {
          can::CanFrame out = f;
          out.utime = world_.utime_at(static_cast<double>(f.utime) * 1e-6);
          if (bus.endpoint->send(out) == can::CanStatus::ok) {
            ++bus.stats.frames_out;
          } else {
            ++bus.stats.send_failures;
          }
        }
      }
    }
  }
  t_s_ = t1;
  record_truth(t1);
  for (auto& sensor : sensors_) sensor->advance(world_, t0, t1);
}

void Simulator::step_to(double t_s) {
  if (!world_.has_truth()) record_truth(t_s_);
  deliver_inbound();
  if (!std::isfinite(t_s)) return;
  while (t_s - t_s_ > 1e-12) {
    const double next = std::min(t_s, t_s_ + params_.step_s);
    substep(next);
  }
}

SimResult Simulator::drop_bus(const std::string& bus_name, bool dropped) {
  Bus* bus = find_bus(bus_name);
  if (bus == nullptr) return refused("no bus '" + bus_name + "'");
  bus->dropped = dropped;
  return ok(std::string(dropped ? "dropped" : "restored") + " bus '" + bus_name + "'");
}

SimResult Simulator::set_stream(const std::string& device, std::uint32_t can_id, bool enabled) {
  can::SimulatedNode* n = node(device);
  if (n == nullptr) return refused("no device '" + device + "'");
  if (!n->set_stream_enabled(can_id, enabled)) {
    return refused("device '" + device + "' has no stream " + hex(can_id));
  }
  return ok(std::string(enabled ? "resumed" : "stopped") + " stream " + hex(can_id) + " of '" +
            device + "'");
}

SimResult Simulator::raise_error(const std::string& device, std::uint32_t code) {
  can::SimulatedNode* n = node(device);
  if (n == nullptr) return refused("no device '" + device + "'");
  if (!n->raise_error(code)) {
    return refused("device '" + device + "' cannot raise error code " + hex(code));
  }
  return ok("raised error code " + hex(code) + " on '" + device + "'");
}

SimResult Simulator::clear_errors(const std::string& device) {
  can::SimulatedNode* n = node(device);
  if (n == nullptr) return refused("no device '" + device + "'");
  if (!n->clear_errors()) return refused("device '" + device + "' does not clear errors");
  return ok("cleared the errors of '" + device + "'");
}

SimResult Simulator::power_cycle(const std::string& device, double off_s) {
  can::SimulatedNode* n = node(device);
  if (n == nullptr) return refused("no device '" + device + "'");
  if (!(off_s >= 0.0) || !(off_s <= 3600.0)) {
    return refused("power-cycle off time must be in [0, 3600] s");
  }
  if (!n->power_cycle(t_s_, off_s)) return refused("device '" + device + "' cannot power-cycle");
  return ok("power-cycled '" + device + "' (off for " + std::to_string(off_s) + " s)");
}

SimResult Simulator::apply(const SimCommand& c) {
  using Kind = SimCommand::Kind;
  switch (c.kind) {
    case Kind::drop_bus: return drop_bus(c.target, true);
    case Kind::restore_bus: return drop_bus(c.target, false);
    case Kind::stop_stream: return set_stream(c.target, c.can_id, false);
    case Kind::resume_stream: return set_stream(c.target, c.can_id, true);
    case Kind::raise_error: return raise_error(c.target, c.error_code);
    case Kind::clear_errors: return clear_errors(c.target);
    case Kind::power_cycle: return power_cycle(c.target, c.duration_s);
    case Kind::add_box: {
      const ObstacleStatus s = world_.add_box(c.target, c.center_W, c.size_m, c.yaw_rad);
      if (s != ObstacleStatus::ok) return refused("add_box '" + c.target + "': " + to_string(s));
      return ok("added box '" + c.target + "'");
    }
    case Kind::remove_obstacle: {
      const ObstacleStatus s = world_.remove_obstacle(c.target);
      if (s != ObstacleStatus::ok) {
        return refused("remove_obstacle '" + c.target + "': " + to_string(s));
      }
      return ok("removed obstacle '" + c.target + "'");
    }
  }
  return refused("unknown command");
}

}  // namespace porter::sim
