// FK and Jacobian calls must not touch the heap: this binary counts every operator new.
#include <atomic>
#include <cstdlib>
#include <new>

#include <gtest/gtest.h>

#include "porter/core/kinematics.hpp"
#include "porter/core/robot_loader.hpp"
#include "robot_test_utils.hpp"

namespace {
std::atomic<long> g_allocations{0};
}

// Every replaceable form is replaced, so that no block is allocated by one allocator and freed
// by another: with only operator new(size_t) replaced, libstdc++'s nothrow and array forms (e.g.
// std::stable_sort's temporary buffer) come from ASan's allocator and reach our
// free()-based delete, which ASan reports as alloc-dealloc-mismatch.
namespace {
void* counted_alloc(std::size_t n) noexcept {
  ++g_allocations;
  return std::malloc(n ? n : 1);
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

namespace porter {
namespace {

TEST(KinematicsNoAlloc, ForwardKinematicsAndJacobiansDoNotAllocate) {
  const RobotModel model = load_robot_model(test::robot_yaml());
  KinematicsWorkspace ws;
  RobotConfiguration c;
  PointJacobian J;
  std::array<Eigen::Isometry3d, kNumLinks> T_B_L;
  double sink = 0.0;
  const long before = g_allocations.load();
  for (int i = 0; i < 1000; ++i) {
    c.base = {0.001 * i, -0.002 * i, 0.01 * i};
    c.q_rad.setConstant(0.001 * i);
    forward_kinematics(model, c, ws);
    arm_forward_kinematics(model, c.q_rad, T_B_L);
    for (int link = 0; link < kNumLinks; ++link) {
      point_jacobian(model, ws, link, ws.T_W_L[link].translation(), J);
      sink += J.sum();
    }
  }
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_TRUE(std::isfinite(sink));
}

}  // namespace
}  // namespace porter
