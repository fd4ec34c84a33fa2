// The SVSDF metric g_j and its argmin t* (paper eqs. g, tstar) against brute-force dense sampling
// in time, and its gradients (w.r.t. the query point and the raw trajectory parameters, envelope
// theorem) against finite differences.

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "backend_fixtures.hpp"
#include "porter/backend/svsdf.hpp"
#include "porter/backend/swept_body.hpp"
#include "porter/core/kinematics.hpp"

namespace porter::backend {
namespace {

using testing::point_near;

constexpr char kPayload[] = "t_bar";

/// Slow reference: SDF_j(T_j(t)^-1 p) at every t of a dense grid over [lo, hi], with the pose from
/// the trajectory's own heading rule and porter::forward_kinematics (core), nothing of the back-end
/// but the field.
struct DenseMin {
  double value = std::numeric_limits<double>::infinity();
  double t = 0.0;
};
DenseMin dense_minimum(const SweptBody& body, const RobotSdf& sdf, int link, const Eigen::Vector3d& p,
                       double lo, double hi, double dt) {
  DenseMin best;
  const Trajectory& traj = body.trajectory();
  KinematicsWorkspace ws;
  const int n = static_cast<int>(std::ceil((hi - lo) / dt));
  for (int k = 0; k <= n; ++k) {
    const double t = std::min(hi, lo + k * dt);
    const TrajVector z = traj.position(t);
    RobotConfiguration c;
    c.base = {z[0], z[1], traj.base_motion(t).yaw_rad};
    c.q_rad = z.tail<kNumArmJoints>();
    forward_kinematics(body.model(), c, ws);
    const Eigen::Isometry3d& T = ws.T_W_L[static_cast<std::size_t>(link)];
    const double v = sdf.link(link).distance(T.inverse() * p);
    if (v < best.value) best = {v, t};
  }
  return best;
}

testing::RandomTrajectoryOptions RandomTrajectoryOptionsLong() {
  testing::RandomTrajectoryOptions o;
  o.pieces = 8;
  return o;
}

class SvsdfTest : public ::testing::Test {
 protected:
  SvsdfTest() : model_(testing::robot(kPayload)), sdf_(testing::robot_sdf(kPayload)), body_(model_) {}
  const RobotModel& model_;
  const RobotSdf& sdf_;
  SweptBody body_;
};

TEST_F(SvsdfTest, FullSearchMatchesDenseSampling) {
  std::mt19937 rng(5);
  int inside = 0;
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    body_.reset(testing::random_trajectory(model_, seed));
    SvsdfEvaluator eval(sdf_, body_, SvsdfSettings{});
    for (int link = 0; link < kNumLinks; ++link) {
      for (int n = 0; n < 4; ++n) {
        const Eigen::Vector3d p = point_near(body_, link, rng, 0.15);
        SvsdfValue v;
        eval.full(link, p, v);
        const DenseMin ref = dense_minimum(body_, sdf_, link, p, 0.0, body_.duration_s(), 2e-4);
        EXPECT_NEAR(v.g, ref.value, 1e-3) << "seed " << seed << " link " << link << " t* " << v.t_star_s
                                           << " dense t " << ref.t;
        // Never noticeably worse than the dense grid (candidates are ranked on the trilinear scan,
        // so a near-tie between two local minima may resolve to the other one).
        EXPECT_LE(v.g, ref.value + 5e-4);
        // t* is where the value is attained.
        EXPECT_NEAR(eval.evaluate_at(link, p, v.t_star_s, nullptr), v.g, 1e-9);
        inside += v.g < 0.0;
      }
    }
  }
  EXPECT_GT(inside, 3);  // the sample covers points inside swept volumes too
}

TEST_F(SvsdfTest, HintsDoNotChangeTheResultAndScanBoundsHold) {
  // The scan skips samples by a Lipschitz bound and may start from a hint: the result must be the
  // same with any hint, and every per-sample lower bound it reports (the profile) must hold for the
  // trilinear value at that sample (slow reference: every sample looked up).
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int skipped_somewhere = 0;
  for (std::uint64_t seed : {4u, 5u}) {
    body_.reset(testing::random_trajectory(model_, seed, RandomTrajectoryOptionsLong()));
    SvsdfEvaluator eval(sdf_, body_, SvsdfSettings{});
    for (int link = 0; link < kNumLinks; ++link) {
      for (double spread : {0.05, 0.3, 0.9}) {
        const Eigen::Vector3d p = point_near(body_, link, rng, spread);
        SvsdfValue plain, hinted, at_answer;
        ScanProfile profile;
        SearchOptions with_profile;
        with_profile.profile = &profile;
        eval.search(link, p, 0.0, body_.duration_s(), plain, with_profile);
        SearchOptions hint;
        hint.hint_t_s = u(rng) * body_.duration_s();
        eval.search(link, p, 0.0, body_.duration_s(), hinted, hint);
        hint.hint_t_s = plain.t_star_s;
        eval.search(link, p, 0.0, body_.duration_s(), at_answer, hint);
        EXPECT_EQ(plain.g, hinted.g) << "link " << link << " spread " << spread;
        EXPECT_EQ(plain.t_star_s, hinted.t_star_s);
        EXPECT_EQ(plain.g, at_answer.g);
        EXPECT_EQ(plain.t_star_s, at_answer.t_star_s);
        ASSERT_EQ(static_cast<int>(profile.lower.size()), body_.num_samples() - profile.k_lo);
        for (std::size_t i = 0; i < profile.lower.size(); ++i) {
          const int k = profile.k_lo + static_cast<int>(i);
          const double v = sdf_.link(link).distance_fast(body_.sample_pose(k, link).apply(p));
          EXPECT_LE(profile.lower[i], v + 1e-12) << "link " << link << " sample " << k;
        }
      }
    }
    skipped_somewhere += eval.stats().samples_evaluated < eval.stats().samples_in_range;
  }
  EXPECT_GT(skipped_somewhere, 0);  // the skip is exercised
}

TEST_F(SvsdfTest, WindowedSearchMatchesDenseSamplingInTheWindow) {
  std::mt19937 rng(9);
  SvsdfSettings settings;
  settings.window_half_width_s = 0.7;
  for (std::uint64_t seed : {4u, 5u}) {
    body_.reset(testing::random_trajectory(model_, seed));
    SvsdfEvaluator eval(sdf_, body_, settings);
    for (int link = 1; link < kNumLinks; ++link) {
      for (int n = 0; n < 3; ++n) {
        const Eigen::Vector3d p = point_near(body_, link, rng, 0.1);
        SvsdfValue base;
        eval.full(0, p, base);
        SvsdfValue v;
        eval.windowed(link, p, base.t_star_s, v);
        const double lo = std::max(0.0, base.t_star_s - settings.window_half_width_s);
        const double hi = std::min(body_.duration_s(), base.t_star_s + settings.window_half_width_s);
        EXPECT_GE(v.t_star_s, lo - 1e-12);
        EXPECT_LE(v.t_star_s, hi + 1e-12);
        const DenseMin ref = dense_minimum(body_, sdf_, link, p, lo, hi, 2e-4);
        EXPECT_NEAR(v.g, ref.value, 1e-3) << "link " << link;
        // A wide enough window finds the full minimum.
        SvsdfValue whole;
        eval.search(link, p, 0.0, body_.duration_s(), whole);
        EXPECT_LE(whole.g, v.g + 1e-9);
      }
    }
  }
}

TEST_F(SvsdfTest, GradientWithRespectToThePointMatchesFiniteDifferences) {
  std::mt19937 rng(13);
  body_.reset(testing::random_trajectory(model_, 7));
  SvsdfEvaluator eval(sdf_, body_, SvsdfSettings{});
  int checked = 0;
  for (int link = 0; link < kNumLinks; ++link) {
    for (int n = 0; n < 4; ++n) {
      const Eigen::Vector3d p = point_near(body_, link, rng, 0.1);
      SvsdfValue v;
      eval.full(link, p, v);
      const double h = 1e-6;
      Eigen::Vector3d fd;
      for (int a = 0; a < 3; ++a) {
        SvsdfValue vp, vm;
        Eigen::Vector3d dp = Eigen::Vector3d::Zero();
        dp[a] = h;
        eval.full(link, p + dp, vp);
        eval.full(link, p - dp, vm);
        fd[a] = (vp.g - vm.g) / (2 * h);
      }
      // The trilinear field's slope jumps at cell faces; a jump between p -+ h shows as a
      // mismatch of at most the jump, so compare loosely and require most to be tight.
      const double err = (fd - v.grad_p).norm();
      EXPECT_LT(err, 0.05) << "link " << link;
      checked += err < 1e-4;
    }
  }
  EXPECT_GE(checked, 26);  // of 32
}

TEST_F(SvsdfTest, GradientWithRespectToTheTrajectoryMatchesFiniteDifferences) {
  std::mt19937 rng(17);
  const Trajectory traj = testing::random_trajectory(model_, 11, testing::RandomTrajectoryOptions::with_pieces(3));
  body_.reset(traj);
  SvsdfEvaluator eval(sdf_, body_, SvsdfSettings{});
  int tight = 0, total = 0;
  for (int link : {0, 2, 5, 7}) {
    for (int n = 0; n < 3; ++n) {
      const Eigen::Vector3d p = point_near(body_, link, rng, 0.1);
      SvsdfValue v;
      eval.full(link, p, v);
      TrajectoryGradient grad;
      grad.reset(traj.num_pieces());
      grad.add(traj, v.sensitivity, 1.0);
      auto g_of = [&](const Trajectory& t) {
        SweptBody b(model_);
        b.reset(t);
        SvsdfEvaluator e(sdf_, b, SvsdfSettings{});
        SvsdfValue out;
        e.full(link, p, out);
        return out.g;
      };
      for (int i = 0; i < traj.num_pieces(); ++i) {
        // Durations, and the coefficients of the piece holding t* (others have zero gradient).
        const double hT = 1e-6;
        const double fdT = (g_of(testing::perturbed(traj, i, -1, 0, hT)) - g_of(testing::perturbed(traj, i, -1, 0, -hT))) / (2 * hT);
        ++total;
        tight += std::abs(fdT - grad.duration(i)) < 1e-4 * (1 + std::abs(fdT));
        EXPECT_NEAR(fdT, grad.duration(i), 0.05 * (1 + std::abs(fdT))) << "link " << link << " T" << i;
        if (i != v.sensitivity.piece) {
          EXPECT_TRUE(grad.coeffs(i).isZero());
          continue;
        }
        for (int row = 0; row < kTrajNumCoeffs; ++row) {
          for (int col = 0; col < kTrajDim; ++col) {
            const double h = 1e-6 / std::pow(std::max(1.0, traj.piece(i).duration_s), row);
            const double fd = (g_of(testing::perturbed(traj, i, row, col, h)) -
                               g_of(testing::perturbed(traj, i, row, col, -h))) / (2 * h);
            ++total;
            tight += std::abs(fd - grad.coeffs(i)(row, col)) < 1e-4 * (1 + std::abs(fd));
            EXPECT_NEAR(fd, grad.coeffs(i)(row, col), 0.05 * (1 + std::abs(fd)))
                << "link " << link << " piece " << i << " c(" << row << "," << col << ")";
          }
        }
      }
    }
  }
  EXPECT_GE(tight, 0.9 * total);
}

TEST_F(SvsdfTest, PrefilterBoxesContainTheLinkEverywhere) {
  std::mt19937 rng(21);
  body_.reset(testing::random_trajectory(model_, 13));
  std::uniform_real_distribution<double> u(0.0, 1.0);
  BodyState st;
  for (int n = 0; n < 300; ++n) {
    const double t = u(rng) * body_.duration_s();
    body_.evaluate(t, st);
    for (int link = 0; link < kNumLinks; ++link) {
      const Eigen::AlignedBox3d& b = model_.links[static_cast<std::size_t>(link)].bounds;
      for (int c = 0; c < 8; ++c) {
        const auto l = static_cast<std::size_t>(link);
        const Eigen::Vector3d corner =
            st.kin.R_W_L[l] * b.corner(static_cast<Eigen::AlignedBox3d::CornerType>(c)) + st.kin.t_W_L[l];
        EXPECT_TRUE(body_.piece_box(link, st.piece).contains(corner)) << "link " << link << " t " << t;
        EXPECT_TRUE(body_.link_box(link).contains(corner));
      }
    }
  }
}

}  // namespace
}  // namespace porter::backend
