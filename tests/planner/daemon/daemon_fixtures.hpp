#pragma once
// Shared by the daemon tests: a Planner on the empty scene (open 10 x 6 m floor, start x = 0,
// goal x = 8, T payload), obstacles added to its grid, and a clock the test can move forward.

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>

#include "porter/core/occupancy_grid.hpp"
#include "porter/core/payload.hpp"
#include "porter/core/payload_loader.hpp"
#include "porter/core/robot_loader.hpp"
#include "porter/core/scene_loader.hpp"
#include "porter/core/scene_voxelizer.hpp"
#include "porter/pipeline/planner.hpp"
#include "porter/pipeline/settings_yaml.hpp"
#include "porter/runtime/clock.hpp"

namespace porter::planner_daemon::testing {

inline std::string source_dir() { return PORTER_SOURCE_DIR; }

inline Scene empty_scene() { return load_scene(source_dir() + "/config/scenes/empty.yaml"); }

inline std::unique_ptr<pipeline::Planner> make_planner(const Scene& s) {
  const RobotModel model = attach_payload(load_robot_model(source_dir() + "/config/robots/scout_mini_piper/robot.yaml"),
                                          load_payload(s.payload_file));
  pipeline::PlannerSettings settings = pipeline::load_planner_settings(source_dir() + "/config/planner");
  settings.kernels.kernels.resolution_m = s.resolution_m;
  return std::make_unique<pipeline::Planner>(model, settings);
}

/// Marks every voxel whose centre lies in [x0, x1] x [y0, y1] x [0, z1].
inline OccupancyGrid with_box(OccupancyGrid g, double x0, double x1, double y0, double y1, double z1 = 2.4) {
  for (int ix = 0; ix < g.dims().x(); ++ix)
    for (int iy = 0; iy < g.dims().y(); ++iy)
      for (int iz = 0; iz < g.dims().z(); ++iz) {
        const Eigen::Vector3d c = g.voxel_center_W(ix, iy, iz);
        if (c.x() >= x0 && c.x() <= x1 && c.y() >= y0 && c.y() <= y1 && c.z() <= z1) g.set(ix, iy, iz);
      }
  return g;
}

/// Wall clock plus an offset the test moves (plans take real time; the test jumps ahead).
struct TestClock {
  std::shared_ptr<std::atomic<std::int64_t>> offset_us = std::make_shared<std::atomic<std::int64_t>>(0);
  std::int64_t operator()() const { return runtime::wall_utime() + offset_us->load(); }
  void advance_to(std::int64_t utime) const { offset_us->store(utime - runtime::wall_utime()); }
};

}  // namespace porter::planner_daemon::testing
