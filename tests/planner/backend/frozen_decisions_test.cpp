// Frozen ball-search decisions (kc_svsdf.hpp "Frozen decisions"): recording changes
// nothing, a replay at the recording point reproduces Algorithm 1, the replayed D and the g_j(p)
// surrogate have finite-difference-exact gradients, and SvsdfSafetyTerm::refresh_decisions() makes
// the next evaluation Algorithm 1's again.

#include <gtest/gtest.h>

#include <random>

#include "backend_fixtures.hpp"
#include "porter/backend/kc_svsdf.hpp"
#include "porter/backend/svsdf_safety_term.hpp"

namespace porter::backend {
namespace {

using testing::point_near;

constexpr char kPayload[] = "t_bar";

class KcSvsdfFrozenDecisionsTest : public ::testing::Test {
 protected:
  KcSvsdfFrozenDecisionsTest() : model_(testing::robot(kPayload)), sdf_(testing::robot_sdf(kPayload)), body_(model_) {
    traj_ = testing::random_trajectory(model_, 21, testing::RandomTrajectoryOptions::with_pieces(3));
    body_.reset(*traj_);
  }
  /// D[link] on `traj` at p with `decisions` replayed (record = false; the record is copied).
  double replayed(const Trajectory& traj, const Eigen::Vector3d& p, int link, const KcSvsdfSettings& s,
                  BallDecisions decisions) {
    SweptBody b(model_);
    b.reset(traj);
    KcSvsdf kc(sdf_, b, s);
    KcSvsdfResult r;
    kc.evaluate(p, 1u << link, r, std::numeric_limits<double>::infinity(), nullptr, &decisions, false);
    return r.links[static_cast<std::size_t>(link)].d;
  }
  const RobotModel& model_;
  const RobotSdf& sdf_;
  SweptBody body_;
  std::optional<Trajectory> traj_;
};

TEST_F(KcSvsdfFrozenDecisionsTest, RecordingChangesNothingAndTheReplayReproducesAlgorithm1) {
  std::mt19937 rng(11);
  for (bool filter : {true, false}) {
    KcSvsdfSettings s;
    s.kinematic_filter = filter;
    KcSvsdf kc(sdf_, body_, s);
    int inside = 0;
    for (int n = 0; n < 64; ++n) {
      const int link = n % kNumLinks;
      const Eigen::Vector3d p = point_near(body_, link, rng, 0.02);
      KcSvsdfResult plain, recorded, replay;
      BallDecisions decisions;
      kc.evaluate(p, 1u << link, plain);
      kc.evaluate(p, 1u << link, recorded, std::numeric_limits<double>::infinity(), nullptr, &decisions, true);
      const auto j = static_cast<std::size_t>(link);
      EXPECT_EQ(plain.links[j].d, recorded.links[j].d);
      EXPECT_TRUE(plain.links[j].escape == recorded.links[j].escape);
      EXPECT_EQ(decisions[j].valid, plain.links[j].inside) << "link " << link;
      if (!plain.links[j].inside) continue;
      ++inside;
      EXPECT_EQ(decisions[j].directions.size(), static_cast<std::size_t>(plain.links[j].iterations));
      kc.evaluate(p, 1u << link, replay, std::numeric_limits<double>::infinity(), nullptr, &decisions, false);
      EXPECT_TRUE(replay.links[j].replayed);
      EXPECT_NEAR(replay.links[j].d, plain.links[j].d, 1e-12) << "link " << link;
      EXPECT_LE((replay.links[j].escape - plain.links[j].escape).norm(), 1e-12) << "link " << link;
    }
    EXPECT_GE(inside, 10) << "filter " << filter;
  }
}

TEST_F(KcSvsdfFrozenDecisionsTest, ReplayedAndSurrogateGradientsMatchFiniteDifferences) {
  std::mt19937 rng(12);
  KcSvsdfSettings s;
  KcSvsdf kc(sdf_, body_, s);
  int replays = 0, surrogates = 0, checked = 0, rough = 0;
  for (int n = 0; n < 40; ++n) {
    const int link = n % kNumLinks;
    const Eigen::Vector3d p = point_near(body_, link, rng, 0.02);
    const auto j = static_cast<std::size_t>(link);
    BallDecisions decisions;
    KcSvsdfResult r;
    kc.evaluate(p, 1u << link, r, std::numeric_limits<double>::infinity(), nullptr, &decisions, true);
    if (!r.links[j].inside) continue;
    // Half of the inside points are evaluated without a record: the surrogate D = g_j(p).
    const bool surrogate = n % 2 == 1;
    if (surrogate) decisions = BallDecisions{};
    kc.evaluate(p, 1u << link, r, std::numeric_limits<double>::infinity(), nullptr, &decisions, false);
    const LinkDistance& l = r.links[j];
    ASSERT_EQ(l.replayed, !surrogate);
    ASSERT_EQ(l.surrogate, surrogate);
    if (surrogate) {
      EXPECT_EQ(l.d, l.g);
    }
    if (l.saturated || l.on_window_edge || l.d == 0.0) continue;
    (surrogate ? surrogates : replays)++;
    TrajectoryGradient grad;
    grad.reset(traj_->num_pieces());
    r.add_gradient(*traj_, link, 1.0, grad);
    auto expect_match = [&](auto&& f, double analytic, const std::string& what) {
      const double h = 4e-7;
      const double d1 = (f(h) - f(-h)) / (2 * h), d2 = (f(0.25 * h) - f(-0.25 * h)) / (0.5 * h);
      // Only the t* refinements' own switches remain (no sample set, argmax or epsilon test).
      if (std::abs(d1 - d2) > 1e-3 * (1 + std::abs(d2))) {
        ++rough;
        return;
      }
      ++checked;
      EXPECT_NEAR(d2, analytic, 1e-3 * (1 + std::abs(d2))) << what << (surrogate ? " surrogate" : " replay");
    };
    for (int a = 0; a < 3; ++a) {
      expect_match(
          [&](double e) {
            Eigen::Vector3d q = p;
            q[a] += e;
            return replayed(*traj_, q, link, s, decisions);
          },
          l.grad_p[a], "link " + std::to_string(link) + " p" + std::to_string(a));
    }
    for (int i = 0; i < traj_->num_pieces(); ++i) {
      for (int row = 0; row < kTrajNumCoeffs; row += 2) {
        for (int col : {0, 2, 5, 7}) {
          expect_match([&](double e) { return replayed(testing::perturbed(*traj_, i, row, col, e), p, link, s, decisions); },
                       grad.coeffs(i)(row, col),
                       "link " + std::to_string(link) + " c" + std::to_string(i) + "(" + std::to_string(row) + "," +
                           std::to_string(col) + ")");
        }
      }
    }
  }
  EXPECT_GE(replays, 4);
  EXPECT_GE(surrogates, 4);
  EXPECT_LE(rough, 0.05 * (checked + rough));
}

TEST_F(KcSvsdfFrozenDecisionsTest, SafetyTermReplaysUntilRefreshed) {
  // Points inside the swept volume of a random trajectory; a second trajectory nearby.
  std::mt19937 rng(13);
  std::vector<ObstaclePoint> points;
  for (int n = 0; n < 80; ++n) points.push_back({point_near(body_, 1 + n % 7, rng, 0.03), kAllLinks});
  const Trajectory other = testing::perturbed(*traj_, 1, 0, 3, 0.02);
  SvsdfSafetySettings frozen_settings;
  frozen_settings.weight = 1.0;
  frozen_settings.threads = 2;
  SvsdfSafetySettings plain_settings = frozen_settings;
  plain_settings.freeze_ball_decisions = false;
  SvsdfSafetyTerm frozen(model_, sdf_, frozen_settings), plain(model_, sdf_, plain_settings);
  frozen.set_points(points);
  plain.set_points(points);
  auto cost = [](SvsdfSafetyTerm& term, const Trajectory& traj) {
    TrajectoryGradient grad;
    grad.reset(traj.num_pieces());
    return term.evaluate(traj, grad, nullptr);
  };
  // The first evaluation is a refresh point: Algorithm 1's value.
  EXPECT_EQ(cost(frozen, *traj_), cost(plain, *traj_));
  ASSERT_GT(frozen.kc_stats().inside_links, 0);
  EXPECT_EQ(frozen.kc_stats().replays, 0);
  // The next ones replay (no ball search is run), until refresh_decisions().
  const std::int64_t iterations = frozen.kc_stats().ball_iterations;
  cost(frozen, other);
  EXPECT_GT(frozen.kc_stats().replays, 0);
  const double again = cost(frozen, *traj_), reference = cost(plain, *traj_);
  EXPECT_NEAR(again, reference, 1e-9 * (1 + reference));  // replay at the recording point
  frozen.refresh_decisions();
  frozen.reset_stats();
  EXPECT_EQ(cost(frozen, other), cost(plain, other));
  EXPECT_EQ(frozen.kc_stats().replays, 0);
  EXPECT_GT(iterations, 0);
}

}  // namespace
}  // namespace porter::backend
