// porter-scene-map: publishes a scene's obstacles (config/scenes/*.yaml, voxelized at the
// scene's resolution) as MAP_OCTOMAP at a fixed rate, stamped with the current time. A stand-in
// for porter-mapper in simulation and tests: the planner gets the scene's exact voxel map instead
// of one built from LiDAR scans. Obstacles added to porter-sim later (SIM_COMMAND) are not in it.
//
// usage: porter-scene-map --scene FILE [--rate-hz R] [--lcm-url URL] [--count N]
//   --rate-hz R   publish rate, Hz (default 2)
//   --count N     stop after N maps (default: until SIGINT/SIGTERM)
// exit codes: 0 stopped, 2 bad arguments, 3 bad scene, 4 LCM unavailable.

#include <octomap/OcTree.h>

#include <cstdio>
#include <sstream>
#include <string>

#include "porter/channels.hpp"
#include "porter/core/scene_loader.hpp"
#include "porter/core/scene_voxelizer.hpp"
#include "porter/lcm_bus.hpp"
#include "porter/runtime/clock.hpp"
#include "porter/runtime/log.hpp"
#include "porter/runtime/periodic.hpp"
#include "porter/runtime/stop.hpp"

namespace rt = porter::runtime;

int main(int argc, char** argv) {
  rt::init_log("porter-scene-map");
  std::string scene_path, url;
  double rate_hz = 2.0;
  long count = -1;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (i + 1 >= argc) {
      scene_path.clear();
      break;
    }
    if (a == "--scene") {
      scene_path = argv[++i];
    } else if (a == "--lcm-url") {
      url = argv[++i];
    } else if (a == "--rate-hz") {
      rate_hz = std::atof(argv[++i]);
    } else if (a == "--count") {
      count = std::atol(argv[++i]);
    } else {
      scene_path.clear();
      break;
    }
  }
  if (scene_path.empty() || !(rate_hz > 0.0 && rate_hz <= 50.0)) {
    std::fprintf(stderr, "usage: porter-scene-map --scene FILE [--rate-hz R (0, 50]] [--lcm-url URL] [--count N]\n");
    return 2;
  }
  porter::Scene scene;
  try {
    scene = porter::load_scene(scene_path);
  } catch (const std::exception& e) {
    rt::log_error(e.what());
    return 3;
  }
  const double t0 = rt::mono_s();
  const porter::OccupancyGrid grid = porter::voxelize(scene);
  octomap::OcTree tree(grid.resolution_m());
  std::int64_t occupied = 0;
  for (int iz = 0; iz < grid.dims().z(); ++iz)
    for (int iy = 0; iy < grid.dims().y(); ++iy)
      for (int ix = 0; ix < grid.dims().x(); ++ix) {
        if (!grid.occupied(ix, iy, iz)) continue;
        const Eigen::Vector3d c = grid.voxel_center_W(ix, iy, iz);
        tree.updateNode(octomap::point3d(static_cast<float>(c.x()), static_cast<float>(c.y()), static_cast<float>(c.z())),
                        true, true);
        ++occupied;
      }
  tree.updateInnerOccupancy();
  tree.prune();
  std::ostringstream stream;
  tree.writeBinaryData(stream);
  const std::string bytes = stream.str();
  rt::log_info("scene " + scene.name + ": " + std::to_string(occupied) + " occupied voxels of " +
               std::to_string(grid.resolution_m()) + " m, " + std::to_string(bytes.size()) + " bytes, built in " +
               rt::format_ms(rt::mono_s() - t0));

  rt::install_stop_handlers();
  porter::LcmBus bus(url);
  if (!bus.good()) {
    rt::log_error("LCM unavailable at '" + url + "'");
    return 4;
  }
  porter::octomap_t msg;
  msg.frame_id = "world";
  msg.resolution_m = grid.resolution_m();
  msg.binary = true;
  msg.tree_type = "OcTree";
  msg.data.assign(bytes.begin(), bytes.end());
  msg.num_bytes = static_cast<std::int32_t>(msg.data.size());
  rt::PeriodicLoop loop(1.0 / rate_hz);
  for (std::int64_t n = 1; !rt::stop_requested() && (count < 0 || n <= count); ++n) {
    msg.utime = rt::wall_utime();
    msg.map_id = n;
    bus.publish(porter::channels::kMapOctomap, msg);
    if (count >= 0 && n == count) break;
    loop.wait();
  }
  rt::log_info("stopping after " + std::to_string(loop.cycles() + 1) + " maps");
  return 0;
}
