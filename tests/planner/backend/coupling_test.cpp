// The kinematic coupling at work: a case where the per-link escape directions conflict along the
// chain. A cluster of obstacle points sits in the Piper's elbow region, inside links 4 and 5 and
// within 1 cm of link 3. Optimizing only the arm joints against J_s with plain normalized gradient
// steps:
//   - svsdf_per_link: links 4 and 5 escape through their nearest faces, which needs joint 2 to
//     rise; that swings link 3 into the cluster (a new collision), whose own escape pulls back: the
//     cost stalls with points still inside;
//   - kc_svsdf: the KinematicFilter only lets links 4 and 5 escape where joints 2 and 3 agree with
//     links 2 and 3; joint 2 goes down and every link clears the cluster.
// The case was found by a seeded search over random arm configurations and clusters (both methods
// fail or succeed elsewhere: the filter is not uniformly better), and is frozen here with the
// mechanism it exhibits. The test fails if the coupling is removed (both runs are then the same).

#include <gtest/gtest.h>

#include "backend_fixtures.hpp"
#include "porter/backend/kc_svsdf.hpp"
#include "porter/backend/svsdf_safety_term.hpp"

namespace porter::backend {
namespace {

Trajectory stationary(const TrajVector& z) {
  TrajectoryPiece p;
  p.duration_s = 1.0;
  p.coeffs.setZero();
  p.coeffs.row(0) = z.transpose();
  return *Trajectory::create({p}, 0.0).trajectory;
}

struct Descent {
  std::vector<TrajVector> z;             ///< configuration after each step
  std::vector<double> cost;
  std::vector<int> inside;
  std::vector<std::array<double, kNumLinks>> min_d;  ///< per link, over the cluster
};

Descent optimize(bool kinematic_filter, int steps) {
  const RobotModel& model = testing::robot("t_bar");
  const RobotSdf& sdf = testing::robot_sdf("t_bar");
  const Eigen::Vector3d center(0.1473, -0.2388, 0.5741);
  const double spacing = 0.056;
  std::vector<ObstaclePoint> points;
  for (int a = -1; a <= 1; ++a)
    for (int b = -1; b <= 1; ++b)
      for (int c = -1; c <= 1; ++c) points.push_back({center + spacing * Eigen::Vector3d(a, b, c), kAllLinks & ~1u});
  SvsdfSafetySettings s;
  s.kc.kinematic_filter = kinematic_filter;
  s.safety_margin_m = 0.03;
  s.weight = 1e4;
  s.threads = 1;
  SvsdfSafetyTerm term(model, sdf, s);
  term.set_points(points);

  TrajVector z;
  z << 0.0, 0.0, -1.6395, 1.3459, -0.9909, -0.7213, -1.0486, -1.0894;
  Descent run;
  for (int k = 0; k <= steps; ++k) {
    const Trajectory traj = stationary(z);
    TrajectoryGradient grad;
    grad.reset(1);
    SafetyStats stats;
    run.z.push_back(z);
    // Every step is an accepted iterate: Algorithm 1 decides afresh there (svsdf_safety_term.hpp).
    term.refresh_decisions();
    run.cost.push_back(term.evaluate(traj, grad, &stats));
    run.inside.push_back(stats.inside);
    SweptBody body(model);
    body.reset(traj);
    KcSvsdf kc(sdf, body, s.kc);
    std::array<double, kNumLinks> min_d;
    min_d.fill(1.0);
    for (const ObstaclePoint& o : points) {
      KcSvsdfResult r;
      kc.evaluate(o.p_W, o.links, r);
      for (int j = 1; j < kNumLinks; ++j) min_d[static_cast<std::size_t>(j)] = std::min(min_d[static_cast<std::size_t>(j)], r.links[static_cast<std::size_t>(j)].d);
    }
    run.min_d.push_back(min_d);
    TrajVector g = grad.coeffs(0).row(0).transpose();
    g.head<2>().setZero();  // the base stays where it is
    if (g.norm() == 0.0) break;
    z -= 0.01 * g / g.norm();  // 1 cm-scale normalized step
  }
  return run;
}

TEST(KinematicCoupling, ResolvesAChainConflictWherePerLinkSvsdfStalls) {
  const Descent kc = optimize(true, 40);
  const Descent per_link = optimize(false, 40);

  // The start: links 4 and 5 penetrated, link 3 just outside (1.1 cm).
  ASSERT_GT(kc.inside.front(), 0);
  EXPECT_GT(kc.min_d.front()[3], 0.0);
  EXPECT_LT(kc.min_d.front()[4], 0.0);

  // Per-link: the escapes of links 4-5 raise joint 2 and push link 3 into the cluster; the cost
  // stalls with points still inside.
  EXPECT_GT(per_link.z[10][3], per_link.z[0][3] + 0.02);  // q2 went up
  EXPECT_LT(per_link.min_d.back()[3], 0.0);       // link 3 now in collision
  EXPECT_GT(per_link.inside.back(), 0);
  EXPECT_GT(per_link.cost.back(), 0.9 * per_link.cost[20]);  // no progress over the last 20 steps

  // KC-SVSDF: joint 2 goes down; every link clears the cluster and the penalty vanishes.
  EXPECT_LT(kc.z[10][3], kc.z[0][3] - 0.02);
  EXPECT_EQ(kc.inside.back(), 0);
  EXPECT_LT(kc.cost.back(), 1e-3 * kc.cost.front());
  for (int j = 1; j < kNumLinks; ++j) EXPECT_GT(kc.min_d.back()[static_cast<std::size_t>(j)], 0.0) << "link " << j;
}

}  // namespace
}  // namespace porter::backend
