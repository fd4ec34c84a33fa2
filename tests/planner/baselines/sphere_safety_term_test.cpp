// The sphere baseline's back-end term: zero far from obstacles, positive near them, and its
// gradient with respect to the raw trajectory parameters against finite differences.

#include <gtest/gtest.h>

#include "backend_fixtures.hpp"
#include "porter/baselines/sphere_safety_term.hpp"
#include "porter/core/scene_voxelizer.hpp"

namespace porter::baselines {
namespace {

OccupancyGrid pillar_grid(const Trajectory& traj) {
  Scene scene;
  scene.bounds_W = Eigen::AlignedBox3d(Eigen::Vector3d(-6, -6, 0), Eigen::Vector3d(6, 6, 2.5));
  scene.resolution_m = 0.05;
  // A pillar next to the trajectory's midpoint.
  const TrajVector mid = traj.position(0.5 * traj.total_duration_s());
  CollisionShape pillar;
  pillar.geometry = Cylinder{0.1, 2.0};
  pillar.T_parent_shape.translation() = Eigen::Vector3d(mid[0] + 0.45, mid[1] + 0.45, 1.0);
  scene.obstacles.push_back(pillar);
  return voxelize(scene);
}

TEST(SphereSafetyTerm, GradientMatchesFiniteDifferences) {
  const RobotModel& model = backend::testing::robot("t_bar");
  const Trajectory traj = backend::testing::random_trajectory(model, 31, backend::testing::RandomTrajectoryOptions::with_pieces(3));
  const OccupancyGrid grid = pillar_grid(traj);
  SphereSafetySettings s;
  s.safety_margin_m = 0.3;
  s.weight = 1e3;
  SphereSafetyTerm term(model, s);
  term.prepare(grid, traj);
  backend::TrajectoryGradient grad;
  grad.reset(traj.num_pieces());
  backend::SafetyStats stats;
  const double J = term.evaluate(traj, grad, &stats);
  ASSERT_GT(J, 0.0);
  ASSERT_GT(stats.violations, 0);
  auto J_of = [&](const Trajectory& t) {
    backend::TrajectoryGradient g;
    g.reset(t.num_pieces());
    return term.evaluate(t, g, nullptr);
  };
  int checked = 0;
  for (int i = 0; i < traj.num_pieces(); ++i) {
    const double hT = 1e-6;
    const double fdT = (J_of(backend::testing::perturbed(traj, i, -1, 0, hT)) -
                        J_of(backend::testing::perturbed(traj, i, -1, 0, -hT))) / (2 * hT);
    EXPECT_NEAR(fdT, grad.duration(i), 1e-4 * (1 + std::abs(fdT))) << "T" << i;
    for (int row = 0; row < kTrajNumCoeffs; ++row) {
      for (int col = 0; col < kTrajDim; ++col) {
        const double h = 1e-6;
        const double fd = (J_of(backend::testing::perturbed(traj, i, row, col, h)) -
                           J_of(backend::testing::perturbed(traj, i, row, col, -h))) / (2 * h);
        EXPECT_NEAR(fd, grad.coeffs(i)(row, col), 1e-4 * (1 + std::abs(fd))) << "c" << i << "(" << row << "," << col << ")";
        checked += fd != 0.0;
      }
    }
  }
  EXPECT_GT(checked, 20);
}

TEST(SphereSafetyTerm, FarObstaclesCostNothing) {
  const RobotModel& model = backend::testing::robot("t_bar");
  const Trajectory traj = backend::testing::random_trajectory(model, 32);
  OccupancyGrid empty(Eigen::Vector3d(-8, -8, 0), 0.05, Eigen::Vector3i(320, 320, 50));
  OccupancyGrid far = empty;
  const TrajVector start = traj.position(0.0);
  for (int k = 0; k < 20; ++k) far.set(static_cast<int>((start[0] + 8.0) / 0.05), 5, k);  // ~7 m away
  double J[2];
  backend::SafetyStats stats;
  for (int m = 0; m < 2; ++m) {
    SphereSafetyTerm term(model, SphereSafetySettings{});
    term.prepare(m == 0 ? empty : far, traj);
    backend::TrajectoryGradient grad;
    grad.reset(traj.num_pieces());
    J[m] = term.evaluate(traj, grad, &stats);
  }
  EXPECT_EQ(J[0], J[1]);  // the ground's share only
  EXPECT_GT(stats.link_queries, 0);
}

}  // namespace
}  // namespace porter::baselines
