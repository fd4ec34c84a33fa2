#pragma once
// Planar rigid transforms (SE(2)) on porter::BasePose {x_m, y_m, yaw_rad}, for odometry
// arithmetic. A BasePose used as a transform T_A_B maps points in B to points in A.
//
// Thread-safety: pure functions. Failure: none (non-finite inputs give non-finite outputs).

#include "porter/core/types.hpp"

namespace porter::state {

/// Wraps an angle to (-pi, pi], rad.
double wrap_angle(double angle_rad);

/// T_A_C = T_A_B * T_B_C.
BasePose compose(const BasePose& T_A_B, const BasePose& T_B_C);
/// T_B_A = T_A_B^-1.
BasePose inverse(const BasePose& T_A_B);
/// T_A_B^-1 * T_A_C = T_B_C: the motion from B to C, expressed in B.
BasePose between(const BasePose& T_A_B, const BasePose& T_A_C);
/// Pose at fraction s in [0, 1] from a to b: positions linearly, heading along the shorter arc.
BasePose interpolate(const BasePose& a, const BasePose& b, double s);
/// Unicycle motion over dt_s at forward speed v_mps and yaw rate omega_radps (exact arc).
BasePose integrate_unicycle(const BasePose& start, double v_mps, double omega_radps, double dt_s);

}  // namespace porter::state
