// porter-bench-collision: whole-body kernel collision checks (paper §IV-C) against mesh-level
// FCL 0.7 on the same configurations. A benchmark, not a test: it prints, asserts nothing.
//
//   build-*/tests/bench/porter-bench-collision [--quick]
//
// Fixed seeds, shipped scenes `tunnel` and `forest` with the T payload, one thread. Times are
// thread CPU time (the machine may be shared); each figure is the best of 5 passes. Frozen
// fixture: do not change the seeds, the counts or the selection rules, or results stop being
// comparable.
//
// Configuration sets (per scene):
//   free-near  whole-body free (kernel check, self-collision included) but in collision with a
//              0.3 m safety margin: free configurations close to obstacles, the expensive case;
//   colliding  in collision (kernel check), with the same closeness filter;
// each in two orders: "scattered" (independent uniform draws over the whole map, cold caches)
// and "local" (64 configurations around each base pose drawn, as a search expanding one node or
// an arm layer at one base waypoint sees them).
// Columns: whole-body check() (environment + self-collision), the same set through check_batch()
// (eight configurations per pass, one per lane; what motion and trajectory checks use), then
// check()'s environment part and self-collision part alone (each including forward kinematics),
// forward kinematics alone, FCL on the first 2000 of the set; the ratios are kernel checks per
// second over FCL checks per second, for check() and (last column) for check_batch().
// FCL: every link as one BVH (OBBRSS) mesh plus the non-allowed link pairs, against two obstacle
// models: "FCL exact" = the scene's exact obstacles as meshes in a dynamic AABB tree (FCL's best
// case: a handful of primitives), "FCL map" = an fcl::OcTree of the same occupancy grid the
// kernels test (what a deployed stack has: a voxel map from the LiDAR mapper). The ground and the
// map bounds are not modelled for FCL (less work).

#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "collision_test_utils.hpp"
#include "fcl_geometry.hpp"
#include "porter/core/scene_voxelizer.hpp"
#include "porter/planner/collision/kernel_collision_checker.hpp"

namespace {

using namespace porter;
using namespace porter::planner;

double cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

/// Best-of-`passes` CPU seconds of fn().
double best_time(int passes, const std::function<void()>& fn) {
  double best = 1e30;
  for (int p = 0; p < passes; ++p) {
    const double t0 = cpu_seconds();
    fn();
    best = std::min(best, cpu_seconds() - t0);
  }
  return best;
}

struct ConfigSets {
  std::vector<RobotConfiguration> free_scattered, colliding_scattered, free_local, colliding_local;
};

ConfigSets make_sets(const RobotModel& model, const Scene& scene, const KernelCollisionChecker& checker,
                     const KernelCollisionChecker& near, int count, std::uint64_t seed) {
  ConfigSets s;
  std::mt19937_64 rng(seed);
  auto classify = [&](const RobotConfiguration& c, std::vector<RobotConfiguration>& free_set,
                      std::vector<RobotConfiguration>& coll_set) {
    if (!near.check_environment(c).in_collision) return;
    if (checker.check(c).in_collision) {
      if (static_cast<int>(coll_set.size()) < count) coll_set.push_back(c);
    } else if (static_cast<int>(free_set.size()) < count) {
      free_set.push_back(c);
    }
  };
  while (static_cast<int>(s.free_scattered.size()) < count || static_cast<int>(s.colliding_scattered.size()) < count)
    classify(test::random_configuration(model, scene, rng, 0.1), s.free_scattered, s.colliding_scattered);
  while (static_cast<int>(s.free_local.size()) < count || static_cast<int>(s.colliding_local.size()) < count) {
    const RobotConfiguration anchor = test::random_configuration(model, scene, rng, 0.4);
    std::vector<RobotConfiguration> f, c;
    for (int i = 0; i < 64 * 8 && (f.size() < 64 || c.size() < 64); ++i) {
      RobotConfiguration x = anchor;
      x.base.x_m += test::uniform(rng, -0.25, 0.25);
      x.base.y_m += test::uniform(rng, -0.25, 0.25);
      x.base.yaw_rad += test::uniform(rng, -0.3, 0.3);
      x.q_rad = test::random_joints(model, rng);
      classify(x, f, c);
    }
    for (const auto& x : f)
      if (static_cast<int>(s.free_local.size()) < count) s.free_local.push_back(x);
    for (const auto& x : c)
      if (static_cast<int>(s.colliding_local.size()) < count) s.colliding_local.push_back(x);
  }
  return s;
}

void bench_scene(const std::string& name, bool quick) {
  const RobotModel model = test::shipped_robot_with("t_bar");
  const Scene scene = test::shipped_scene(name);
  std::printf("\n== scene %s, payload t_bar ==\n", name.c_str());

  const auto t_build = std::chrono::steady_clock::now();
  KernelCollisionChecker checker(model);
  const double build_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_build).count();
  OccupancyGrid grid = voxelize(scene);
  const double set_map_s = best_time(1, [&] { checker.set_map(grid); });
  // An incremental update: a 0.3 x 0.3 x 1 m box appears a quarter of the way along the map.
  OccupancyGrid changed = grid;
  const Eigen::Vector3i mid(grid.dims().x() / 4, grid.dims().y() / 2, 0);
  for (int z = 0; z < 20; ++z)
    for (int y = -3; y < 3; ++y)
      for (int x = -3; x < 3; ++x) changed.set(mid.x() + x, mid.y() + y, z);
  const double update_s = best_time(1, [&] { checker.set_map(changed); });
  const long changed_voxels = static_cast<long>(checker.last_map_update().changed_voxels);
  checker.set_map(grid);
  KernelCheckerSettings wide;
  wide.map.safety_margin_m = 0.3;
  KernelCollisionChecker near(model, wide);
  near.set_map(grid);

