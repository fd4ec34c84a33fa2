#pragma once
// Forward kinematics of the planning chain for the back-end's inner loops (the t* refinement runs
// it tens of times per query point): link poses only up to the link asked for (the base needs no
// arm at all), rotations and translations kept apart (3x3 products, no 4x4), no allocation.
// Same conventions and results as porter::forward_kinematics / point_jacobian (kinematics.hpp),
// which the tests use as the slow reference.
//
// Thread-safety: a ChainKinematics is immutable (share it); a Workspace belongs to one thread.

#include <array>

#include <Eigen/Core>

#include "porter/core/robot_model.hpp"
#include "porter/core/types.hpp"

namespace porter::backend {

class ChainKinematics {
 public:
  struct Workspace {
    std::array<Eigen::Matrix3d, kNumLinks> R_W_L;   ///< link orientations in W
    std::array<Eigen::Vector3d, kNumLinks> t_W_L;   ///< link origins in W
    std::array<Eigen::Vector3d, kNumArmJoints> axis_W;
    std::array<Eigen::Vector3d, kNumArmJoints> origin_W;
    int up_to = -1;                                 ///< last link computed
  };

  explicit ChainKinematics(const RobotModel& model);

  /// Poses of links 0..up_to_link (and the axes/origins of joints 1..min(up_to_link, 6)).
  void compute(const RobotConfiguration& config, int up_to_link, Workspace& ws) const;

  /// d p_W / d[x, y, yaw, q1..q6] of the point of `link` at p_W (ws computed up to `link`);
  /// columns of joints that do not move the link are zero.
  static void point_jacobian(const Workspace& ws, int link, const Eigen::Vector3d& p_W, PointJacobian& J);

 private:
  std::array<Eigen::Matrix3d, kNumArmJoints> R_parent_joint_;
  std::array<Eigen::Vector3d, kNumArmJoints> t_parent_joint_;
  std::array<Eigen::Vector3d, kNumArmJoints> axis_;
  Eigen::Matrix3d R_L6_EE_;
  Eigen::Vector3d t_L6_EE_;
};

}  // namespace porter::backend
