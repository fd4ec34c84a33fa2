// The fast penalty kernel (src/piece_sampler.cpp) against the slow reference integrand
// (src/sample_penalty.hpp through minco::integrate_piece_penalty): same cost, same per-term
// split, same gradient, term by term, at points from far infeasible to nearly feasible. And the
// extra-cost extension point against central finite differences.
#include <random>

#include <gtest/gtest.h>

#include "porter/midend/midend_problem.hpp"
#include "porter/midend/reference_path.hpp"
#include "porter/minco/polynomial.hpp"
#include "synthetic_paths.hpp"

namespace porter::midend {
namespace {

const std::uint32_t kMasks[] = {kTermWheelVelocity, kTermWheelAcceleration, kTermJointPosition,
                                kTermJointVelocity, kTermJointAcceleration, kTermResidualBase,
                                kTermResidualArm,   kTermMinSpeed,          kTermAll};

MidendLimits tight_limits() {
  MidendLimits l = MidendLimits::from_robot(testing::scout_mini_piper_model());
  l.wheel_omega_max_radps = 6.0;
  l.wheel_alpha_max_radps2 = 2.0;
  l.joint_velocity_max_radps.setConstant(0.3);
  l.joint_acceleration_max_radps2.setConstant(0.5);
  l.joint_upper_rad[1] = 1.25;
  l.joint_lower_rad[4] = 0.45;
  return l;
}

double breakdown_error(const CostBreakdown& a, const CostBreakdown& b) {
  const double pairs[][2] = {{a.wheel_velocity, b.wheel_velocity},
                             {a.wheel_acceleration, b.wheel_acceleration},
                             {a.joint_position, b.joint_position},
                             {a.joint_velocity, b.joint_velocity},
                             {a.joint_acceleration, b.joint_acceleration},
                             {a.residual_base, b.residual_base},
                             {a.residual_arm, b.residual_arm},
                             {a.min_speed, b.min_speed}};
  double e = 0.0;
  for (const auto& p : pairs) e = std::max(e, std::abs(p[0] - p[1]) / std::max(1e-12, std::abs(p[1])));
  return e;
}

void compare(const planner::WholeBodyPath& path, const MidendLimits& limits, unsigned seed,
             const MidendSettings& settings = {}) {
  const ReferenceBuild ref = build_reference_path(path, limits, settings);
  ASSERT_EQ(ref.outcome, ReferenceOutcome::kOk);
  MidendProblem problem(ref.path, limits, settings);
  const int n = problem.num_variables();
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  int active_samples = 0;
  for (const double sigma : {0.0, 0.003, 0.03, 0.15, 0.5}) {
    Eigen::VectorXd x = problem.initial_guess();
    for (int k = 0; k < n; ++k) x[k] += sigma * normal(rng);
    for (const std::uint32_t mask : kMasks) {
      problem.set_terms(mask);
      Eigen::VectorXd g_fast(n), g_ref(n);
      CostBreakdown b_fast, b_ref;
      problem.set_reference_sampling(false);
      const double f_fast = problem.evaluate(x, &g_fast, &b_fast);
      problem.set_reference_sampling(true);
      const double f_ref = problem.evaluate(x, &g_ref, &b_ref);
      ASSERT_TRUE(std::isfinite(f_ref));
      EXPECT_NEAR(f_fast, f_ref, 1e-12 * std::max(1.0, std::abs(f_ref))) << "mask " << mask << " sigma " << sigma;
      EXPECT_LT(breakdown_error(b_fast, b_ref), 1e-10) << "mask " << mask << " sigma " << sigma;
      EXPECT_LE((g_fast - g_ref).norm(), 1e-10 * std::max(1.0, g_ref.norm())) << "mask " << mask << " sigma " << sigma;
      if (b_ref.penalties() - b_ref.boundary_heading > 0.0) ++active_samples;
    }
  }
  EXPECT_GT(active_samples, 10);  // the comparison is not between two zeros
}

TEST(PieceSampler, MatchesReferenceOnForest) { compare(testing::forest_slalom(50), tight_limits(), 1); }
TEST(PieceSampler, MatchesReferenceOnThreePointTurn) { compare(testing::three_point_turn(), tight_limits(), 2); }
TEST(PieceSampler, MatchesReferenceWithRobotLimits) {
  compare(testing::forward_with_turn(), MidendLimits::from_robot(testing::scout_mini_piper_model()), 3);
}
// Pieces spanning many reference edges (interior nodes, ties between them) and one edge each.
TEST(PieceSampler, MatchesReferenceWithLongAndSingleEdgePieces) {
  MidendSettings wide;
  wide.max_edges_per_piece = 8;
  wide.piece_length_m = 4.0;
  wide.piece_arm_motion_rad = 4.0;
  wide.piece_duration_ratio = 100.0;
  // Keeps kappa at samples_per_edge * edges: with the time-based minimum (the tight limits make
  // these pieces long) the two min-speed sums run over many more samples and differ by rounding
  // at the 2e-12 level, above this test's 1e-12. The time-based kappa is compared above.
  wide.max_sample_interval_s = 0.0;
  compare(testing::forest_slalom(50), tight_limits(), 4, wide);
  MidendSettings single;
  single.max_edges_per_piece = 1;
  single.max_sample_interval_s = 0.0;  // as above
  compare(testing::three_point_turn(), tight_limits(), 5, single);
}

/// A safety-like extra cost: K = sum_i sum_j w_j (T_i / kappa) |p_xy(t_ij) - c|^2 ... over each
/// piece's samples t_ij = (j / kappa) T_i, plus a joint term, with its exact partials.
double sample_extra(const Trajectory& traj, ExtraCostGradient* grad) {
  constexpr int kKappa = 6;
  const Eigen::Vector2d centre(0.5, 1.0);
  double k_total = 0.0;
  for (int i = 0; i < traj.num_pieces(); ++i) {
    const TrajectoryPiece& p = traj.piece(i);
    for (int j = 0; j <= kKappa; ++j) {
      const double frac = static_cast<double>(j) / kKappa;
      const double t = frac * p.duration_s;
      const double w = (j == 0 || j == kKappa ? 0.5 : 1.0) * p.duration_s / kKappa;
      const TrajVector z = piece_derivative(p.coeffs, t, 0);
      const TrajVector zd = piece_derivative(p.coeffs, t, 1);
      const Eigen::Vector2d d = z.head<2>() - centre;
      const double q = z[3] - 0.2;
      const double g = 0.1 * d.squaredNorm() + 0.3 * q * q * q * q;
      k_total += w * g;
      if (grad) {
        TrajVector dg = TrajVector::Zero();
        dg.head<2>() = 0.2 * d;
        dg[3] = 1.2 * q * q * q;
        grad->coeffs[static_cast<std::size_t>(i)] += w * minco::basis(t, 0) * dg.transpose();
        grad->durations_s[static_cast<std::size_t>(i)] += g / kKappa * (j == 0 || j == kKappa ? 0.5 : 1.0) +
                                                          w * frac * dg.dot(zd);
      }
    }
  }
  return k_total;
}

TEST(MidendExtraCost, GradientMatchesCentralDifferences) {
  MidendSettings settings;
  const MidendLimits limits = MidendLimits::from_robot(testing::scout_mini_piper_model());
  const ReferenceBuild ref = build_reference_path(testing::three_point_turn(), limits, settings);
  ASSERT_EQ(ref.outcome, ReferenceOutcome::kOk);
  MidendProblem problem(ref.path, limits, settings);
  problem.set_extra_cost(sample_extra);
  const int n = problem.num_variables();
  std::mt19937 rng(7);
  std::normal_distribution<double> normal(0.0, 0.05);
  Eigen::VectorXd x = problem.initial_guess();
  for (int k = 0; k < n; ++k) x[k] += normal(rng);
  for (const std::uint32_t mask : {static_cast<std::uint32_t>(kTermExtra), static_cast<std::uint32_t>(kTermAll)}) {
    problem.set_terms(mask);
    Eigen::VectorXd g(n);
    CostBreakdown b;
    const double f = problem.evaluate(x, &g, &b);
    ASSERT_TRUE(std::isfinite(f));
    EXPECT_GT(b.extra, 0.0);
    if (mask == kTermExtra) {
      EXPECT_DOUBLE_EQ(f, b.extra);
    }
    Eigen::VectorXd fd(n);
    for (int k = 0; k < n; ++k) {
      const double h = 1e-6 * std::max(1.0, std::abs(x[k]));
      Eigen::VectorXd xs = x;
      auto f_at = [&](double dx) {
        xs[k] = x[k] + dx;
        return problem.evaluate(xs, nullptr, nullptr);
      };
      fd[k] = (-f_at(2 * h) + 8 * f_at(h) - 8 * f_at(-h) + f_at(-2 * h)) / (12.0 * h);
    }
    EXPECT_LT((g - fd).norm() / fd.norm(), 1e-6) << "mask " << mask;
  }
  // Masking the term or removing the function removes it.
  problem.set_terms(kTermAll & ~kTermExtra);
  CostBreakdown b;
  problem.evaluate(x, nullptr, &b);
  EXPECT_EQ(b.extra, 0.0);
  problem.set_terms(kTermAll);
  problem.set_extra_cost({});
  problem.evaluate(x, nullptr, &b);
  EXPECT_EQ(b.extra, 0.0);
}

TEST(MidendExtraCost, NonFiniteExtraCostRejectsThePoint) {
  MidendSettings settings;
  const MidendLimits limits = MidendLimits::from_robot(testing::scout_mini_piper_model());
  const ReferenceBuild ref = build_reference_path(testing::forward_with_turn(), limits, settings);
  MidendProblem problem(ref.path, limits, settings);
  problem.set_extra_cost([](const Trajectory&, ExtraCostGradient*) { return std::numeric_limits<double>::infinity(); });
  Eigen::VectorXd g(problem.num_variables());
  EXPECT_FALSE(std::isfinite(problem.evaluate(problem.initial_guess(), &g, nullptr)));
  EXPECT_TRUE(g.isZero());
}

// MidendSettings::limit_penalty_fraction: the joint-rate (and wheel) penalties start at f * the
// limit. With the limits at 1.05 x the largest joint speed / acceleration the initial guess has
// at any sample: no cost with f = 1, a positive one with f = 0.9 (both samplers, same value).
TEST(PieceSampler, LimitPenaltiesStartAtTheFractionOfTheLimit) {
  const MidendLimits robot = MidendLimits::from_robot(testing::scout_mini_piper_model());
  const ReferenceBuild ref = build_reference_path(testing::forward_with_turn(), robot, MidendSettings{});
  ASSERT_EQ(ref.outcome, ReferenceOutcome::kOk);
  double qd = 0.0, qdd = 0.0;  // largest |q_dot|, |q_ddot| at the penalty samples
  {
    MidendProblem problem(ref.path, robot, MidendSettings{});
    const Eigen::VectorXd x = problem.initial_guess();
    const std::vector<TrajectoryPiece> pieces = problem.pieces(x.data());
    std::size_t i = 0;
    for (const ReferenceSegment& seg : ref.path.segments) {
      for (int p = 0; p < seg.num_pieces(); ++p, ++i) {
        ASSERT_LT(i, pieces.size());
        for (int j = 0; j <= seg.intervals[p]; ++j) {
          const double t = pieces[i].duration_s * j / seg.intervals[p];
          const minco::Basis b1 = minco::basis(t, 1), b2 = minco::basis(t, 2);
          const TrajVector v = pieces[i].coeffs.transpose() * b1, a = pieces[i].coeffs.transpose() * b2;
          qd = std::max(qd, v.tail<kNumArmJoints>().cwiseAbs().maxCoeff());
          qdd = std::max(qdd, a.tail<kNumArmJoints>().cwiseAbs().maxCoeff());
        }
      }
    }
  }
  ASSERT_GT(qd, 0.0);
  ASSERT_GT(qdd, 0.0);
  MidendLimits limits = robot;
  limits.joint_velocity_max_radps.setConstant(1.05 * qd);
  limits.joint_acceleration_max_radps2.setConstant(1.05 * qdd);
  for (const std::uint32_t mask : {kTermJointVelocity, kTermJointAcceleration}) {
    double cost[2][2] = {};  // [f = 1, f = 0.9][fast, reference]
    for (int k = 0; k < 2; ++k) {
      MidendSettings settings;
      settings.limit_penalty_fraction = k == 0 ? 1.0 : 0.9;
      MidendProblem problem(ref.path, limits, settings);
      problem.set_terms(mask);
      const Eigen::VectorXd x = problem.initial_guess();
      for (int r = 0; r < 2; ++r) {
        problem.set_reference_sampling(r == 1);
        Eigen::VectorXd g(problem.num_variables());
        cost[k][r] = problem.evaluate(x, &g, nullptr);
      }
    }
    EXPECT_EQ(cost[0][0], 0.0) << "mask " << mask;
    EXPECT_EQ(cost[0][1], 0.0) << "mask " << mask;
    EXPECT_GT(cost[1][0], 0.0) << "mask " << mask;
    EXPECT_NEAR(cost[1][0], cost[1][1], 1e-12 * cost[1][1]) << "mask " << mask;
  }
}

}  // namespace
}  // namespace porter::midend

