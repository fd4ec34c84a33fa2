// The fast chain kinematics and the swept body's state against the core's slow references
// (porter::forward_kinematics, point_jacobian, Trajectory::base_motion), and the heading gradient
// against finite differences.

#include <gtest/gtest.h>

#include <random>

#include "backend_fixtures.hpp"
#include "porter/backend/chain_kinematics.hpp"
#include "porter/backend/swept_body.hpp"
#include "porter/core/kinematics.hpp"

namespace porter::backend {
namespace {

TEST(ChainKinematics, MatchesCoreForwardKinematicsAndJacobians) {
  const RobotModel& model = testing::robot("t_bar");
  const ChainKinematics fast(model);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  KinematicsWorkspace ref;
  ChainKinematics::Workspace ws;
  for (int n = 0; n < 200; ++n) {
    RobotConfiguration c;
    c.base = {3 * u(rng), 3 * u(rng), 3.1 * u(rng)};
    for (int j = 0; j < kNumArmJoints; ++j) c.q_rad[j] = 2.0 * u(rng);
    forward_kinematics(model, c, ref);
    for (int up_to = 0; up_to < kNumLinks; ++up_to) {
      fast.compute(c, up_to, ws);
      for (int l = 0; l <= up_to; ++l) {
        const auto i = static_cast<std::size_t>(l);
        EXPECT_LT((ws.R_W_L[i] - ref.T_W_L[i].linear()).norm(), 1e-12);
        EXPECT_LT((ws.t_W_L[i] - ref.T_W_L[i].translation()).norm(), 1e-12);
      }
      const Eigen::Vector3d p(u(rng), u(rng), 1 + u(rng));
      PointJacobian J_fast, J_ref;
      ChainKinematics::point_jacobian(ws, up_to, p, J_fast);
      point_jacobian(model, ref, up_to, p, J_ref);
      EXPECT_LT((J_fast - J_ref).norm(), 1e-12) << "link " << up_to;
    }
  }
}

TEST(SweptBody, StateMatchesTheTrajectoryAndItsHeadingRule) {
  const RobotModel& model = testing::robot("t_bar");
  for (int eta : {1, -1}) {
    testing::RandomTrajectoryOptions o;
    o.eta = eta;
    const Trajectory traj = testing::random_trajectory(model, 3, o);
    SweptBody body(model);
    body.reset(traj);
    BodyState s;
    for (int k = 0; k <= 400; ++k) {
      const double t = traj.total_duration_s() * k / 400.0;
      body.evaluate(t, s);
      const BaseMotion bm = traj.base_motion(t);
      EXPECT_NEAR(s.config.base.yaw_rad, bm.yaw_rad, 1e-12);
      EXPECT_NEAR(s.config_rate[2], bm.yaw_rate_radps, 1e-9);
      EXPECT_LT((s.z - traj.position(t)).norm(), 1e-12);
      // d yaw / d pdot against finite differences of the heading formula.
      const double h = 1e-7;
      for (int a = 0; a < 2; ++a) {
        Eigen::Vector2d v = s.z_dot.head<2>();
        Eigen::Vector2d vp = v, vm = v;
        vp[a] += h;
        vm[a] -= h;
        double dp = std::atan2(eta * vp.y(), eta * vp.x()) - std::atan2(eta * vm.y(), eta * vm.x());
        dp = std::remainder(dp, 2 * M_PI);
        EXPECT_NEAR(dp / (2 * h), s.dyaw_dheading[a], 1e-5 * (1 + std::abs(s.dyaw_dheading[a])));
      }
    }
    // The cache holds the exact poses at its sample times.
    for (int k = 0; k < body.num_samples(); k += 7) {
      body.evaluate(body.sample_time(k), s);
      for (int l = 0; l < kNumLinks; ++l) {
        const InversePose& inv = body.sample_pose(k, l);
        const Eigen::Vector3d p(0.3, -0.2, 0.7);
        EXPECT_LT((inv.apply(s.kin.R_W_L[static_cast<std::size_t>(l)] * p + s.kin.t_W_L[static_cast<std::size_t>(l)]) - p).norm(), 1e-12);
      }
    }
  }
}

}  // namespace
}  // namespace porter::backend
