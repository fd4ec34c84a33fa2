#pragma once
// The safety thresholds s_j of the SVSDF penalty, chosen so that a trajectory whose penalty is zero
// passes the final kernel re-check (paper §VI-C leaves s_thr open; this is Porter's rule).
//
// The kernel check (planner/collision robot_kernels.hpp) flags link j only when its geometry comes
// within the inflation bound I_j of an occupied voxel's box. The penalty measures d_j from voxel
// centres (obstacle_points.hpp), and a voxel's box reaches h sqrt(3)/2 from its centre; the link's
// SDF errs by at most err_j. So d_j >= I_j + h sqrt(3)/2 + err_j keeps the link out of the flagged
// set. Below the ground (voxels under z = 0, ground points at their centres) the check flags a
// link lower than I_j; a link point at height I_j is within sqrt((I_j + h/2)^2 + h^2/2) of a
// ground point (half a voxel down, at most half a diagonal sideways), so that plus err_j is the
// ground margin. A slack is added to both: the cubic penalty settles where it balances the smooth
// terms, slightly inside its threshold.
//
// Pure function; thread-safe.

#include <array>

#include "porter/backend/robot_sdf.hpp"
#include "porter/backend/svsdf_safety_term.hpp"
#include "porter/core/types.hpp"

namespace porter::backend {

struct RecheckMargins {
  std::array<double, kNumLinks> obstacle_m{};  ///< s_j
  std::array<double, kNumLinks> ground_m{};    ///< ground margin of link j
};

/// `inflation_m[j]`: the re-check's inflation bound of link j (m, >= 0); `voxel_m`: the map's voxel
/// edge h (> 0); `slack_m` >= 0.
RecheckMargins recheck_margins(const std::array<double, kNumLinks>& inflation_m, double voxel_m,
                               const RobotSdf& sdf, double slack_m = 0.01);

/// Writes `margins` into settings.link_margin_m / link_ground_margin_m.
void apply_recheck_margins(const RecheckMargins& margins, SvsdfSafetySettings& settings);

}  // namespace porter::backend