namespace porter::midend {
namespace {

// MidendSettings::residual_penalty_fraction: the residual penalties start at f * rho. Every
// interior arm waypoint of a straight line is offset by 0.6 rho_m on q1: no residual cost with
// f = 1, a positive one with f = 0.5 (both samplers, same value).
TEST(PieceSampler, ResidualPenaltyStartsAtTheFractionOfRho) {
  const MidendLimits limits = MidendLimits::from_robot(testing::scout_mini_piper_model());
  double cost[2][2] = {};  // [f = 1, f = 0.5][fast, reference]
  for (int k = 0; k < 2; ++k) {
    MidendSettings settings;
    settings.residual_penalty_fraction = k == 0 ? 1.0 : 0.5;
    settings.max_edges_per_piece = 1;
    const ReferenceBuild ref = build_reference_path(testing::straight_line(12), limits, settings);
    ASSERT_EQ(ref.outcome, ReferenceOutcome::kOk);
    MidendProblem problem(ref.path, limits, settings);
    ASSERT_EQ(problem.num_segments(), 1);
    problem.set_terms(kTermResidualArm);
    Eigen::VectorXd x = problem.initial_guess();
    for (int i = 0; i + 1 < problem.num_pieces(); ++i) x[kTrajDim * i + 2] += 0.6 * settings.residual_arm_bound_rad;
    for (int r = 0; r < 2; ++r) {
      problem.set_reference_sampling(r == 1);
      CostBreakdown b;
      Eigen::VectorXd g(problem.num_variables());
      problem.evaluate(x, &g, &b);
      cost[k][r] = b.residual_arm;
    }
  }
  EXPECT_EQ(cost[0][0], 0.0);
  EXPECT_EQ(cost[0][1], 0.0);
  EXPECT_GT(cost[1][0], 0.0);
  EXPECT_NEAR(cost[1][0], cost[1][1], 1e-12 * cost[1][1]);
}

}  // namespace
}  // namespace porter::midend

