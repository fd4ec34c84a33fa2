// Fuzz target: a TRAJECTORY datagram as porter-tracker receives it: the LCM guard, lcm-gen's
// decoder, then from_msg. Input: the message without its 8-byte fingerprint (the target puts it
// in front). from_msg must never throw; a trajectory it accepts must sample to finite values and
// go back to a message that converts again.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "porter/lcm_guard.hpp"
#include "porter/msg/trajectory_msg.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using porter::minco_trajectory_t;
  static const std::uint64_t hash = static_cast<std::uint64_t>(minco_trajectory_t::getHash());
  std::vector<std::uint8_t> datagram(8 + size);  // exactly the datagram: ASan sees any overread
  for (int i = 0; i < 8; ++i) datagram[i] = static_cast<std::uint8_t>(hash >> (8 * (7 - i)));
  if (size > 0) std::memcpy(datagram.data() + 8, data, size);
  if (!porter::lcm_guard_check<minco_trajectory_t>(datagram.data(), datagram.size()).ok) return 0;
  minco_trajectory_t msg;
  const int n = static_cast<int>(datagram.size());
  if (msg.decode(datagram.data(), 0, n) != n) std::abort();
  porter::TrajectoryMsgResult r;
  try {
    r = porter::from_msg(msg);
  } catch (...) {
    std::abort();
  }
  if (!r.ok()) {
    if (r.error.empty()) std::abort();
    return 0;
  }
  const porter::Trajectory& t = r.value->trajectory;
  const double total = t.total_duration_s();
  for (int i = 0; i <= 16; ++i) {
    const double ts = total * i / 16.0;
    for (int order = 0; order <= 3; ++order)
      if (!t.derivative(ts, order).allFinite()) std::abort();
    if (!std::isfinite(t.base_motion(ts).yaw_rad)) std::abort();
  }
  const minco_trajectory_t back = porter::to_msg(t, 0, 1, "world", "");
  if (!porter::from_msg(back).ok()) std::abort();
  return 0;
}
