#pragma once
// Internal: base-only collision checks along arcs and chords (Hybrid A*, shots).

#include <cmath>
#include <cstdint>
#include <vector>

#include "porter/frontend/reeds_shepp.hpp"
#include "porter/planner/collision/collision_checker.hpp"

namespace porter::frontend::detail {

/// Linear interpolation in (x, y) and along the shorter way in yaw.
inline BasePose lerp_pose(const BasePose& a, const BasePose& b, double t) {
  return {a.x_m + t * (b.x_m - a.x_m), a.y_m + t * (b.y_m - a.y_m),
          wrap_angle(a.yaw_rad + t * wrap_angle(b.yaw_rad - a.yaw_rad))};
}

/// Checks the base at the interior and end samples of the arc (the start is assumed checked).
inline bool base_arc_free(const planner::CollisionChecker& checker, const BasePose& from, double kappa,
                          double signed_length_m, double step_m, std::int64_t* checks) {
  const int n = std::max(1, static_cast<int>(std::ceil(std::abs(signed_length_m) / step_m - 1e-9)));
  for (int k = n; k >= 1; --k) {  // end first: it is the likeliest to fail
    ++*checks;
    if (checker.check_base(drive_arc(from, kappa, signed_length_m * k / n))) return false;
  }
  return true;
}

/// Checks the base at interior samples of the straight chord a -> b (ends assumed checked).
inline bool base_chord_free(const planner::CollisionChecker& checker, const BasePose& a, const BasePose& b,
                            double step_m, std::int64_t* checks) {
  const double len = std::hypot(b.x_m - a.x_m, b.y_m - a.y_m);
  const int n = static_cast<int>(std::ceil(len / step_m - 1e-9));
  for (int k = 1; k < n; ++k) {
    ++*checks;
    if (checker.check_base(lerp_pose(a, b, static_cast<double>(k) / n))) return false;
  }
  return true;
}

/// Checks samples[i] for i in [1, size) in a coarse-to-fine order (every 8th first, then every
/// 4th, ...), so that a colliding long shot is usually rejected after a few checks.
inline bool base_samples_free(const planner::CollisionChecker& checker, const std::vector<BaseSample>& samples,
                              std::int64_t* checks) {
  for (std::size_t stride = 8; stride >= 1; stride /= 2) {
    for (std::size_t i = stride; i < samples.size(); i += stride) {
      if (stride < 8 && i % (2 * stride) == 0) continue;  // done in a coarser pass
      ++*checks;
      if (checker.check_base(samples[i].pose)) return false;
    }
  }
  return true;
}

}  // namespace porter::frontend::detail
