// porter-map-diff: where two runs' maps of the same newest scan differ, and which of them a
// deterministic replay of the inputs reproduces.
//
//   porter-map-diff --log A.lcmlog --compare B.lcmlog [--inputs INPUTS.lcmlog
//                   [--config porter_mapper.yaml] [--payload FILE|none]] [--all]
//
// Pairs the MAP_OCTOMAP messages of A and B by octomap_t.utime (the newest integrated scan's
// last point). For every pair whose streams differ it reads both maps back with OctoMap and
// prints, per voxel state change (free / occupied / unknown in A -> in B), how many voxels,
// their key range and height, how far the nearest and farthest lie from the map's robot pose,
// and how many lie within 4 voxels of the edge of the region either map knows (the window's
// edge). --all prints identical pairs too.
//
// With --inputs (the log scripts/replay plays: LIDAR_POINTS and ROBOT_STATE) the inputs go
// through porter-mapper's node in the log's order, each cloud processed as soon as the state
// covers it, with a queue that never overflows, a map after every cloud: the reference. Every map of A
// and B is then checked against the reference map of the same utime, and the scans the
// reference integrated are listed against the maps' utimes.
// Exit codes: 0 done, 2 bad arguments or config, 3 unreadable log.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>
#include <octomap/OcTree.h>

#include "mapper_node.hpp"
#include "mapper_params.hpp"
#include "porter/channels.hpp"
#include "porter/core/load_error.hpp"
#include "porter/core/payload.hpp"
#include "porter/core/payload_loader.hpp"
#include "porter/core/robot_loader.hpp"
#include "porter/octomap_t.hpp"
#include "porter/point_cloud_t.hpp"
#include "porter/robot_state_t.hpp"

namespace pm = porter::mapping;

namespace {

struct Map {
  std::int64_t map_id = 0;
  double resolution_m = 0.05;
  double x_m = 0, y_m = 0;
  std::vector<std::uint8_t> data;
};

template <class Msg>
bool decode(const lcm::LogEvent& e, Msg& m) {
  return m.decode(e.data, 0, static_cast<int>(e.datalen)) >= 0;
}

bool read_maps(const std::string& path, std::map<std::int64_t, Map>& out) {
  lcm::LogFile log(path, "r");
  if (!log.good()) return false;
  for (const lcm::LogEvent* e = log.readNextEvent(); e != nullptr; e = log.readNextEvent()) {
    if (e->channel != porter::channels::kMapOctomap.name()) continue;
    porter::octomap_t m;
    if (!decode(*e, m) || !m.binary) continue;
    Map& x = out[m.utime];
    x.map_id = m.map_id;
    x.resolution_m = m.resolution_m;
    x.x_m = m.robot_x_m;
    x.y_m = m.robot_y_m;
    x.data.assign(m.data.begin(), m.data.end());
  }
  return true;
}

// 0 unknown, 1 free, 2 occupied, for every voxel of the key box lo..hi.
struct Dense {
  std::array<int, 3> lo{}, hi{};
  std::vector<std::uint8_t> v;
  std::size_t at(int x, int y, int z) const {
    return (static_cast<std::size_t>(z - lo[2]) * static_cast<std::size_t>(hi[1] - lo[1] + 1) +
            static_cast<std::size_t>(y - lo[1])) * static_cast<std::size_t>(hi[0] - lo[0] + 1) +
           static_cast<std::size_t>(x - lo[0]);
  }
};

std::unique_ptr<octomap::OcTree> read_tree(const Map& m) {
  auto tree = std::make_unique<octomap::OcTree>(m.resolution_m);
  std::istringstream in(std::string(m.data.begin(), m.data.end()));
  if (!m.data.empty() && !tree->readBinaryData(in)) return nullptr;
  return tree;
}

void bounds(const octomap::OcTree& t, std::array<int, 3>& lo, std::array<int, 3>& hi) {
  const int depth = static_cast<int>(t.getTreeDepth());
  for (auto it = t.begin_leafs(); it != t.end_leafs(); ++it) {
    const octomap::OcTreeKey k = it.getIndexKey();
    const int side = 1 << (depth - static_cast<int>(it.getDepth()));
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], static_cast<int>(k[a]));
      hi[a] = std::max(hi[a], static_cast<int>(k[a]) + side - 1);
    }
  }
}

void fill(const octomap::OcTree& t, Dense& d) {
  const int depth = static_cast<int>(t.getTreeDepth());
  for (auto it = t.begin_leafs(); it != t.end_leafs(); ++it) {
    const octomap::OcTreeKey k = it.getIndexKey();
    const int side = 1 << (depth - static_cast<int>(it.getDepth()));
    const std::uint8_t s = t.isNodeOccupied(*it) ? 2 : 1;
    for (int z = k[2]; z < k[2] + side; ++z)
      for (int y = k[1]; y < k[1] + side; ++y)
        for (int x = k[0]; x < k[0] + side; ++x) d.v[d.at(x, y, z)] = s;
  }
}

const char* kState[] = {"unknown", "free", "occupied"};

