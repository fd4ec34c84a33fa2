// Trajectory queries must not allocate: the tracker evaluates them in its 100 Hz loop.
// This executable replaces the global allocation functions to count calls.

#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>
#include <vector>

#include "porter/core/trajectory.hpp"

namespace {
std::atomic<long> g_allocations{0};

void* counted_alloc(std::size_t n) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(n == 0 ? 1 : n)) return p;
  throw std::bad_alloc();
}
}  // namespace

void* operator new(std::size_t n) { return counted_alloc(n); }
void* operator new[](std::size_t n) { return counted_alloc(n); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  return std::malloc(n == 0 ? 1 : n);
}
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  return std::malloc(n == 0 ? 1 : n);
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }

namespace porter {
namespace {

TEST(TrajectoryAlloc, QueriesDoNotAllocate) {
  std::vector<TrajectoryPiece> pieces(6);
  for (size_t i = 0; i < pieces.size(); ++i) {
    pieces[i].duration_s = 0.5 + 0.1 * static_cast<double>(i);
    pieces[i].eta = (i % 2 == 0) ? 1 : -1;
    for (int k = 0; k < kTrajNumCoeffs; ++k)
      for (int d = 0; d < kTrajDim; ++d)
        pieces[i].coeffs(k, d) = std::sin(1.0 + k + 3.0 * d + 7.0 * static_cast<double>(i));
  }
  pieces[3].coeffs.block<5, 2>(1, 0).setZero();  // a held-heading piece
  TrajectoryResult r = Trajectory::create(pieces, 0.2);
  ASSERT_TRUE(r.ok()) << r.error;
  const Trajectory& traj = *r.trajectory;

  const long before = g_allocations.load();
  double sum = 0.0;
  double tau = 0.0;
  for (int s = -10; s <= 1010; ++s) {
    const double t = traj.total_duration_s() * s / 1000.0;
    sum += traj.locate(t, &tau) + tau;
    for (int order = 0; order <= 6; ++order) sum += traj.derivative(t, order).sum();
    sum += traj.yaw_rad(t) + traj.base_motion(t).yaw_accel_radps2;
    sum += traj.wheel_rates(t, 0.4, 0.08).left_radps2;
    sum += traj.sample(t, 0.4, 0.08).wheels.right_radps;
  }
  const long after = g_allocations.load();
  EXPECT_EQ(after, before);
  EXPECT_TRUE(std::isfinite(sum));
  // The counter does see allocations (so the check above can fail).
  std::vector<double>* probe = new std::vector<double>(3);
  EXPECT_GT(g_allocations.load(), after);
  delete probe;
}

}  // namespace
}  // namespace porter
