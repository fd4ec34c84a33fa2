// Fuzz target: porter-mapper's LCM inputs. The first byte picks the channel (ROBOT_STATE or
// LIDAR_POINTS), the rest is decoded as that lcm type and, when it decodes, handed to the
// process's MapperNode (conversions, queue, de-skew, integration); every few inputs a map is
// built. Whatever arrives: no crash, no out-of-bounds access, the map stream stays well formed
// (it reads back into an OcTree of the map's resolution).
#include <cstdint>
#include <sstream>

#include <octomap/OcTree.h>

#include "fuzz_allocation_limit.hpp"
#include "porter/lcm_guard.hpp"
#include "mapper_node.hpp"

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

porter::mapping::app::MapperNode& node() {
  // A small window and no self-filter: the allocation limit (1 MiB) holds, and the robot model
  // needs no files.
  static porter::mapping::app::MapperNode n = [] {
    porter::mapping::app::MapperConfig cfg;
    cfg.mapper.map.dims = {48, 48, 24};
    cfg.mapper.max_range_m = 1.0;
    cfg.mapper.self_filter = false;
    cfg.state_wait_s = 0.0;
    return porter::mapping::app::MapperNode(cfg, porter::RobotModel{});
  }();
  return n;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  static std::int64_t now_ns = 0;
  static unsigned calls = 0;
  now_ns += 1'000'000;
  const std::uint8_t channel = data[0] % 2;
  data += 1;
  size -= 1;
  if (channel == 0) {
    porter::robot_state_t msg;
    if (!decode(data, size, msg)) return 0;
    node().on_state(msg);
  } else {
    porter::point_cloud_t msg;
    if (!decode(data, size, msg)) return 0;
    node().on_cloud(msg, now_ns);
  }
  porter::mapping::app::StepResult r;
  while (node().step(now_ns, 0, r)) {
  }
  if (++calls % 64 == 0) {
    porter::octomap_t map;
    node().make_map(map);
    if (map.num_bytes != static_cast<std::int32_t>(map.data.size())) __builtin_trap();
    octomap::OcTree tree(map.resolution_m);
    std::istringstream in(std::string(map.data.begin(), map.data.end()));
    tree.readBinaryData(in);
  }
  return 0;
}
