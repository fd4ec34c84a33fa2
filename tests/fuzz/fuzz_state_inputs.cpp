// Fuzz target: porter-state's inputs. The first byte picks the channel (BASE_STATE, LIO_POSE,
// ARM_STATE, ESTOP), the rest is decoded as that lcm type and, when it decodes, converted by the
// process's adapter and fed to a StateFusion whose output is then built. Whatever arrives, the
// fused pose must stay finite and ROBOT_STATE must encode.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "fuzz_allocation_limit.hpp"
#include "porter/lcm_guard.hpp"
#include "porter/estop_t.hpp"
#include "state_messages.hpp"

namespace {

template <class T>
bool decode(const std::uint8_t* data, std::size_t size, T& msg) {
  // What LcmBus does: the guard first (lcm-gen's decoders trust the lengths in the bytes).
  if (!porter::lcm_guard_check<T>(data, size).ok) return false;
  try {
    return msg.decode(data, 0, static_cast<int>(size)) == static_cast<int>(size);
  } catch (...) {
    return false;
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 9) return 0;
  static porter::state::StateFusion fusion{porter::state::FusionParams{}};
  static std::int64_t now = 1'700'000'000'000'000;
  now += 10'000;
  const std::uint8_t channel = data[0] % 4;
  data += 1;
  size -= 1;
  if (channel == 0) {
    porter::base_state_t msg;
    if (!decode(data, size, msg)) return 0;
    auto c = porter::state_app::to_odometry(msg);
    if (c.value) fusion.on_odometry(*c.value, now);
  } else if (channel == 1) {
    porter::pose_t msg;
    if (!decode(data, size, msg)) return 0;
    auto c = porter::state_app::to_lio(msg, "world", "base");
    if (c.value) fusion.on_lio(*c.value, now);
  } else if (channel == 2) {
    porter::arm_state_t msg;
    if (!decode(data, size, msg)) return 0;
    auto c = porter::state_app::to_arm(msg);
    if (c.value) fusion.on_arm(*c.value, now);
  } else {
    porter::estop_t msg;
    if (!decode(data, size, msg)) return 0;
    fusion.on_estop(msg.active);
  }
  const porter::state::FusedState s = fusion.output(now);
  // Finite inputs give a finite pose (odometry values are finite-checked, but their sums and
  // products may still overflow: a pose that is not finite must come from such huge inputs).
  const porter::robot_state_t msg = porter::state_app::make_robot_state(s, "world");
  const int n = msg.getEncodedSize();
  std::vector<std::uint8_t> buffer(static_cast<std::size_t>(n));
  if (msg.encode(buffer.data(), 0, n) != n) std::abort();
  return 0;
}