struct Change {
  long n = 0, near_edge = 0;
  std::array<int, 3> lo{1 << 30, 1 << 30, 1 << 30}, hi{-(1 << 30), -(1 << 30), -(1 << 30)};
  double dmin = 1e9, dmax = 0;
};

// Prints where the two maps differ; false when they cannot be read.
bool diff(const Map& a, const Map& b) {
  const auto ta = read_tree(a), tb = read_tree(b);
  if (!ta || !tb) return false;
  Dense d;
  d.lo = {1 << 30, 1 << 30, 1 << 30};
  d.hi = {-(1 << 30), -(1 << 30), -(1 << 30)};
  std::array<int, 3> alo = d.lo, ahi = d.hi, blo = d.lo, bhi = d.hi;
  bounds(*ta, alo, ahi);
  bounds(*tb, blo, bhi);
  for (int i = 0; i < 3; ++i) {
    d.lo[i] = std::min(alo[i], blo[i]);
    d.hi[i] = std::max(ahi[i], bhi[i]);
  }
  if (d.lo[0] > d.hi[0]) {
    std::printf("    both maps empty\n");
    return true;
  }
  const std::size_t n = static_cast<std::size_t>(d.hi[0] - d.lo[0] + 1) * static_cast<std::size_t>(d.hi[1] - d.lo[1] + 1) *
                        static_cast<std::size_t>(d.hi[2] - d.lo[2] + 1);
  Dense e = d;
  d.v.assign(n, 0);
  e.v.assign(n, 0);
  fill(*ta, d);
  fill(*tb, e);
  std::map<std::pair<int, int>, Change> changes;
  const double res = a.resolution_m;
  for (int z = d.lo[2]; z <= d.hi[2]; ++z)
    for (int y = d.lo[1]; y <= d.hi[1]; ++y)
      for (int x = d.lo[0]; x <= d.hi[0]; ++x) {
        const std::size_t i = d.at(x, y, z);
        if (d.v[i] == e.v[i]) continue;
        Change& c = changes[{d.v[i], e.v[i]}];
        ++c.n;
        const std::array<int, 3> k{x, y, z};
        for (int a2 = 0; a2 < 3; ++a2) {
          c.lo[a2] = std::min(c.lo[a2], k[a2]);
          c.hi[a2] = std::max(c.hi[a2], k[a2]);
        }
        const double wx = (x - 32768 + 0.5) * res, wy = (y - 32768 + 0.5) * res;
        const double dist = std::hypot(wx - a.x_m, wy - a.y_m);
        c.dmin = std::min(c.dmin, dist);
        c.dmax = std::max(c.dmax, dist);
        // Within 4 voxels of the x/y edge of the region the two maps know.
        if (x - d.lo[0] < 4 || d.hi[0] - x < 4 || y - d.lo[1] < 4 || d.hi[1] - y < 4) ++c.near_edge;
      }
  std::printf("    known region x %d..%d / %d..%d, y %d..%d / %d..%d (keys, first / second)\n", alo[0], ahi[0], blo[0],
              bhi[0], alo[1], ahi[1], blo[1], bhi[1]);
  for (const auto& [k, c] : changes) {
    std::printf("    %-8s -> %-8s %7ld voxels; keys x %d..%d, y %d..%d, z %.2f..%.2f m; %.2f..%.2f m from the robot; "
                "%ld at the edge\n",
                kState[k.first], kState[k.second], c.n, c.lo[0], c.hi[0], c.lo[1], c.hi[1], (c.lo[2] - 32768) * res,
                (c.hi[2] - 32767) * res, c.dmin, c.dmax, c.near_edge);
  }
  return true;
}

