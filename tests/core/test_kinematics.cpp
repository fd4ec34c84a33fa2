// Forward kinematics of the shipped URDF against the Piper's published modified-DH table, and
// point Jacobians against finite differences.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "porter/core/kinematics.hpp"
#include "porter/core/payload.hpp"
#include "porter/core/payload_loader.hpp"
#include "porter/core/robot_loader.hpp"
#include "robot_test_utils.hpp"

namespace porter {
namespace {

// Piper modified-DH (Craig), piper_sdk kinematics with the default 2-degree J2/J3 offset.
constexpr double kA[6] = {0, 0, 0.28503, -0.02198, 0, 0};
constexpr double kAlpha[6] = {0, -M_PI / 2, 0, M_PI / 2, -M_PI / 2, M_PI / 2};
constexpr double kD[6] = {0.123, 0, 0, 0.25075, 0, 0.091};
const double kOffset[6] = {0, -172.22 * M_PI / 180, -102.78 * M_PI / 180, 0, 0, 0};

Eigen::Isometry3d dh_link(int i, double q) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.rotate(Eigen::AngleAxisd(kAlpha[i], Eigen::Vector3d::UnitX()));
  T.translate(Eigen::Vector3d(kA[i], 0, 0));
  T.rotate(Eigen::AngleAxisd(q + kOffset[i], Eigen::Vector3d::UnitZ()));
  T.translate(Eigen::Vector3d(0, 0, kD[i]));
  return T;
}

// Pose of the Piper's base frame on the Scout Mini's top plate, as the robot's URDF declares it.
Eigen::Isometry3d mount() {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(0.15, 0.0, 0.245);
  return T;
}

JointVector random_q(const RobotModel& model, std::mt19937& rng) {
  JointVector q;
  for (int i = 0; i < kNumArmJoints; ++i) {
    std::uniform_real_distribution<double> u(model.joints[i].lower_rad, model.joints[i].upper_rad);
    q[i] = u(rng);
  }
  return q;
}

class KinematicsTest : public ::testing::Test {
 protected:
  void SetUp() override { model_ = load_robot_model(test::robot_yaml()); }
  RobotModel model_;
};

TEST_F(KinematicsTest, UrdfMatchesPublishedDhAtRandomConfigurations) {
  std::mt19937 rng(42);
  std::array<Eigen::Isometry3d, kNumLinks> T_B_L;
  for (int trial = 0; trial < 50; ++trial) {
    const JointVector q = random_q(model_, rng);
    arm_forward_kinematics(model_, q, T_B_L);
    Eigen::Isometry3d T_dh = mount();
    for (int i = 0; i < kNumArmJoints; ++i) {
      T_dh = T_dh * dh_link(i, q[i]);
      const Eigen::Isometry3d& T = T_B_L[i + 1];
      EXPECT_LT((T.translation() - T_dh.translation()).norm(), 1e-6) << "link " << i + 1 << " trial " << trial;
      EXPECT_LT((T.linear() - T_dh.linear()).norm(), 1e-9) << "link " << i + 1 << " trial " << trial;
    }
  }
}

TEST_F(KinematicsTest, HomePoseMatchesSdkFlangePosition) {
  std::array<Eigen::Isometry3d, kNumLinks> T_B_L;
  arm_forward_kinematics(model_, JointVector::Zero(), T_B_L);
  // piper_sdk's documented home flange position in the arm base frame: [56.128, 0, 213.266] mm.
  const Eigen::Vector3d p_arm = (mount().inverse() * T_B_L[6]).translation();
  EXPECT_NEAR(p_arm.x(), 0.056128, 2e-6);
  EXPECT_NEAR(p_arm.y(), 0.0, 2e-6);
  EXPECT_NEAR(p_arm.z(), 0.213266, 2e-6);
}

TEST_F(KinematicsTest, WorldFkComposesBasePoseAndEndEffectorFrame) {
  RobotConfiguration c;
  c.base = {1.5, -2.0, 0.7};
  c.q_rad << 0.3, 1.2, -1.0, 0.4, -0.5, 0.9;
  KinematicsWorkspace ws;
  forward_kinematics(model_, c, ws);
  std::array<Eigen::Isometry3d, kNumLinks> T_B_L;
  arm_forward_kinematics(model_, c.q_rad, T_B_L);
  for (int j = 0; j < kNumLinks; ++j) {
    const Eigen::Isometry3d expected = c.base.T_W_B() * T_B_L[j];
    EXPECT_LT((ws.T_W_L[j].matrix() - expected.matrix()).norm(), 1e-12) << "link " << j;
  }
  // The grasp frame is 0.135 m along the flange's approach axis.
  const Eigen::Vector3d d = ws.T_W_L[6].inverse() * ws.T_W_L[7].translation();
  EXPECT_NEAR(d.z(), 0.135, 1e-12);
  EXPECT_NEAR(d.head<2>().norm(), 0.0, 1e-12);
  // T_W_J[j] is the joint frame before its rotation: rotating it by q_j gives the link frame.
  for (int j = 1; j <= kNumArmJoints; ++j) {
    Eigen::Isometry3d R = Eigen::Isometry3d::Identity();
    R.linear() = Eigen::AngleAxisd(c.q_rad[j - 1], model_.joints[j - 1].axis).toRotationMatrix();
    EXPECT_LT(((ws.T_W_J[j] * R).matrix() - ws.T_W_L[j].matrix()).norm(), 1e-12);
  }
}

// Central differences of a point fixed on each link, for every whole-body coordinate.
void check_jacobians(const RobotModel& model, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    RobotConfiguration c;
    c.base = {3 * u(rng), 3 * u(rng), M_PI * u(rng)};
    c.q_rad = random_q(model, rng);
    KinematicsWorkspace ws;
    forward_kinematics(model, c, ws);
    for (int link = 0; link < kNumLinks; ++link) {
      const Eigen::Vector3d p_L(0.3 * u(rng), 0.3 * u(rng), 0.3 * u(rng));
      const Eigen::Vector3d p_W = ws.T_W_L[link] * p_L;
      PointJacobian J;
      point_jacobian(model, ws, link, p_W, J);
      const double h = 1e-6;
      for (int k = 0; k < kNumDof; ++k) {
        DofVector plus = c.as_dof(), minus = c.as_dof();
        plus[k] += h;
        minus[k] -= h;
        KinematicsWorkspace wp, wm;
        forward_kinematics(model, RobotConfiguration::from_dof(plus), wp);
        forward_kinematics(model, RobotConfiguration::from_dof(minus), wm);
        const Eigen::Vector3d fd = (wp.T_W_L[link] * p_L - wm.T_W_L[link] * p_L) / (2 * h);
        EXPECT_LT((J.col(k) - fd).norm(), 1e-7 * std::max(1.0, fd.norm()))
            << "link " << link << " dof " << k << " trial " << trial;
      }
    }
  }
}

TEST_F(KinematicsTest, PointJacobiansMatchFiniteDifferences) {
  std::mt19937 rng(7);
  check_jacobians(model_, rng);
}

TEST_F(KinematicsTest, PointJacobiansWithPayloadMatchFiniteDifferences) {
  std::mt19937 rng(8);
  check_jacobians(attach_payload(model_, load_payload(test::payload_yaml("t_bar"))), rng);
}

TEST_F(KinematicsTest, JacobianColumnsOfDownstreamJointsAreZero) {
  RobotConfiguration c;
  c.q_rad << 0.1, 1.0, -1.2, 0.2, 0.3, 0.4;
  KinematicsWorkspace ws;
  forward_kinematics(model_, c, ws);
  for (int link = 0; link <= kNumArmJoints; ++link) {
    PointJacobian J;
    point_jacobian(model_, ws, link, ws.T_W_L[link] * Eigen::Vector3d(0.1, 0.2, 0.3), J);
    for (int j = link; j < kNumArmJoints; ++j) EXPECT_EQ(J.col(3 + j).norm(), 0.0) << link << " " << j;
  }
}

}  // namespace
}  // namespace porter
