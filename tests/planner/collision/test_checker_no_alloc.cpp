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

// Every replaceable form is replaced, so that no block is allocated by one allocator and freed
// by another: with only operator new(size_t) replaced, libstdc++'s nothrow form (std::stable_sort's
// temporary buffer, used when the self-collision pairs are built) came from ASan's allocator and
// reached the free()-based delete below: ASan's alloc-dealloc-mismatch. The aligned forms
// (over-aligned types) are counted too.
namespace {
void* counted_alloc(std::size_t n) noexcept {
  ++g_allocations;
  return std::malloc(n ? n : 1);
}
void* counted_aligned_alloc(std::size_t n, std::align_val_t align) noexcept {
  ++g_allocations;
  const auto a = static_cast<std::size_t>(align);
  return std::aligned_alloc(a, (n + a - 1) / a * a + (n == 0 ? a : 0));
}
}  // namespace

void* operator new(std::size_t n) {
  if (void* p = counted_alloc(n)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) {
  if (void* p = counted_alloc(n)) return p;
  throw std::bad_alloc();
}
void* operator new(std::size_t n, const std::nothrow_t&) noexcept { return counted_alloc(n); }
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept { return counted_alloc(n); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
void* operator new(std::size_t n, std::align_val_t a) {
  if (void* p = counted_aligned_alloc(n, a)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n, std::align_val_t a) {
  if (void* p = counted_aligned_alloc(n, a)) return p;
  throw std::bad_alloc();
}
void* operator new(std::size_t n, std::align_val_t a, const std::nothrow_t&) noexcept {
  return counted_aligned_alloc(n, a);
}
void* operator new[](std::size_t n, std::align_val_t a, const std::nothrow_t&) noexcept {
  return counted_aligned_alloc(n, a);
}
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }

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
