#pragma once
// Internal: base-only collision checks along arcs and chords (Hybrid A*, shots).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "porter/core/robot_model.hpp"
#include "porter/planner/angle.hpp"
#include "porter/frontend/reeds_shepp.hpp"
#include "porter/planner/collision/collision_checker.hpp"

namespace porter::frontend::detail {

/// Linear interpolation in (x, y) and along the shorter way in yaw.
inline BasePose lerp_pose(const BasePose& a, const BasePose& b, double t) {
  return {a.x_m + t * (b.x_m - a.x_m), a.y_m + t * (b.y_m - a.y_m),
          planner::wrap_angle_rad(a.yaw_rad + t * planner::wrap_angle_rad(b.yaw_rad - a.yaw_rad))};
}

/// Largest horizontal distance of the base geometry (link 0's bounds) from the base origin: a
/// yaw change dyaw moves no base point more than this times |dyaw|.
inline double base_reach_m(const RobotModel& model) {
  const Eigen::AlignedBox3d& b = model.links[0].bounds;
  if (b.isEmpty()) return 0.0;
  const double x = std::max(std::abs(b.min().x()), std::abs(b.max().x()));
  const double y = std::max(std::abs(b.min().y()), std::abs(b.max().y()));
  return std::hypot(x, y);
}

/// Samples needed so that no base point moves more than step_m between neighbours: the
/// translation plus reach times the heading change (a turning primitive swings the corners).
inline int base_motion_samples(double length_m, double dyaw_rad, double reach_m, double step_m) {
  return std::max(1, static_cast<int>(std::ceil((std::abs(length_m) + reach_m * std::abs(dyaw_rad)) / step_m)));
}

/// Checks the base at the interior and end samples of the arc (the start is assumed checked).
inline bool base_arc_free(const planner::CollisionChecker& checker, const BasePose& from, double kappa,
                          double signed_length_m, double reach_m, double step_m, std::int64_t* checks) {
  const int n = base_motion_samples(signed_length_m, kappa * signed_length_m, reach_m, step_m);
  for (int k = n; k >= 1; --k) {  // end first: it is the likeliest to fail
    ++*checks;
    if (checker.check_base(drive_arc(from, kappa, signed_length_m * k / n))) return false;
  }
  return true;
}

/// Checks the base at interior samples of the straight chord a -> b (ends assumed checked), at
/// i / n, i = 1..n-1, n = base_motion_samples(|dxy|, dyaw, reach_m, step_m). With reach_m the
/// whole body's reach (ChainRadii::reach_m) and step_m the kernel checker's motion step, these
/// are the base poses KernelCollisionChecker::check_motion() samples when the arm is held, so a
/// chord accepted here never fails there on the base alone.
inline bool base_chord_free(const planner::CollisionChecker& checker, const BasePose& a, const BasePose& b,
                            double reach_m, double step_m, std::int64_t* checks) {
  const int n = base_motion_samples(std::hypot(b.x_m - a.x_m, b.y_m - a.y_m), planner::wrap_angle_rad(b.yaw_rad - a.yaw_rad),
                                    reach_m, step_m);
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
