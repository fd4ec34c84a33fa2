#include "porter/planner/collision/kernel_kinematics.hpp"
#include "porter/planner/collision/simd8.hpp"

#include <algorithm>
#include <cmath>

namespace porter::planner {

namespace {

double link_radius(const Link& link) {
  double r = 0.0;
  for (const auto& s : link.shapes) r = std::max(r, shape_max_distance(s, Eigen::Vector3d::Zero()));
  return r;
}

}  // namespace

ChainRadii compute_chain_radii(const RobotModel& model) {
  ChainRadii out;
  for (int j = 0; j < kNumLinks; ++j)
    out.link_radius_m[static_cast<std::size_t>(j)] = link_radius(model.links[static_cast<std::size_t>(j)]);
  // offset[i]: distance from frame i-1's origin to frame i's origin (i = 1..7).
  std::array<double, kNumLinks> offset{};
  for (int i = 1; i <= kNumArmJoints; ++i)
    offset[static_cast<std::size_t>(i)] =
        model.joints[static_cast<std::size_t>(i - 1)].T_parent_joint.translation().norm();
  offset[kEndEffectorLink] = model.T_L6_EE.translation().norm();
  auto chain_reach = [&](int from) {
    double best = 0.0, along = 0.0;
    for (int k = from; k < kNumLinks; ++k) {
      if (k > from) along += offset[static_cast<std::size_t>(k)];
      best = std::max(best, along + out.link_radius_m[static_cast<std::size_t>(k)]);
    }
    return best;
  };
  for (int j = 1; j <= kNumArmJoints; ++j) out.sweep_radius_m[static_cast<std::size_t>(j - 1)] = chain_reach(j);
  out.reach_m = std::max(out.link_radius_m[0], chain_reach(1) + offset[1]);
  return out;
}

KernelKinematics::FixedTransform::FixedTransform(const Eigen::Isometry3d& iso) : T(iso) {
  const Eigen::Matrix3d R = iso.linear();
  if ((R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() < 1e-12) {
    kind = Kind::kTranslation;
    return;
  }
  for (int j = 0; j < 3; ++j) {
    int k = 0;
    R.col(j).cwiseAbs().maxCoeff(&k);
    const Eigen::Vector3d e = (R(k, j) > 0 ? 1.0 : -1.0) * Eigen::Vector3d::Unit(k);
    if ((R.col(j) - e).cwiseAbs().maxCoeff() > 1e-12) return;  // general rotation
    column[static_cast<std::size_t>(j)] = k;
    sign[static_cast<std::size_t>(j)] = R(k, j) > 0 ? 1.f : -1.f;
  }
  kind = Kind::kPermutation;
}

KernelKinematics::KernelKinematics(const RobotModel& model) : T_L6_EE_(model.T_L6_EE) {
  for (int j = 0; j < kNumArmJoints; ++j) {
    const auto i = static_cast<std::size_t>(j);
    T_parent_joint_[i] = FixedTransform(model.joints[i].T_parent_joint);
    const Eigen::Vector3d a = model.joints[i].axis.normalized();
    Eigen::Matrix3d K;
    K << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
    K_[i] = K;
    K2_[i] = K * K;
    if (a.x() == 0.0 && a.y() == 0.0) z_axis_[i] = a.z() > 0.0 ? 1 : -1;
  }
}

PORTER_KERNEL_CLONES void KernelKinematics::compute(const JointVector& q_rad, ArmPoses& poses) const {
  poses.T_B_J[0] = Pose4f::identity();
  poses.T_B_L[0] = Pose4f::identity();
  static_assert(kNumArmJoints == 6, "two joints in the upper half");
  const v4d q_lo{q_rad[0], q_rad[1], q_rad[2], q_rad[3]}, q_hi{q_rad[4], q_rad[5], 0.0, 0.0};
  v8f sin8, cos8;
  fast_sincos8(q_lo, q_hi, &sin8, &cos8);
  for (int j = 1; j <= kNumArmJoints; ++j) {
    const auto i = static_cast<std::size_t>(j - 1);
    const auto sj = static_cast<std::size_t>(j);
    const float s = sin8[j - 1], c = cos8[j - 1];
    poses.T_B_J[sj] = T_parent_joint_[i].after(poses.T_B_L[sj - 1]);
    if (z_axis_[i] != 0) {
      poses.T_B_L[sj] = poses.T_B_J[sj].rotated_z(c, static_cast<float>(z_axis_[i]) * s);
    } else {
      Eigen::Isometry3d Rq = Eigen::Isometry3d::Identity();  // general axis (not +-z)
      Rq.linear() += double(s) * K_[i] + (1.0 - double(c)) * K2_[i];
      poses.T_B_L[sj] = poses.T_B_J[sj] * Pose4f(Rq);
    }
  }
  poses.T_B_L[kEndEffectorLink] = T_L6_EE_.after(poses.T_B_L[kNumArmJoints]);
  poses.T_B_J[kEndEffectorLink] = poses.T_B_L[kEndEffectorLink];
}

PORTER_KERNEL_CLONES void KernelKinematics::compute_lanes(const std::array<const JointVector*, 8>& q_rad,
                                                           ArmPoseLanes& poses) const {
  poses.T_B_J[0].set_all(Pose4f::identity());
  poses.T_B_L[0] = poses.T_B_J[0];
  for (int j = 1; j <= kNumArmJoints; ++j) {
    const auto i = static_cast<std::size_t>(j - 1);
    const auto sj = static_cast<std::size_t>(j);
    const v4d q_lo{(*q_rad[0])[j - 1], (*q_rad[1])[j - 1], (*q_rad[2])[j - 1], (*q_rad[3])[j - 1]};
    const v4d q_hi{(*q_rad[4])[j - 1], (*q_rad[5])[j - 1], (*q_rad[6])[j - 1], (*q_rad[7])[j - 1]};
    v8f s, c;
    fast_sincos8(q_lo, q_hi, &s, &c);
    T_parent_joint_[i].after(poses.T_B_L[sj - 1], poses.T_B_J[sj]);
    if (z_axis_[i] != 0) {
      PoseLanes::rotated_z(poses.T_B_J[sj], c, z_axis_[i] > 0 ? s : -s, poses.T_B_L[sj]);
    } else {
      // Rodrigues per lane: R(q) = I + s K + (1 - c) K^2 (general axis, not +-z).
      PoseLanes Rq;
      const v8f one_c = v8f_splat(1.f) - c;
      for (int a = 0; a < 3; ++a) {
        for (int b = 0; b < 3; ++b)
          Rq.r[a][b] = v8f_splat(a == b ? 1.f : 0.f) + s * v8f_splat(static_cast<float>(K_[i](a, b))) +
                       one_c * v8f_splat(static_cast<float>(K2_[i](a, b)));
        Rq.t[a] = v8f_splat(0.f);
      }
      PoseLanes::compose(poses.T_B_J[sj], Rq, poses.T_B_L[sj]);
    }
  }
  T_L6_EE_.after(poses.T_B_L[kNumArmJoints], poses.T_B_L[kEndEffectorLink]);
  poses.T_B_J[kEndEffectorLink] = poses.T_B_L[kEndEffectorLink];
}

}  // namespace porter::planner
