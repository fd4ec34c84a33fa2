// The validator's forward kinematics agrees with the core's (two independent implementations of
// the model's joint origins and axes) and pairs follow the model's allowed-collision matrix.
#include <random>

#include <gtest/gtest.h>

#include "porter/core/kinematics.hpp"
#include "porter/validation/chain_kinematics.hpp"
#include "validation_fixture.hpp"

namespace porter::validation {
namespace {

TEST(ChainKinematics, AgreesWithTheCoreKinematicsAtRandomConfigurations) {
  const RobotModel& model = test::robot();
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  KinematicsWorkspace ws;
  for (int n = 0; n < 200; ++n) {
    RobotConfiguration c;
    c.base = {-5 + 10 * u(rng), -5 + 10 * u(rng), -M_PI + 2 * M_PI * u(rng)};
    WholeBodyConfig w{c.base.x_m, c.base.y_m, c.base.yaw_rad, {}};
    for (int j = 0; j < kNumArmJoints; ++j) {
      const ArmJoint& J = model.joints[static_cast<size_t>(j)];
      c.q_rad[j] = w.q_rad[j] = J.lower_rad + (J.upper_rad - J.lower_rad) * u(rng);
    }
    forward_kinematics(model, c, ws);
    const BodyPoses T = body_poses(model, w);
    for (int k = 0; k < kNumLinks; ++k)
      EXPECT_TRUE(T[static_cast<size_t>(k)].matrix().isApprox(ws.T_W_L[static_cast<size_t>(k)].matrix(), 1e-12))
          << "link " << k;
    EXPECT_TRUE(T[kPayloadBody].isApprox(ws.T_W_L[kNumLinks - 1], 1e-12));
  }
}

TEST(ChainKinematics, RodriguesRotation) {
  const Eigen::Vector3d axis = Eigen::Vector3d(1, -2, 0.5).normalized();
  EXPECT_TRUE(axis_rotation(axis, 0.7).isApprox(Eigen::AngleAxisd(0.7, axis).toRotationMatrix(), 1e-14));
}

TEST(ChainKinematics, SelfPairsFollowTheAllowedMatrixAndThePayloadCountsAsLink7) {
  const RobotModel& model = test::robot();
  for (int a = 0; a < kNumBodies; ++a)
    for (int b = 0; b < kNumBodies; ++b) {
      const int la = a == kPayloadBody ? 7 : a, lb = b == kPayloadBody ? 7 : b;
      const bool expect = la != lb && !model.allowed_collisions[static_cast<size_t>(la)][static_cast<size_t>(lb)];
      EXPECT_EQ(self_pair_checked(model, a, b), expect) << a << " " << b;
    }
  EXPECT_FALSE(self_pair_checked(model, 3, 4));            // adjacent
  EXPECT_TRUE(self_pair_checked(model, 0, 3));              // base and upper arm
  EXPECT_TRUE(self_pair_checked(model, 0, kPayloadBody));   // base and payload
  EXPECT_FALSE(self_pair_checked(model, 7, kPayloadBody));  // rigidly attached
}

}  // namespace
}  // namespace porter::validation
