#include "porter/backend/recheck_margins.hpp"

#include <algorithm>
#include <cmath>

namespace porter::backend {

RecheckMargins recheck_margins(const std::array<double, kNumLinks>& inflation_m, double voxel_m,
                               const RobotSdf& sdf, double slack_m) {
  RecheckMargins m;
  const double half_diagonal = 0.5 * std::sqrt(3.0) * voxel_m;
  for (std::size_t j = 0; j < kNumLinks; ++j) {
    const LinkSdf& link = sdf.link(static_cast<int>(j));
    const double err = link.empty() ? 0.0 : link.fine().error_bound_m();
    const double inflation = std::max(0.0, inflation_m[j]);
    m.obstacle_m[j] = inflation + half_diagonal + err + slack_m;
    const double up = inflation + 0.5 * voxel_m;
    m.ground_m[j] = std::min(m.obstacle_m[j], std::sqrt(up * up + 0.5 * voxel_m * voxel_m) + err + slack_m);
  }
  return m;
}

void apply_recheck_margins(const RecheckMargins& margins, SvsdfSafetySettings& settings) {
  settings.link_margin_m = margins.obstacle_m;
  settings.link_ground_margin_m = margins.ground_m;
}

}  // namespace porter::backend
