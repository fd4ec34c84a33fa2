// Fuzz target: porter-planner's inputs. The first byte picks the channel (MAP_OCTOMAP,
// PLAN_GOAL, ROBOT_STATE); the rest is decoded as that lcm type and, when it decodes, converted
// by the process's adapter. A MAP_OCTOMAP message is also given the fuzz bytes as its OctoMap
// stream (with the planner's resolution and type, so the stream parser itself is reached) and
// turned into a planning grid under a small voxel limit. Whatever arrives, a conversion either
// succeeds with finite values or says why, and a status message encodes.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "fuzz_allocation_limit.hpp"
#include "porter/lcm_guard.hpp"
#include "planner_messages.hpp"

namespace {

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
  std::fprintf(stderr, "fuzz_planner_inputs: %s\n", what);
  std::abort();
}

void grid_of(const porter::octomap_t& msg) {
  porter::planner_app::MapParams params;
  params.max_voxels = 2e5;
  params.margin_m = 0.5;
  params.block_m = 1.0;
  params.min_height_m = 0.5;
  const auto t = porter::planner_app::decode_octomap(msg, "world", params);
  if (!t.tree) {
    if (t.error.empty()) fail("a refused map without a reason");
    return;
  }
  const auto g = porter::planner_app::to_grid(*t.tree, {{0.0, 0.0}}, params);
  if (!g.grid && g.error.empty()) fail("a refused grid without a reason");
  if (g.grid && g.grid->num_voxels() > 4 * static_cast<std::int64_t>(params.max_voxels)) fail("grid over the limit");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  const std::uint8_t channel = data[0] % 3;
  data += 1;
  size -= 1;
  if (channel == 0) {
    porter::octomap_t raw;
    raw.frame_id = "world";
    raw.resolution_m = 0.05;
    raw.binary = (data[0] & 1) != 0;
    raw.tree_type = "OcTree";
    raw.data.assign(data + 1, data + size);
    raw.num_bytes = static_cast<std::int32_t>(raw.data.size());
    grid_of(raw);
    porter::octomap_t msg;
    if (decode(data, size, msg)) grid_of(msg);
  } else if (channel == 1) {
    porter::plan_goal_t msg;
    if (!decode(data, size, msg)) return 0;
    const auto c = porter::planner_app::to_goal(msg, "world");
    if (c.goal) {
      const auto& b = c.goal->spec.base;
      if (!std::isfinite(b.x_m) || !std::isfinite(b.y_m) || !std::isfinite(b.yaw_rad)) fail("non-finite goal");
      if (c.goal->spec.arm_q_rad && !c.goal->spec.arm_q_rad->allFinite()) fail("non-finite goal arm");
    } else if (c.error.empty()) {
      fail("a refused goal without a reason");
    }
  } else {
    porter::robot_state_t msg;
    if (!decode(data, size, msg)) return 0;
    const auto c = porter::planner_app::to_measured_state(msg, "world", 1);
    if (c.state && c.state->valid && !c.state->config.as_dof().allFinite()) fail("a valid state that is not finite");
    if (!c.state && c.error.empty()) fail("a refused state without a reason");
  }
  porter::planner_daemon::Report r;
  r.reason = "fuzz";
  const auto s = porter::planner_app::make_status(r, 1);
  const int n = s.getEncodedSize();
  std::vector<std::uint8_t> buffer(static_cast<std::size_t>(n));
  if (s.encode(buffer.data(), 0, n) != n) fail("a status does not encode");
  return 0;
}
