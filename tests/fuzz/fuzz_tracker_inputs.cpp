// Fuzz target: porter-tracker's inputs. The first byte picks the channel (ROBOT_STATE,
// TRAJECTORY, ESTOP), the rest is decoded as that lcm type and, when it decodes, converted by
// the process's adapter and fed to a Tracker that is then stepped. Whatever arrives, the
// commands must stay finite and the output messages must encode.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "fuzz_allocation_limit.hpp"
#include "porter/lcm_guard.hpp"
#include "porter/estop_t.hpp"
#include "tracker_messages.hpp"

namespace {

porter::tracker::Tracker& tracker() {
  static porter::tracker::Tracker instance([] {
    porter::tracker::TrackerParams p;
    p.base_limits.wheel_radius_m = 0.0875;
    p.base_limits.track_width_m = 0.4165;
    p.base_limits.wheel_omega_max_radps = 12.0;
    p.base_limits.wheel_alpha_max_radps2 = 20.0;
    return p;
  }());
  return instance;
}

template <class T>
bool decode(const std::uint8_t* data, std::size_t size, T& msg) {
  // What LcmBus does: the guard first (lcm-gen's decoders trust the lengths in the bytes).
  if (!porter::lcm_guard_check<T>(data, size).ok) return false;
  try {
    return msg.decode(data, 0, static_cast<int>(size)) == static_cast<int>(size);
  } catch (...) {
    return false;  // LcmBus drops these the same way
  }
}

void fail(const char* what) {
  std::fprintf(stderr, "fuzz_tracker_inputs: %s\n", what);
  std::abort();
}

template <class T>
void require_encodes(const T& msg) {
  const int n = msg.getEncodedSize();
  std::vector<std::uint8_t> buffer(static_cast<std::size_t>(n));
  if (msg.encode(buffer.data(), 0, n) != n) fail("an output message does not encode");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 9) return 0;
  static std::int64_t now = 1'700'000'000'000'000;
  now += 10'000;
  const std::uint8_t channel = data[0] % 3;
  data += 1;
  size -= 1;
  auto& t = tracker();
  if (channel == 0) {
    porter::robot_state_t msg;
    if (!decode(data, size, msg)) return 0;
    auto c = porter::tracker_app::to_measured_state(msg, "world");
    if (c.state) t.on_state(*c.state, now);
  } else if (channel == 1) {
    porter::minco_trajectory_t msg;
    if (!decode(data, size, msg)) return 0;
    auto c = porter::tracker_app::to_offer(msg);
    if (c.offer) {
      t.on_trajectory(std::move(*c.offer), now);
    } else {
      t.on_invalid_trajectory(msg.plan_id, c.error);
    }
  } else {
    porter::estop_t msg;
    if (!decode(data, size, msg)) return 0;
    t.on_estop(msg.active, msg.reason, now);
  }
  const auto& out = t.step(now);
  if (!std::isfinite(out.base.v_mps) || !std::isfinite(out.base.omega_radps)) {
    fail("non-finite base command");
  }
  if (out.arm_enabled && (!out.q_rad.allFinite() || !out.qd_radps.allFinite())) {
    fail("non-finite arm command");
  }
  require_encodes(porter::tracker_app::make_base_cmd(out, now));
  require_encodes(porter::tracker_app::make_arm_cmd(out, 100.0, now));
  require_encodes(porter::tracker_app::make_status(out, t.last_refusal(), {}, now));
  return 0;
}
