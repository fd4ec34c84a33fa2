#include "porter/backend/robot_sdf.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <numeric>

#include "porter/backend/task_team.hpp"

namespace porter::backend {

namespace {
std::atomic<std::int64_t> g_builds{0};
}  // namespace

std::int64_t RobotSdf::build_count() { return g_builds.load(std::memory_order_relaxed); }

RobotSdf RobotSdf::build(const RobotModel& model, const SdfGridSettings& settings, int threads) {
  g_builds.fetch_add(1, std::memory_order_relaxed);
  RobotSdf sdf;
  sdf.settings_ = settings;
  // The links are independent: the largest first (bounds volume over the fine spacing cubed, the
  // node count the build visits), each participant taking the next one left.
  std::array<double, kNumLinks> work{};
  for (int j = 0; j < kNumLinks; ++j) {
    const Eigen::AlignedBox3d& box = model.links[static_cast<std::size_t>(j)].bounds;  // ordering only
    if (box.isEmpty() || !box.sizes().allFinite()) continue;
    const double h = choose_sdf_resolution(box, settings);
    work[static_cast<std::size_t>(j)] = (box.sizes().array() / h + 1.0).prod();
  }
  std::array<int, kNumLinks> order{};
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return work[static_cast<std::size_t>(a)] > work[static_cast<std::size_t>(b)];
  });
  std::atomic<int> next{0};
  TaskTeam team(std::max(1, threads), 0);
  team.run([&](int) {
    for (int k = next.fetch_add(1); k < kNumLinks; k = next.fetch_add(1)) {
      const int j = order[static_cast<std::size_t>(k)];
      sdf.links_[static_cast<std::size_t>(j)] = LinkSdf::build(model.links[static_cast<std::size_t>(j)].shapes, settings);
    }
  });
  return sdf;
}

}  // namespace porter::backend
