// porter-bench-pipeline: the planning pipeline as a long-running process uses it: one
// porter::pipeline::Planner per scene, the time of its first plan() (which also builds the
// back-end's robot side when the back-end runs) and of later plan() calls on the same Planner
// (nothing built any more), and a plan after a new map. A benchmark, not a test: it prints,
// asserts nothing.
//
//   build/tests/bench/porter-bench-pipeline [REPEATS=5]
//
// The config directory (scenes, robot, planner settings) is ./config or the one above the
// executable (porter/pipeline/config_dir.hpp).
// Frozen fixture: scenes bridge (h_b 0.9 m, seed 4), tunnel (seed 1), forest (seed 2) with their
// payloads, the shipped settings (config/planner/, kernel resolution from the scene), the request
// the scene file gives (start at rest, exact goal), Stages::kFull. The new map: bridge at
// h_b 1.0 m, tunnel unchanged (the same map again), forest with seed 3's columns (same grid
// geometry: an incremental kernel update). Wall times (the pipeline runs the back-end's term on two
// threads); "later" is the median (min-max) of REPEATS plans of the same request.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "porter/backend/robot_sdf.hpp"
#include "porter/core/payload.hpp"
#include "porter/core/payload_loader.hpp"
#include "porter/core/robot_loader.hpp"
#include "porter/core/scene_loader.hpp"
#include "porter/core/scene_voxelizer.hpp"
#include "porter/pipeline/config_dir.hpp"
#include "porter/pipeline/planner.hpp"
#include "porter/pipeline/settings_yaml.hpp"
#include "porter/planner/collision/kernel_robot.hpp"

namespace {

using namespace porter;
using Clock = std::chrono::steady_clock;

double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

const std::string& config_dir() {
  static const std::string dir = pipeline::find_config_dir();
  return dir;
}

struct Case {
  const char* scene;
  double h_b;              ///< < 0: the scene's
  std::uint64_t seed;
  double next_h_b;         ///< the new map's
  std::uint64_t next_seed;
};

Scene load(const Case& c, double h_b, std::uint64_t seed) {
  SceneLoadOptions options;
  if (h_b > 0.0) options.parameter_overrides["h_b"] = h_b;
  options.seed = seed;
  return load_scene(config_dir() + "/scenes/" + c.scene + ".yaml", options);
}

std::string stage_line(const pipeline::PlanResult& r) {
  char buf[256];
  std::snprintf(buf, sizeof buf, "%s: fe %.0f ms, mid %.0f ms%s, be %s", planner::to_string(r.status),
                r.frontend ? r.frontend->elapsed_s * 1e3 : 0.0, r.midend ? r.midend->time_s * 1e3 : 0.0,
                r.midend && !r.midend->retry.empty() ? " (retry)" : "",
                r.backend ? (std::to_string(static_cast<int>(r.backend->result.elapsed_s * 1e3)) + " ms").c_str() : "-");
  return buf;
}

}  // namespace

int main(int argc, char** argv) {
  if (config_dir().empty()) {
    std::fprintf(stderr, "porter-bench-pipeline: no config directory (run from the repository root)\n");
    return 2;
  }
  const int repeats = argc > 1 ? std::max(1, std::atoi(argv[1])) : 5;
  const Case cases[] = {{"bridge", 0.9, 4, 1.0, 4}, {"tunnel", -1.0, 1, -1.0, 1}, {"forest", -1.0, 2, -1.0, 3}};
  const pipeline::PlannerSettings shipped =
      pipeline::load_planner_settings(config_dir() + "/planner");
  std::printf("scene    build   map | first plan (setup)     | later plans: median (min-max)  | new map    plan | builds  | first / later stages\n");
  for (const Case& c : cases) {
    const Scene scene = load(c, c.h_b, c.seed);
    const RobotModel model = attach_payload(
        load_robot_model(config_dir() + "/robots/scout_mini_piper/robot.yaml"),
        load_payload(scene.payload_file));
    pipeline::PlannerSettings settings = shipped;
    settings.kernels.kernels.resolution_m = scene.resolution_m;
    const std::int64_t kernels0 = planner::KernelRobot::build_count(), sdf0 = backend::RobotSdf::build_count();

    auto t0 = Clock::now();
    pipeline::Planner planner(model, settings);
    const double build_s = since(t0);
    const OccupancyGrid grid = voxelize(scene);
    const pipeline::MapUpdate map = planner.set_map(grid);

    pipeline::PlanRequest req;
    req.start = pipeline::StartState::at_rest(scene.start);
    req.goal = pipeline::GoalSpec::exact(scene.goal);
    req.seed = scene.seed;
    t0 = Clock::now();
    const pipeline::PlanResult first = planner.plan(req);
    const double first_s = since(t0);
    std::vector<double> later;
    pipeline::PlanResult last;
    for (int k = 0; k < repeats; ++k) {
      t0 = Clock::now();
      last = planner.plan(req);
      later.push_back(since(t0));
    }
    std::sort(later.begin(), later.end());

    const Scene next = load(c, c.next_h_b, c.next_seed);
    const pipeline::MapUpdate update = planner.set_map(voxelize(next));
    pipeline::PlanRequest next_req = req;
    next_req.seed = next.seed;
    t0 = Clock::now();
    const pipeline::PlanResult after = planner.plan(next_req);
    const double after_s = since(t0);
    const std::int64_t kernel_builds = planner::KernelRobot::build_count() - kernels0;
    const std::int64_t sdf_builds = backend::RobotSdf::build_count() - sdf0;

    std::printf("%-7s %5.0f %5.0f | %6.0f ms (%5.0f ms) | %6.0f ms (%4.0f-%4.0f)        | %5.0f%s %5.0f | K %lld S %lld | %s / %s; new map: %s\n",
                c.scene, 1e3 * build_s, 1e3 * map.time_s, 1e3 * first_s, 1e3 * first.setup_s,
                1e3 * later[later.size() / 2], 1e3 * later.front(), 1e3 * later.back(), 1e3 * update.time_s,
                update.incremental ? "i" : "f", 1e3 * after_s, static_cast<long long>(kernel_builds),
                static_cast<long long>(sdf_builds), stage_line(first).c_str(), stage_line(last).c_str(),
                stage_line(after).c_str());
    std::fflush(stdout);
  }
  std::printf("build: Planner construction (kernels, self-collision proofs), ms; map: first set_map(), ms;\n"
              "setup: the back-end's robot side built inside the first plan (per-link SDFs, terms);\n"
              "new map: set_map() of the next map (i incremental, f full) and the plan after it;\n"
              "builds: kernel robot sides (K) and per-link SDF sets (S) built for the scene (1 each: never rebuilt)\n");
  return 0;
}
