#pragma once
// Forward kinematics of the Piper's flange from its published modified-DH table (Craig's
// convention, link transform RotX(alpha) TransX(a) RotZ(theta + offset) TransZ(d)), with the
// 2-degree J2/J3 offset of current firmware (the SDK's dh_is_offset = 1):
//   a     = [0, 0, 285.03, -21.98, 0, 0] mm
//   alpha = [0, -90, 0, 90, -90, 90] degrees
//   d     = [123, 0, 0, 250.75, 0, 91] mm
//   theta offset = [0, -172.22, -102.78, 0, 0, 0] degrees
// At q = 0 the flange is at (56.128, 0, 213.266) mm with roll, pitch, yaw = (0, 85, 0) degrees.
// The firmware model uses it for the 0x2A2..0x2A4 end-pose frames.
//
// Thread-safety: pure function.

#include <array>

namespace porter::piper {

struct FlangePose {
  std::array<double, 3> p_m{};      ///< flange origin in the arm's base frame, m
  std::array<double, 3> rpy_rad{};  ///< roll, pitch, yaw: R = Rz(yaw) Ry(pitch) Rx(roll)
};

FlangePose piper_flange_pose(const std::array<double, 6>& q_rad);

}  // namespace porter::piper
