// Fuzz target: trajectory_from_json (files the CLI and tools read). It must never throw, and a
// trajectory it accepts must sample to finite values everywhere and write back to JSON that
// reads again.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "porter/core/trajectory_json.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  porter::TrajectoryResult r;
  try {
    r = porter::trajectory_from_json(text);
  } catch (...) {
    std::abort();  // the header promises no exception
  }
  if (!r.ok()) {
    if (r.error.empty()) std::abort();
    return 0;
  }
  const porter::Trajectory& t = *r.trajectory;
  const double total = t.total_duration_s();
  if (!(total > 0.0) || !std::isfinite(total)) std::abort();
  for (int i = 0; i <= 16; ++i) {
    const double ts = total * i / 16.0;
    for (int order = 0; order <= 3; ++order)
      if (!t.derivative(ts, order).allFinite()) std::abort();
    const auto m = t.base_motion(ts);
    if (!std::isfinite(m.yaw_rad)) std::abort();
  }
  if (!porter::trajectory_from_json(porter::to_json(t)).ok()) std::abort();
  return 0;
}
