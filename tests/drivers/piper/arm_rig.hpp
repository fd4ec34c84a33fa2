#pragma once
// Test rig: an ArmDriver and a PiperFirmware joined by a CAN bus (memory:NAME or the LCM-carried
// lcm:CAN_ARM@URL), stepped together in simulated time: the firmware every 1 ms, the driver
// every 5 ms (porter-arm's 200 Hz), a command source every 10 ms (the tracker's 100 Hz).
// Every frame one side sends is received by the other before the rig goes on (the receiver
// waits for exactly that many frames), so a run is deterministic over either bus.

#include <gtest/gtest.h>

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "porter/can/can_transport.hpp"
#include "porter/channels.hpp"
#include "porter/piper/arm_driver.hpp"
#include "porter/piper/piper_firmware.hpp"
#include "private_lcm_url.hpp"

namespace porter::piper::test {

/// The robot model's limits (config/robots/scout_mini_piper URDF = the Piper SDK's table).
inline ArmDriverParams rig_driver_params() {
  ArmDriverParams p;
  p.lower_rad = {-2.6179, 0.0, -2.967, -1.745, -1.22, -2.09439};
  p.upper_rad = {2.6179, 3.14, 0.0, 1.745, 1.22, 2.09439};
  return p;
}

/// "memory" -> a private in-memory bus `name`; "lcm" -> CAN_ARM over udpm on a free port.
inline std::string bus_spec(const std::string& kind, const std::string& name) {
  if (kind == "memory") return "memory:" + name;
  return "lcm:" + std::string(channels::kCanArm.name()) + "@" + porter::test::private_lcm_url();
}

class ArmRig {
 public:
  ArmRig(const std::string& spec, const ArmDriverParams& dp = rig_driver_params(),
         const PiperFirmwareParams& fp = {})
      : driver(dp),
        fw(fp),
        driver_bus_(can::open_can_bus(spec, "porter-arm-test")),
        fw_bus_(can::open_can_bus(spec, "piper-firmware-test")) {
    EXPECT_TRUE(driver_bus_->is_open()) << driver_bus_->last_error();
    EXPECT_TRUE(fw_bus_->is_open()) << fw_bus_->last_error();
  }

  /// Runs for `duration_s` of simulated time.
  void run(double duration_s) {
    const long ticks = std::lround(duration_s / 0.001);
    for (long i = 0; i < ticks && ok_; ++i) tick();
  }
  /// Runs until `done()` holds (checked every tick) or `max_s` passed; true when it held.
  bool run_until(const std::function<bool()>& done, double max_s) {
    const long ticks = std::lround(max_s / 0.001);
    for (long i = 0; i < ticks && ok_; ++i) {
      if (done()) return true;
      tick();
    }
    return done();
  }
  bool ok() const { return ok_; }

  ArmDriver driver;
  PiperFirmware fw;
  double t = 0.0;
  /// Set: sent to the driver every 10 ms as an ARM_CMD would be.
  std::optional<ArmCommand> command;
  /// Every frame the driver sent, with the time it was sent.
  std::vector<std::pair<double, can::CanFrame>> driver_frames;
  std::vector<ArmEvent> events;

  bool saw_event(const std::string& text) const {
    for (const ArmEvent& e : events) {
      if (e.text.find(text) != std::string::npos) return true;
    }
    return false;
  }
  /// Driver frames with `id` sent at or after `since_s`.
  std::vector<can::CanFrame> sent(std::uint32_t id, double since_s = 0.0) const {
    std::vector<can::CanFrame> out;
    for (const auto& [ts, f] : driver_frames) {
      if (f.id == id && ts >= since_s) out.push_back(f);
    }
    return out;
  }

 private:
  void tick() {
    ++tick_;
    t = static_cast<double>(tick_) * 0.001;
    fw_out_.clear();
    fw.advance(t, fw_out_);
    transfer(*fw_bus_, *driver_bus_, fw_out_, [&](const can::CanFrame& f) { driver.on_frame(f, t); });
    if (command && tick_ % 10 == 0) driver.on_command(*command, t);
    if (tick_ % 5 == 0) {
      drv_out_.clear();
      driver.step(t, drv_out_);
      for (const can::CanFrame& f : drv_out_) driver_frames.emplace_back(t, f);
      transfer(*driver_bus_, *fw_bus_, drv_out_, [&](const can::CanFrame& f) { fw.receive(f, t); });
      for (ArmEvent& e : driver.take_events()) events.push_back(std::move(e));
    }
    // Both endpoints poll every tick, as the processes do; over LCM this also consumes each
    // endpoint's own echoed frames, which would otherwise fill its receive queue.
    expect_nothing_waiting(*driver_bus_);
    expect_nothing_waiting(*fw_bus_);
  }

  void expect_nothing_waiting(can::CanBus& bus) {
    can::CanFrame stray;
    if (bus.receive(stray, 0) == can::CanStatus::ok) {
      ADD_FAILURE() << "unexpected frame on " << bus.describe() << ": " << can::to_string(stray);
      ok_ = false;
    }
  }

  void transfer(can::CanBus& from, can::CanBus& to, const std::vector<can::CanFrame>& frames,
                const std::function<void(const can::CanFrame&)>& deliver) {
    for (const can::CanFrame& f : frames) {
      if (from.send(f) != can::CanStatus::ok) {
        ADD_FAILURE() << "send failed on " << from.describe() << ": " << from.last_error();
        ok_ = false;
        return;
      }
    }
    can::CanFrame got;
    for (std::size_t i = 0; i < frames.size(); ++i) {
      const can::CanStatus s = to.receive(got, 2000);
      if (s != can::CanStatus::ok) {
        ADD_FAILURE() << "frame " << i << " of " << frames.size() << " did not arrive on " << to.describe()
                      << ": " << can::to_string(s);
        ok_ = false;
        return;
      }
      EXPECT_EQ(got, frames[i]) << "frames arrived out of order";
      deliver(got);
    }
  }

  std::unique_ptr<can::CanBus> driver_bus_;
  std::unique_ptr<can::CanBus> fw_bus_;
  long tick_ = 0;
  bool ok_ = true;
  std::vector<can::CanFrame> fw_out_, drv_out_;
};

}  // namespace porter::piper::test
