// Queries of the kernel checker must not touch the heap: this binary counts every operator new.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>
#include <random>

#include "collision_test_utils.hpp"
#include "porter/core/scene_voxelizer.hpp"
#include "porter/core/trajectory.hpp"
#include "porter/planner/collision/kernel_collision_checker.hpp"

namespace {
std::atomic<long> g_allocations{0};
}

void* operator new(std::size_t n) {
  ++g_allocations;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace porter::planner {
namespace {

TEST(KernelCheckerNoAlloc, QueriesDoNotAllocate) {
  const RobotModel model = test::shipped_robot_with("t_bar");
  const Scene scene = test::shipped_scene("forest");
  KernelCollisionChecker checker(model);
  checker.set_map(voxelize(scene));
  std::mt19937_64 rng(5);
  std::vector<RobotConfiguration> configs;
  for (int i = 0; i < 2000; ++i) configs.push_back(test::random_configuration(model, scene, rng));
  TrajVector p0 = TrajVector::Zero(), p1 = TrajVector::Zero(), v = TrajVector::Zero();
  p0 << 1.0, 0.0, 0.0, 0.6, -0.9, 0.0, 0.5, 0.0;
  p1 << 3.0, 0.5, 0.0, 0.6, -0.9, 0.0, 0.5, 0.0;
  TrajectoryPiece piece;
  piece.duration_s = 4.0;
  piece.coeffs = quintic_hermite(p0, v, v, p1, v, v, 4.0);
  const TrajectoryResult traj = Trajectory::create({piece}, 0.0);
  ASSERT_TRUE(traj.ok());
  std::vector<CollisionResult> results(configs.size());
  int sink = 0;
  const long before = g_allocations.load();
  checker.check_batch(configs.data(), configs.size(), results.data());
  for (const CollisionResult& r : results) sink += r.in_collision;
  for (std::size_t i = 0; i + 1 < configs.size(); ++i) {
    sink += checker.check(configs[i]).in_collision;
    sink += checker.check_base(configs[i].base).in_collision;
    sink += checker.check_self(configs[i].q_rad).in_collision;
    if (i % 50 == 0) sink += checker.check_motion(configs[i], configs[i + 1]).in_collision;
  }
  sink += checker.check_trajectory(*traj.trajectory).in_collision;
  EXPECT_EQ(g_allocations.load(), before);
  EXPECT_GT(sink, 0);
}

}  // namespace
}  // namespace porter::planner
