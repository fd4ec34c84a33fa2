// The back-end problem: the warm start round trip (mid-end trajectory -> decision vector -> the
// same pieces), and the whole back-end cost (every mid-end term + J_s through the mid-end's
// extra-cost hook) against central finite differences on every variable: waypoints, the tau
// variables with the time map T = exp(sigma) T(tau), the global time scale sigma and the gear
// states.

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
/// every swept volume, off the windows' edges and with no t* at a segment junction: there J_s is
/// smooth and its envelope gradient exact, so this checks the chain rule. (Inside points make D
/// piecewise continuous, the ball search's discrete choices; their gradients are checked point by
/// point in kc_svsdf_test.) At a gear switch the base reverses, so a link's distance to a point
/// behind it has a kink there in t and its minimum can sit on the kink; the envelope theorem
/// (dD/dt = 0 at t*) does not hold at such a minimum, as at a window's edge, and the gradient
/// misses the junction time's own motion (seen on the bridge fixture: entries of a gear state,
/// a duration before the switch and a waypoint 5e-4 off their central differences, which agree
/// at two step sizes).
std::vector<ObstaclePoint> points_around(const SweptBody& body, const RobotSdf& sdf, int count,
                                         std::uint64_t seed, const std::vector<double>& junctions_s) {
  std::mt19937 rng(static_cast<unsigned>(seed));
  std::uniform_real_distribution<double> u(0.0, 1.0), s(-1.0, 1.0);
  std::vector<ObstaclePoint> out;
  BodyState st;
  KcSvsdfSettings ks;
  ks.svsdf.time_tolerance_s = 1e-9;
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
      for (const double t : junctions_s) smooth = smooth && std::abs(d.t_star_s - t) > 1e-6;
      close = close || d.d < 0.08;
    }
    if (smooth && close) out.push_back({p, (1u << kNumLinks) - 1});
  }
  return out;
}

double rel(const Eigen::VectorXd& a, const Eigen::VectorXd& b, double floor) {
  return (a - b).norm() / std::max(b.norm(), floor);
}

struct Fixture {
  planner::WholeBodyPath path;
  midend::MidendResult mid;
};

Fixture solve_midend(int which) {
  Fixture f;
  f.path = which == 0 ? midend::testing::forward_with_turn() : midend::testing::three_point_turn();
  f.mid = midend::MidEnd(testing::robot(kPayload)).solve(f.path, 5.0);
  return f;
}

class BackendProblemTest : public ::testing::TestWithParam<int> {};

TEST_P(BackendProblemTest, WarmStartRoundTrip) {
  const RobotModel& model = testing::robot(kPayload);
  const Fixture fx = solve_midend(GetParam());
  ASSERT_TRUE(fx.mid.ok()) << fx.mid.message;
  const midend::MidEnd mid(model);
  midend::ReferenceBuild ref = midend::build_reference_path(fx.path, mid.limits(), mid.settings());
  ASSERT_EQ(ref.outcome, midend::ReferenceOutcome::kOk);
  SvsdfSafetyTerm safety(model, testing::robot_sdf(kPayload), SvsdfSafetySettings{});
  safety.prepare(OccupancyGrid(), *fx.mid.trajectory);
  BackendProblem problem(std::move(ref.path), mid.limits(), mid.settings(), safety);

  Eigen::VectorXd x;
  ASSERT_TRUE(problem.midend().decision_from_trajectory(*fx.mid.trajectory, x));
  ASSERT_EQ(x.size(), problem.num_variables());
  // The mid-end hands the back-end exactly this decision vector with its solution.
  ASSERT_TRUE(fx.mid.solution.has_value());
  EXPECT_EQ(fx.mid.solution->x, x);
  EXPECT_EQ(fx.mid.solution->reference.num_pieces(), problem.num_pieces());
  const std::optional<Trajectory> back = problem.trajectory(x.data());
  ASSERT_TRUE(back.has_value());
  ASSERT_EQ(back->num_pieces(), fx.mid.trajectory->num_pieces());
  for (int i = 0; i < back->num_pieces(); ++i) {
    EXPECT_NEAR(back->piece(i).duration_s, fx.mid.trajectory->piece(i).duration_s, 1e-9);
    EXPECT_LT((back->piece(i).coeffs - fx.mid.trajectory->piece(i).coeffs).norm(),
              1e-6 * (1 + fx.mid.trajectory->piece(i).coeffs.norm()));
  }
  // With no obstacle points the back-end cost is the mid-end's.
  BackendCost c;
  const double f = problem.evaluate(x.data(), nullptr, &c);
  EXPECT_EQ(c.safety, 0.0);
  EXPECT_NEAR(f, fx.mid.final_cost.total(), 1e-9 * (1.0 + std::abs(f)));

  // A trajectory with another piece structure is refused, not mapped.
  std::vector<TrajectoryPiece> fewer(fx.mid.trajectory->pieces().begin(), fx.mid.trajectory->pieces().end() - 1);
  const TrajectoryResult shorter = Trajectory::create(std::move(fewer), problem.midend().start_yaw_rad());
  ASSERT_TRUE(shorter.ok());
  EXPECT_FALSE(problem.midend().decision_from_trajectory(*shorter.trajectory, x));
}

