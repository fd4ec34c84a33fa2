// The back-end problem: the warm start round trip (mid-end trajectory -> decision vector ->
// the same pieces) and the gradient of mid-end + J_s with respect to the decision vector (the
// adapter's MINCO adjoint and gear mapping) against finite differences.

#include <gtest/gtest.h>

#include <random>

#include "backend_fixtures.hpp"
#include "porter/backend/backend_problem.hpp"
#include "porter/backend/kc_svsdf.hpp"
#include "porter/backend/svsdf_safety_term.hpp"
#include "porter/midend/midend.hpp"
#include "synthetic_paths.hpp"

namespace porter::backend {
namespace {

constexpr char kPayload[] = "t_bar";

/// Obstacle points near the trajectory's links, within the safety margin of some link but outside
/// every swept volume and off the windows' edges: there J_s is smooth, so this checks the adapter's
/// chain rule. (Inside points make D piecewise continuous, the ball search's discrete choices; their
/// gradients are checked point by point in kc_svsdf_test.)
std::vector<ObstaclePoint> points_around(const SweptBody& body, const RobotSdf& sdf, int count,
                                         std::uint64_t seed) {
  std::mt19937 rng(static_cast<unsigned>(seed));
  std::uniform_real_distribution<double> u(0.0, 1.0), s(-1.0, 1.0);
  std::vector<ObstaclePoint> out;
  BodyState st;
  KcSvsdfSettings ks;
  ks.svsdf.time_tolerance_s = 1e-7;
  KcSvsdf kc(sdf, body, ks);
  KcSvsdfResult r;
  for (int n = 0; static_cast<int>(out.size()) < count && n < 100 * count; ++n) {
    const int link = n % kNumLinks;
    body.evaluate(u(rng) * body.duration_s(), st);
    const Eigen::AlignedBox3d& b = body.model().links[static_cast<std::size_t>(link)].bounds;
    const Eigen::Vector3d p_L = b.min() + b.sizes().cwiseProduct(Eigen::Vector3d(u(rng), u(rng), u(rng)));
    const auto l = static_cast<std::size_t>(link);
    const Eigen::Vector3d p = st.kin.R_W_L[l] * p_L + st.kin.t_W_L[l] + 0.08 * Eigen::Vector3d(s(rng), s(rng), s(rng));
    kc.evaluate(p, kAllLinks, r);
    bool smooth = true, close = false;
    for (const LinkDistance& d : r.links) {
      smooth = smooth && d.d > 0.01 && !d.on_window_edge;
      close = close || d.d < 0.08;
    }
    if (smooth && close) out.push_back({p, (1u << kNumLinks) - 1});
  }
  return out;
}

class BackendProblemTest : public ::testing::TestWithParam<int> {};

TEST_P(BackendProblemTest, WarmStartRoundTripAndGradient) {
  const RobotModel& model = testing::robot(kPayload);
  const planner::WholeBodyPath path =
      GetParam() == 0 ? midend::testing::forward_with_turn() : midend::testing::three_point_turn();
  const midend::MidEnd mid(model);
  const midend::MidendResult m = mid.solve(path, 1.0);
  ASSERT_TRUE(m.ok()) << m.message;

  midend::ReferenceBuild ref = midend::build_reference_path(path, mid.limits(), mid.settings());
  ASSERT_EQ(ref.outcome, midend::ReferenceOutcome::kOk);
  SvsdfSafetySettings ss;
  ss.weight = 1e3;
  // The envelope gradient's error is linear in the t* tolerance (1e-5 s by default: ~5e-4 relative,
  // ample for the optimizer); tighten it so the comparison can be tight.
  ss.kc.svsdf.time_tolerance_s = 1e-7;
  SvsdfSafetyTerm safety(model, testing::robot_sdf(kPayload), ss);
  safety.prepare(OccupancyGrid(), *m.trajectory);
  safety.set_points(points_around(safety.body(), testing::robot_sdf(kPayload), 15, 3));
  ASSERT_EQ(safety.points().size(), 15u);
  BackendProblem problem(std::move(ref.path), mid.limits(), mid.settings(), safety);

  Eigen::VectorXd x;
  ASSERT_TRUE(problem.decision_from_trajectory(*m.trajectory, x));
  const std::optional<Trajectory> back = problem.trajectory(x.data());
  ASSERT_TRUE(back.has_value());
  ASSERT_EQ(back->num_pieces(), m.trajectory->num_pieces());
  for (int i = 0; i < back->num_pieces(); ++i) {
    EXPECT_NEAR(back->piece(i).duration_s, m.trajectory->piece(i).duration_s, 1e-9);
    EXPECT_LT((back->piece(i).coeffs - m.trajectory->piece(i).coeffs).norm(), 1e-6 * (1 + m.trajectory->piece(i).coeffs.norm()));
  }

  // Gradient of the collision term alone (the mid-end's own terms have their own tests).
  problem.midend().set_terms(0);
  Eigen::VectorXd grad(problem.num_variables());
  BackendCost cost;
  const double f = problem.evaluate(x.data(), grad.data(), &cost);
  ASSERT_GT(cost.safety, 0.0);
  ASSERT_GT(cost.safety_stats.violations, 10);
  ASSERT_EQ(cost.safety_stats.inside, 0);
  EXPECT_NEAR(f, cost.safety, 1e-12 * (1 + f));
  // J_s is smooth at these points except where a t* switches between two local minima; an entry
  // whose two central differences disagree straddles such a switch and is not compared.
  int checked = 0, rough = 0;
  for (int k = 0; k < problem.num_variables(); ++k) {
    if (grad[k] == 0.0 && k % 5 != 0) continue;  // sample the zero entries
    auto f = [&](double e) {
      Eigen::VectorXd xe = x;
      xe[k] += e;
      return problem.evaluate(xe.data(), nullptr, nullptr);
    };
    const double h = 2e-6;
    const double d1 = (f(h) - f(-h)) / (2 * h);
    const double d2 = (f(0.25 * h) - f(-0.25 * h)) / (0.5 * h);
    if (std::abs(d1 - d2) > 1e-3 * (std::abs(d2) + 1e-3 * cost.safety)) {
        ++rough;
      continue;
    }
    ++checked;
    EXPECT_NEAR(d2, grad[k], 1e-4 * (std::abs(d2) + std::abs(grad[k])) + 1e-6 * cost.safety) << "variable " << k;
  }
  EXPECT_GT(checked, 20);
  EXPECT_LE(rough, 0.05 * (checked + rough));
}

INSTANTIATE_TEST_SUITE_P(Paths, BackendProblemTest, ::testing::Values(0, 1));

}  // namespace
}  // namespace porter::backend