// The inputs through the node in log order: a map after every integrated cloud.
bool reference(const std::string& inputs, const pm::app::MapperConfig& cfg, const porter::RobotModel& robot,
               std::map<std::int64_t, std::vector<std::uint8_t>>& maps, std::vector<std::int64_t>& dropped) {
  lcm::LogFile log(inputs, "r");
  if (!log.good()) return false;
  pm::app::MapperConfig c = cfg;
  c.max_queued_clouds = 1 << 20;
  pm::app::MapperNode node(c, robot);
  porter::octomap_t msg;
  std::int64_t scans_in = 0;
  std::uint64_t no_state = 0;
  const auto drain = [&](std::int64_t now_ns) {
    pm::app::StepResult r;
    while (node.step(now_ns, 0, r)) {
      node.make_map(msg);
      maps[msg.utime] = msg.data;
    }
    const auto k = node.counters();
    if (k.dropped_no_state != no_state) {
      dropped.push_back(static_cast<std::int64_t>(k.dropped_no_state - no_state));
      no_state = k.dropped_no_state;
    }
  };
  for (const lcm::LogEvent* e = log.readNextEvent(); e != nullptr; e = log.readNextEvent()) {
    const std::int64_t now_ns = e->timestamp * 1000;
    if (e->channel == porter::channels::kRobotState.name()) {
      porter::robot_state_t m;
      if (decode(*e, m)) node.on_state(m);
    } else if (e->channel == porter::channels::kLidarPoints.name()) {
      porter::point_cloud_t m;
      if (decode(*e, m)) {
        node.on_cloud(m, now_ns);
        ++scans_in;
      }
    } else {
      continue;
    }
    drain(now_ns);
  }
  const auto k = node.counters();
  std::printf("reference: %ld clouds in, %lu processed, %lu dropped without state, %lu rejected, %zu maps\n", scans_in,
              k.clouds_processed, k.dropped_no_state, k.rejected, maps.size());
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  std::string a_path, b_path, inputs, config_path = PORTER_SOURCE_DIR "/config/mapping/porter_mapper.yaml", payload;
  bool all = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--all") {
      all = true;
      continue;
    }
    if (i + 1 >= argc) {
      std::fprintf(stderr, "porter-map-diff: %s needs a value\n", arg.c_str());
      return 2;
    }
    const std::string v = argv[++i];
    if (arg == "--log") a_path = v;
    else if (arg == "--compare") b_path = v;
    else if (arg == "--inputs") inputs = v;
    else if (arg == "--config") config_path = v;
    else if (arg == "--payload") payload = v;
    else {
      std::fprintf(stderr, "usage: porter-map-diff --log A --compare B [--inputs INPUTS [--config F] [--payload F|none]] [--all]\n");
      return 2;
    }
  }
  if (a_path.empty() || b_path.empty()) {
    std::fprintf(stderr, "usage: porter-map-diff --log A --compare B [--inputs INPUTS [--config F] [--payload F|none]] [--all]\n");
    return 2;
  }
  std::map<std::int64_t, Map> a, b;
  if (!read_maps(a_path, a) || !read_maps(b_path, b)) {
    std::fprintf(stderr, "porter-map-diff: cannot read %s or %s\n", a_path.c_str(), b_path.c_str());
    return 3;
  }
  std::map<std::int64_t, std::vector<std::uint8_t>> ref;
  std::vector<std::int64_t> ref_dropped;
  if (!inputs.empty()) {
    pm::app::MapperConfig cfg;
    porter::RobotModel robot;
    try {
      cfg = pm::app::load_mapper_config(config_path);
      if (!payload.empty()) cfg.payload_yaml = payload == "none" ? "" : payload;
      robot = porter::load_robot_model(cfg.robot_yaml);
      if (!cfg.payload_yaml.empty()) robot = porter::attach_payload(robot, porter::load_payload(cfg.payload_yaml));
    } catch (const porter::LoadError& e) {
      std::fprintf(stderr, "porter-map-diff: %s\n", e.what());
      return 2;
    }
    if (!reference(inputs, cfg, robot, ref, ref_dropped)) {
      std::fprintf(stderr, "porter-map-diff: cannot read %s\n", inputs.c_str());
      return 3;
    }
  }
  const auto vs_ref = [&](std::int64_t utime, const Map& m) -> char {
    if (ref.empty()) return ' ';
    const auto it = ref.find(utime);
    if (it == ref.end()) return '?';  // the reference has no map of this scan
    return it->second == m.data ? '=' : 'X';
  };
  long pairs = 0, same = 0, a_ref = 0, a_ref_same = 0, b_ref = 0, b_ref_same = 0;
  for (const auto& [utime, m] : a) {
    if (!ref.empty() && ref.count(utime)) {
      ++a_ref;
      a_ref_same += vs_ref(utime, m) == '=';
    }
  }
  for (const auto& [utime, m] : b) {
    if (!ref.empty() && ref.count(utime)) {
      ++b_ref;
      b_ref_same += vs_ref(utime, m) == '=';
    }
  }
  for (const auto& [utime, ma] : a) {
    const auto it = b.find(utime);
    if (it == b.end()) continue;
    const Map& mb = it->second;
    ++pairs;
    const bool identical = ma.data == mb.data;
    same += identical;
    if (identical && !all) continue;
    std::printf("utime %ld: maps %ld / %ld, %zu / %zu bytes, %s; against the reference: %c %c\n", utime, ma.map_id,
                mb.map_id, ma.data.size(), mb.data.size(), identical ? "identical" : "DIFFERENT", vs_ref(utime, ma),
                vs_ref(utime, mb));
    if (!identical && !diff(ma, mb)) std::printf("    unreadable stream\n");
  }
  if (!ref.empty()) {
    std::printf("against the reference: first %ld of %ld maps equal, second %ld of %ld (maps of scans the reference "
                "also mapped)\n", a_ref_same, a_ref, b_ref_same, b_ref);
    const auto list = [&](const char* name, const std::map<std::int64_t, Map>& maps) {
      std::printf("%s, map by map (= as the reference, X not, ? a scan the reference did not map):\n  ", name);
      for (const auto& [utime, m] : maps) std::printf("%c", vs_ref(utime, m));
      std::printf("\n");
    };
    list("first", a);
    list("second", b);
  }
  std::printf("maps: %zu and %zu; pairs of the same newest scan %ld, byte-identical %ld\n", a.size(), b.size(), pairs, same);
  return 0;
}