  const KernelStorage st = checker.storage();
  std::printf("kernels: %d (N0 %d", st.kernel_count, checker.kernels().num_samples(0));
  for (int j = 1; j < kNumLinks; ++j) std::printf(" + %d", checker.kernels().num_samples(j));
  std::printf("), robot kernels %.1f kB, self-collision %.1f kB, map kernel %.1f kB (grid %d x %d x %d)\n",
              st.robot_kernel_bytes / 1024.0, st.self_collision_bytes / 1024.0, st.map_kernel_bytes / 1024.0,
              grid.dims().x(), grid.dims().y(), grid.dims().z());
  std::printf("build (kernels + self proofs) %.0f ms; set_map full %.1f ms, incremental %.1f ms (%ld voxels changed)\n",
              1e3 * build_s, 1e3 * set_map_s, 1e3 * update_s, changed_voxels);

  const int count = quick ? 2000 : 20000;
  const ConfigSets sets = make_sets(model, scene, checker, near, count, 2024);
  test::FclWorld fcl(model, scene.obstacles);
  test::FclWorld fcl_map(model, grid);
  const int fcl_count = quick ? 200 : 2000;
  std::printf("%-20s %9s %7s %9s %7s %6s %6s %5s %11s %5s %10s %5s %5s\n", "set", "check/s", "ns", "batch/s", "ns",
              "env ns", "self", "FK", "FCL exact/s", "ratio", "FCL map/s", "ratio", "batch");
  auto run = [&](const char* label, const std::vector<RobotConfiguration>& v) {
    int sink = 0;
    const double tk = best_time(5, [&] {
      for (const auto& c : v) sink += checker.check(c).in_collision;
    });
    std::vector<CollisionResult> results(v.size());
    const double tb = best_time(5, [&] {
      checker.check_batch(v.data(), v.size(), results.data());
      for (const CollisionResult& r : results) sink += r.in_collision;
    });
    const double te = best_time(5, [&] {
      for (const auto& c : v) sink += checker.check_environment(c).in_collision;
    });
    const double ts = best_time(5, [&] {
      for (const auto& c : v) sink += checker.check_self(c.q_rad).in_collision;
    });
    ArmPoses poses;
    const double tq = best_time(5, [&] {
      for (const auto& c : v) {
        checker.kinematics().compute(c.q_rad, poses);
        sink += poses.T_B_L[kEndEffectorLink].t[0] > 1e9f;
      }
    });
    const std::vector<RobotConfiguration> sub(v.begin(), v.begin() + std::min<std::size_t>(v.size(), fcl_count));
    const double tf = best_time(1, [&] {
      for (const auto& c : sub) sink += fcl.in_collision(c);
    });
    const double tm = best_time(1, [&] {
      for (const auto& c : sub) sink += fcl_map.in_collision(c);
    });
    const double n = static_cast<double>(v.size());
    const double kernel_rate = n / tk, batch_rate = n / tb, fcl_rate = static_cast<double>(sub.size()) / tf;
    const double map_rate = static_cast<double>(sub.size()) / tm;
    std::printf("%-20s %9.3g %7.1f %9.3g %7.1f %6.1f %6.1f %5.1f %11.3g %4.0fx %10.3g %4.0fx %4.0fx%s\n", label,
                kernel_rate, 1e9 * tk / n, batch_rate, 1e9 * tb / n, 1e9 * te / n, 1e9 * ts / n, 1e9 * tq / n, fcl_rate,
                kernel_rate / fcl_rate, map_rate, kernel_rate / map_rate, batch_rate / map_rate, sink < 0 ? "!" : "");
  };
  run("free-near scattered", sets.free_scattered);
  run("free-near local", sets.free_local);
  run("colliding scattered", sets.colliding_scattered);
  run("colliding local", sets.colliding_local);

  // Motion checks between free configurations 0.5-2 m apart (base), arm moving too; the cost
  // per metre of base travel over the free ones.
  std::mt19937_64 rng(77);
  std::vector<std::pair<RobotConfiguration, RobotConfiguration>> segments;
  double metres = 0.0;
  while (static_cast<int>(segments.size()) < (quick ? 50 : 300)) {
    const RobotConfiguration& a = sets.free_scattered[rng() % sets.free_scattered.size()];
    RobotConfiguration b = a;
    const double d = test::uniform(rng, 0.5, 2.0), dir = test::uniform(rng, -M_PI, M_PI);
    b.base.x_m += d * std::cos(dir);
    b.base.y_m += d * std::sin(dir);
    b.base.yaw_rad += test::uniform(rng, -0.5, 0.5);
    for (int j = 0; j < kNumArmJoints; ++j) b.q_rad[j] += test::uniform(rng, -0.2, 0.2);
    if (checker.check(b).in_collision || checker.check_motion(a, b).in_collision) continue;
    segments.emplace_back(a, b);
    metres += d;
  }
  long samples = 0;
  for (const auto& s : segments) samples += checker.motion_intervals(s.first, s.second) + 1;
  int sink = 0;
  const double tm = best_time(5, [&] {
    for (const auto& s : segments) sink += checker.check_motion(s.first, s.second).in_collision;
  });
  std::printf("motion checks (free segments): %.1f us per metre of base travel, %.0f samples/m (step %.3f m)%s\n",
              1e6 * tm / metres, samples / metres, checker.motion_step_m(), sink ? "!" : "");
}

}  // namespace

int main(int argc, char** argv) {
  const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
  std::printf("porter-bench-collision%s: kernel whole-body checks (env + self) vs FCL mesh-level\n",
              quick ? " --quick" : "");
  for (const char* scene : {"tunnel", "forest"}) bench_scene(scene, quick);
  return 0;
}
