#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>

#include "collision_test_utils.hpp"
#include "porter/core/kinematics.hpp"
#include "porter/planner/collision/kernel_kinematics.hpp"

namespace porter::planner {
namespace {

TEST(FastSinCos, MatchesStdWithinFloatPrecision) {
  for (double x = -50.0; x <= 50.0; x += 0.0137) {
    float s = 0, c = 0;
    fast_sincos(x, &s, &c);
    EXPECT_NEAR(s, std::sin(x), 3e-7) << x;
    EXPECT_NEAR(c, std::cos(x), 3e-7) << x;
  }
  for (double x : {0.0, M_PI / 4, M_PI / 2, M_PI, -M_PI, 1e5 + 0.3}) {
    float s = 0, c = 0;
    fast_sincos(x, &s, &c);
    EXPECT_NEAR(s, std::sin(x), 3e-7) << x;
    EXPECT_NEAR(c, std::cos(x), 3e-7) << x;
  }
}

TEST(FastSinCos, EightLanesMatchStdWithinFloatPrecision) {
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> wide(-60.0, 60.0);
  const double special[8] = {0.0, M_PI / 4, M_PI / 2, M_PI, -M_PI, 1e5 + 0.3, -3 * M_PI / 4, 2 * M_PI};
  for (int trial = 0; trial < 3000; ++trial) {
    alignas(32) double x[8];
    for (int i = 0; i < 8; ++i) x[i] = trial == 0 ? special[i] : wide(rng);
    v8f s, c;
    fast_sincos8(v4d{x[0], x[1], x[2], x[3]}, v4d{x[4], x[5], x[6], x[7]}, &s, &c);
    for (int i = 0; i < 8; ++i) {
      ASSERT_NEAR(s[i], std::sin(x[i]), 3e-7) << x[i];
      ASSERT_NEAR(c[i], std::cos(x[i]), 3e-7) << x[i];
    }
  }
}

TEST(KernelKinematics, MatchesCoreForwardKinematics) {
  const RobotModel model = test::shipped_robot_with("t_bar");
  const KernelKinematics kin(model);
  std::mt19937_64 rng(5);
  for (int i = 0; i < 500; ++i) {
    RobotConfiguration c;
    c.q_rad = test::random_joints(model, rng);
    KinematicsWorkspace ws;
    forward_kinematics(model, c, ws);
    ArmPoses poses;
    kin.compute(c.q_rad, poses);
    for (int j = 0; j < kNumLinks; ++j) {
      EXPECT_TRUE(poses.T_B_L[static_cast<std::size_t>(j)].isometry().matrix().isApprox(
          ws.T_W_L[static_cast<std::size_t>(j)].matrix(), 1e-5));
      EXPECT_LT((poses.T_B_J[static_cast<std::size_t>(j)].isometry().matrix() -
                 ws.T_W_J[static_cast<std::size_t>(j)].matrix())
                    .cwiseAbs()
                    .maxCoeff(),
                2e-6);
    }
  }
}

// Eight configurations per pass, one per lane, against compute() one at a time; the second model
// turns two joints about general axes (not +-z) so the per-lane Rodrigues path runs too.
TEST(KernelKinematics, LanesMatchOneConfigurationAtATime) {
  RobotModel general = test::shipped_robot_with("t_bar");
  general.joints[1].axis = Eigen::Vector3d(1.0, 2.0, 0.5).normalized();
  general.joints[4].axis = Eigen::Vector3d(0.0, -1.0, 0.0);
  for (const RobotModel& model : {test::shipped_robot_with("t_bar"), general}) {
    const KernelKinematics kin(model);
    std::mt19937_64 rng(8);
    for (int trial = 0; trial < 300; ++trial) {
      std::array<JointVector, 8> q;
      std::array<const JointVector*, 8> qp{};
      for (int i = 0; i < 8; ++i) {
        q[static_cast<std::size_t>(i)] = test::random_joints(model, rng);
        qp[static_cast<std::size_t>(i)] = &q[static_cast<std::size_t>(i)];
      }
      ArmPoseLanes lanes;
      kin.compute_lanes(qp, lanes);
      for (int i = 0; i < 8; ++i) {
        ArmPoses one;
        kin.compute(q[static_cast<std::size_t>(i)], one);
        const ArmPoses got = lanes.lane(i);
        RobotConfiguration c;
        c.q_rad = q[static_cast<std::size_t>(i)];
        KinematicsWorkspace ws;
        forward_kinematics(model, c, ws);
        for (std::size_t k = 0; k < static_cast<std::size_t>(kNumLinks); ++k) {
          ASSERT_LT((got.T_B_L[k].isometry().matrix() - one.T_B_L[k].isometry().matrix()).cwiseAbs().maxCoeff(), 2e-6)
              << "trial " << trial << " lane " << i << " link " << k;
          ASSERT_LT((got.T_B_J[k].isometry().matrix() - one.T_B_J[k].isometry().matrix()).cwiseAbs().maxCoeff(), 2e-6);
          ASSERT_LT((got.T_B_L[k].isometry().matrix() - ws.T_W_L[k].matrix()).cwiseAbs().maxCoeff(), 2e-6);
        }
      }
    }
  }
}

TEST(ChainRadii, BoundEveryLinkPointOverRandomConfigurations) {
  const RobotModel model = test::shipped_robot_with("arc");
  const ChainRadii radii = compute_chain_radii(model);
  std::mt19937_64 rng(6);
  for (int i = 0; i < 300; ++i) {
    RobotConfiguration c;
    c.q_rad = test::random_joints(model, rng);
    KinematicsWorkspace ws;
    forward_kinematics(model, c, ws);
    for (int k = 0; k < kNumLinks; ++k)
      for (const auto& s : model.links[static_cast<std::size_t>(k)].shapes) {
        CollisionShape sw = s;
        sw.T_parent_shape = ws.T_W_L[static_cast<std::size_t>(k)] * s.T_parent_shape;
        EXPECT_LE(shape_max_distance(sw, Eigen::Vector3d::Zero()), radii.reach_m + 1e-9);
        for (int j = 1; j <= std::min(k, kNumArmJoints); ++j)
          EXPECT_LE(shape_max_distance(sw, ws.origin_W[static_cast<std::size_t>(j - 1)]),
                    radii.sweep_radius_m[static_cast<std::size_t>(j - 1)] + 1e-9);
      }
  }
}

}  // namespace
}  // namespace porter::planner