namespace porter::midend {
namespace {

// Pieces whose values are too large for the screen's products (SampleRows::moderate is false:
// here every duration is scaled by e^60 through the global time scale, the last variable) take
// the exact path at every sample; fast and reference still agree.
TEST(PieceSampler, MatchesReferenceWhenTheScreenStandsDown) {
  const MidendLimits limits = tight_limits();
  const ReferenceBuild ref = build_reference_path(testing::three_point_turn(), limits, MidendSettings{});
  ASSERT_EQ(ref.outcome, ReferenceOutcome::kOk);
  MidendProblem problem(ref.path, limits, MidendSettings{});
  Eigen::VectorXd x = problem.initial_guess();
  x[problem.num_variables() - 1] = 60.0;
  const int n = problem.num_variables();
  Eigen::VectorXd g_fast(n), g_ref(n);
  CostBreakdown b_fast, b_ref;
  problem.set_terms(kTermAll & ~(kTermEnergy | kTermTime));
  const double f_fast = problem.evaluate(x, &g_fast, &b_fast);
  problem.set_reference_sampling(true);
  const double f_ref = problem.evaluate(x, &g_ref, &b_ref);
  ASSERT_TRUE(std::isfinite(f_ref));
  ASSERT_GT(b_ref.residual_base + b_ref.residual_arm, 0.0);  // slow motion: the residuals bite
  EXPECT_NEAR(f_fast, f_ref, 1e-12 * std::max(1.0, std::abs(f_ref)));
  EXPECT_LE((g_fast - g_ref).norm(), 1e-10 * std::max(1.0, g_ref.norm()));
}

}  // namespace
}  // namespace porter::midend