TEST_P(BackendProblemTest, WholeCostGradientMatchesCentralDifferences) {
  const RobotModel& model = testing::robot(kPayload);
  const Fixture fx = solve_midend(GetParam());
  ASSERT_TRUE(fx.mid.ok()) << fx.mid.message;
  const midend::MidEnd mid(model);
  midend::ReferenceBuild ref = midend::build_reference_path(fx.path, mid.limits(), mid.settings());
  ASSERT_EQ(ref.outcome, midend::ReferenceOutcome::kOk);
  SvsdfSafetySettings ss;
  ss.weight = 1e3;
  // The envelope gradient's error is linear in the t* tolerance; tighten it for a tight comparison.
  ss.kc.svsdf.time_tolerance_s = 1e-10;
  ss.kc.svsdf.max_refine_iterations = 100;
  SvsdfSafetyTerm safety(model, testing::robot_sdf(kPayload), ss);
  BackendProblem problem(std::move(ref.path), mid.limits(), mid.settings(), safety);
  const int n = problem.num_variables();

  Eigen::VectorXd x;
  ASSERT_TRUE(problem.midend().decision_from_trajectory(*fx.mid.trajectory, x));
  // Away from the warm start, so that the time map's factors are not 1 and the mid-end terms are
  // not at their minimum: sigma != 0 (every duration scaled by exp(sigma)), waypoints, taus and
  // gear states jittered.
  std::mt19937 rng(7u + static_cast<unsigned>(GetParam()));
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k + 1 < n; ++k) x[k] += 0.02 * u(rng);
  x[n - 1] = 0.15;
  const std::optional<Trajectory> traj = problem.trajectory(x.data());
  ASSERT_TRUE(traj.has_value());
  safety.prepare(OccupancyGrid(), *traj);
  std::vector<double> junctions_s;  // the end of every segment but the last
  {
    double t = 0.0;
    int piece = 0;
    for (const auto& seg : problem.midend().reference().segments) {
      for (int i = 0; i < seg.num_pieces(); ++i) t += traj->piece(piece++).duration_s;
      junctions_s.push_back(t);
    }
    junctions_s.pop_back();
  }
  safety.set_points(points_around(safety.body(), testing::robot_sdf(kPayload), 25, 3 + GetParam(), junctions_s));
  ASSERT_EQ(safety.points().size(), 25u);

  // Which variables are waypoints / taus / gear states / sigma, from the documented layout.
  std::vector<int> kind(static_cast<std::size_t>(n), 2);  // 0 waypoint, 1 tau, 2 gear, 3 sigma
  {
    int o = 0;
    for (const auto& seg : problem.midend().reference().segments) {
      for (int k = 0; k < kTrajDim * (seg.num_pieces() - 1); ++k) {
        kind[static_cast<std::size_t>(o++)] = 0;
      }
      for (int i = 0; i < seg.num_pieces(); ++i) {
        kind[static_cast<std::size_t>(o++)] = 1;
      }
    }
    kind[static_cast<std::size_t>(n - 1)] = 3;
  }

  for (const std::uint32_t mask : {static_cast<std::uint32_t>(midend::kTermExtra), static_cast<std::uint32_t>(midend::kTermAll)}) {
    problem.midend().set_terms(mask);
    Eigen::VectorXd g(n);
    BackendCost cost;
    const double f = problem.evaluate(x.data(), g.data(), &cost);
    ASSERT_TRUE(std::isfinite(f));
    ASSERT_GT(cost.safety, 0.0);
    ASSERT_GT(cost.safety_stats.violations, 10);
    ASSERT_EQ(cost.safety_stats.inside, 0);
    if (mask == midend::kTermExtra) {
      EXPECT_NEAR(f, cost.safety, 1e-12 * (1 + f));
    } else {
      EXPECT_GT(f, cost.safety);
    }

    // J_s is smooth at these points except where a t* switches between two local minima; an
    // entry whose two central differences (steps h and h/4) disagree straddles such a switch and
    // is left out (the count is bounded below).
    Eigen::VectorXd fd(n);
    std::vector<int> smooth;
    for (int k = 0; k < n; ++k) {
      Eigen::VectorXd xs = x;
      auto f_at = [&](double e) {
        xs[k] = x[k] + e;
        return problem.evaluate(xs.data(), nullptr, nullptr);
      };
      const double h = 1e-5;
      const double d1 = (f_at(h) - f_at(-h)) / (2 * h);
      const double d2 = (f_at(0.25 * h) - f_at(-0.25 * h)) / (0.5 * h);
      fd[k] = d2;
      if (std::abs(d1 - d2) <= 1e-5 * (std::abs(d2) + 1e-3 * g.lpNorm<Eigen::Infinity>())) smooth.push_back(k);
    }
    ASSERT_GE(static_cast<int>(smooth.size()), n - n / 10) << "too many entries straddle a t* switch";
    Eigen::VectorXd ga(smooth.size()), gf(smooth.size());
    for (std::size_t i = 0; i < smooth.size(); ++i) {
      ga[static_cast<Eigen::Index>(i)] = g[smooth[i]];
      gf[static_cast<Eigen::Index>(i)] = fd[smooth[i]];
    }
    EXPECT_LT(rel(ga, gf, 1e-12), 1e-5) << "mask " << mask;
    // J_s sees only the swept volume. Between rest states a uniform time scaling leaves it
    // unchanged, so its sigma partial (sum_i T_i dJ_s/dT_i) must cancel; gear switches pin the
    // base speed and break the invariance.
    const bool invariant = mask == midend::kTermExtra && problem.num_segments() == 1;
    if (invariant) {
      EXPECT_LT(std::abs(g[n - 1]), 1e-6 * g.norm());
    }
    for (int kd = 0; kd < (invariant ? 3 : 4); ++kd) {
      std::vector<int> idx;
      for (int k : smooth) {
        if (kind[static_cast<std::size_t>(k)] == kd) idx.push_back(k);
      }
      if (idx.empty()) continue;
      Eigen::VectorXd a(idx.size()), b(idx.size());
      for (std::size_t i = 0; i < idx.size(); ++i) {
        a[static_cast<Eigen::Index>(i)] = g[idx[i]];
        b[static_cast<Eigen::Index>(i)] = fd[idx[i]];
      }
      // Every block carries a real share of the gradient (the test would be vacuous otherwise);
      // it is compared relative to its own norm.
      EXPECT_GT(b.norm(), 1e-4 * gf.norm()) << "mask " << mask << " block " << kd;
      EXPECT_LT(rel(a, b, 1e-3 * gf.norm()), 1e-5) << "mask " << mask << " block " << kd;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Paths, BackendProblemTest, ::testing::Values(0, 1));

}  // namespace
}  // namespace porter::backend
