// KC-SVSDF (Algorithm 1): outside values equal g_j, the ball search against a brute-force depth,
// laziness equals the full algorithm, the KinematicFilter holds for the chosen direction, and the
// gradients (trajectory and point, inside and outside, with the sample set fixed) against finite
// differences.

#include <gtest/gtest.h>

#include <random>

#include "backend_fixtures.hpp"
#include "porter/backend/kc_svsdf.hpp"

namespace porter::backend {
namespace {

using testing::point_near;

constexpr char kPayload[] = "t_bar";

class KcSvsdfTest : public ::testing::Test {
 protected:
  KcSvsdfTest() : model_(testing::robot(kPayload)), sdf_(testing::robot_sdf(kPayload)), body_(model_) {
    traj_ = testing::random_trajectory(model_, 21, testing::RandomTrajectoryOptions::with_pieces(3));
    body_.reset(*traj_);
  }
  double D(const Trajectory& traj, const Eigen::Vector3d& p, int link, const KcSvsdfSettings& s) {
    SweptBody b(model_);
    b.reset(traj);
    KcSvsdf kc(sdf_, b, s);
    KcSvsdfResult r;
    kc.evaluate(p, 1u << link, r);
    return r.links[static_cast<std::size_t>(link)].d;
  }
  const RobotModel& model_;
  const RobotSdf& sdf_;
  SweptBody body_;
  std::optional<Trajectory> traj_;
};

TEST_F(KcSvsdfTest, OutsideValuesAreTheSvsdfAndGAccumulatesEscapes) {
  std::mt19937 rng(1);
  KcSvsdf kc(sdf_, body_, KcSvsdfSettings{});
  SvsdfEvaluator eval(sdf_, body_, KcSvsdfSettings{}.svsdf);
  int outside = 0;
  for (int n = 0; n < 40; ++n) {
    const Eigen::Vector3d p = point_near(body_, n % kNumLinks, rng, 0.2);
    KcSvsdfResult r;
    kc.evaluate(p, kAllLinks, r);
    DofVector G = DofVector::Zero();
    SvsdfValue base;
    eval.full(0, p, base);
    EXPECT_EQ(r.t0_star_s, base.t_star_s);
    // The window holds t0* +- dt.
    EXPECT_LE(r.window_lo_s, base.t_star_s - KcSvsdfSettings{}.svsdf.window_half_width_s + 1e-12);
    EXPECT_GE(r.window_hi_s, base.t_star_s + KcSvsdfSettings{}.svsdf.window_half_width_s - 1e-12);
    for (int j = 0; j < kNumLinks; ++j) {
      const LinkDistance& l = r.links[static_cast<std::size_t>(j)];
      ASSERT_TRUE(l.computed);
      G += l.escape;
      // Joint i moves links i..7 only: the escape of link j has no entry on joints above j.
      for (int c = 3 + std::min(j, kNumArmJoints); c < kNumDof; ++c) EXPECT_EQ(l.escape[c], 0.0);
      if (l.inside) continue;
      ++outside;
      SvsdfValue v;
      if (j == 0) v = base; else eval.search(j, p, r.window_lo_s, r.window_hi_s, v);
      EXPECT_EQ(l.d, v.g);
      EXPECT_TRUE(l.escape.isApprox(v.d_config));
      EXPECT_GT(l.d, 0.0);
    }
    EXPECT_LT((G - r.G).norm(), 1e-12);
  }
  EXPECT_GT(outside, 200);
}

TEST_F(KcSvsdfTest, LazyEvaluationEqualsTheFullAlgorithm) {
  std::mt19937 rng(2);
  KcSvsdf kc(sdf_, body_, KcSvsdfSettings{});
  int inside = 0;
  for (int n = 0; n < 40; ++n) {
    const int link = n % kNumLinks;
    const Eigen::Vector3d p = point_near(body_, link, rng, 0.03);
    KcSvsdfResult all, one;
    kc.evaluate(p, kAllLinks, all);
    kc.evaluate(p, 1u << link, one);
    const LinkDistance& a = all.links[static_cast<std::size_t>(link)];
    const LinkDistance& b = one.links[static_cast<std::size_t>(link)];
    inside += a.inside;
    EXPECT_EQ(a.d, b.d) << "link " << link;
    EXPECT_TRUE(a.escape == b.escape);
    // Only the links it depends on were computed.
    for (int j = 0; j < kNumLinks; ++j) {
      if (one.links[static_cast<std::size_t>(j)].computed && j != link) {
        EXPECT_TRUE(b.inside && (j == link - 1 || j == link - 2 || j < link)) << "link " << link << " computed " << j;
      }
    }
  }
  EXPECT_GT(inside, 10);
}

/// Brute-force depth of p in link j's swept volume: along each of many directions, the first
/// distance at which g_j (dense steps, full search) becomes positive; the minimum over directions.
double brute_force_depth(SvsdfEvaluator& eval, int link, const Eigen::Vector3d& p, double max_r) {
  double depth = max_r;
  const int n = 600;
  for (int k = 0; k < n; ++k) {
    const double z = 1.0 - (2.0 * k + 1.0) / n, rho = std::sqrt(1 - z * z), phi = 2.399963 * k;
    const Eigen::Vector3d d(rho * std::cos(phi), rho * std::sin(phi), z);
    for (double r = 0.0; r < depth; r += 1e-3) {
      SvsdfValue v;
      eval.full(link, p + r * d, v);
      if (v.g > 0.0) {
        depth = std::min(depth, r);
        break;
      }
    }
  }
  return depth;
}

TEST_F(KcSvsdfTest, BallSearchFindsTheDepth) {
  std::mt19937 rng(3);
  KcSvsdfSettings s;
  s.kinematic_filter = false;  // unconstrained: D must be minus the depth
  s.ball_samples = 64;
  s.svsdf.window_half_width_s = 100.0;  // whole trajectory for every link
  KcSvsdf kc(sdf_, body_, s);
  SvsdfEvaluator eval(sdf_, body_, s.svsdf);
  int checked = 0;
  for (int n = 0; n < 60 && checked < 6; ++n) {
    const int link = std::vector<int>{0, 2, 7}[static_cast<std::size_t>(n % 3)];
    const Eigen::Vector3d p = point_near(body_, link, rng, 0.0);
    KcSvsdfResult r;
    kc.evaluate(p, 1u << link, r);
    const LinkDistance& l = r.links[static_cast<std::size_t>(link)];
    if (!l.inside) continue;
    ++checked;
    const double depth = brute_force_depth(eval, link, p, s.initial_radius_m);
    // r stays an upper bound on the depth (each shrink is by a sample's distance to the volume)
    // and comes within the angular sampling error + epsilon of it.
    EXPECT_GE(-l.d, depth - 2e-3) << "link " << link;
    EXPECT_LE(-l.d, depth + s.epsilon_m + 0.1 * depth + 2e-3) << "link " << link;
    EXPECT_LE(l.d, l.g + 1e-9);  // never shallower than the conservative metric g
  }
  EXPECT_GE(checked, 4);
}

TEST_F(KcSvsdfTest, ChosenDirectionSatisfiesTheKinematicFilter) {
  std::mt19937 rng(4);
  KcSvsdf kc(sdf_, body_, KcSvsdfSettings{});
  int checked = 0;
  for (int n = 0; n < 200; ++n) {
    const int link = 2 + n % 6;
    const Eigen::Vector3d p = point_near(body_, link, rng, 0.01);
    KcSvsdfResult r;
    kc.evaluate(p, 1u << link, r);
    const LinkDistance& l = r.links[static_cast<std::size_t>(link)];
    if (!l.inside || l.filter_relaxed || l.d == 0.0) continue;
    ++checked;
    // escape_j = J^T (p - y*) must agree with G on the two upstream joints.
    for (int i : {link - 2, link - 1}) {
      const int c0 = i == 0 ? 0 : 2 + i, nc = i == 0 ? 3 : 1;
      double G_dot = 0.0, G_norm2 = 0.0;
      for (int c = c0; c < c0 + nc; ++c) {
        double G_c = 0.0;
        for (int u = i; u < link; ++u) G_c += r.links[static_cast<std::size_t>(u)].escape[c];
        G_dot += G_c * l.escape[c];
        G_norm2 += G_c * G_c;
      }
      if (G_norm2 < std::pow(KcSvsdfSettings{}.consensus_tolerance, 2)) continue;  // no consensus
      EXPECT_GE(G_dot, -1e-12) << "link " << link << " joint " << i;
    }
  }
  EXPECT_GE(checked, 10);
}

/// Central difference of f at two steps. D is piecewise smooth (the ball search's discrete choices
/// -- worst sample, iteration count -- switch across thin sets): where the two differences disagree
/// the step straddles a switch, and the entry is reported as non-smooth instead of compared.
struct Difference {
  double value = 0.0;
  bool smooth = true;
};
template <class F>
Difference central_difference(F&& f, double h) {
  const double d1 = (f(h) - f(-h)) / (2 * h);
  const double d2 = (f(0.25 * h) - f(-0.25 * h)) / (0.5 * h);
  return {d2, std::abs(d1 - d2) <= 1e-3 * (1 + std::abs(d2))};
}

TEST_F(KcSvsdfTest, GradientsMatchFiniteDifferencesInsideAndOutside) {
  std::mt19937 rng(5);
  for (bool filter : {true, false}) {
    KcSvsdfSettings s;
    s.kinematic_filter = filter;
    KcSvsdf kc(sdf_, body_, s);
    int inside = 0, outside = 0, checked = 0, rough = 0;
    auto expect_match = [&](const Difference& fd, double analytic, const std::string& what) {
      if (!fd.smooth) {
        ++rough;
        return;
      }
      ++checked;
      // The t* tolerance (1e-5 s) leaves ~1e-4 of slack in the envelope gradient.
      EXPECT_NEAR(fd.value, analytic, 1e-3 * (1 + std::abs(fd.value))) << what;
    };
    for (int n = 0; n < 48; ++n) {
      const int link = n % kNumLinks;
      const Eigen::Vector3d p = point_near(body_, link, rng, n % 2 ? 0.02 : 0.1);
      KcSvsdfResult r;
      kc.evaluate(p, 1u << link, r);
      const LinkDistance& l = r.links[static_cast<std::size_t>(link)];
      if (l.saturated || l.d == 0.0 || l.on_window_edge) continue;
      (l.inside ? inside : outside)++;
      const std::string tag = std::string(l.inside ? "inside" : "outside") + " link " + std::to_string(link);
      TrajectoryGradient grad;
      grad.reset(traj_->num_pieces());
      r.add_gradient(*traj_, link, 1.0, grad);
      const double h = 4e-7;
      for (int a = 0; a < 3; ++a) {
        auto f = [&](double e) {
          Eigen::Vector3d q = p;
          q[a] += e;
          KcSvsdfResult rr;
          kc.evaluate(q, 1u << link, rr);
          return rr.links[static_cast<std::size_t>(link)].d;
        };
        expect_match(central_difference(f, h), l.grad_p[a], tag + " p" + std::to_string(a));
      }
      for (int i = 0; i < traj_->num_pieces(); ++i) {
        // Moving a raw duration with the coefficients held opens a position gap at the knot after
        // piece i; an instant near that knot then sees the gap, which no MINCO trajectory has (the
        // duration gradient through MINCO is checked in backend_problem_test).
        bool near_knot = false;
        for (const PointSensitivity& t : l.terms) {
          near_knot = near_knot || (t.piece == i && traj_->piece(i).duration_s - t.tau_s < 0.1) ||
                      (t.piece == i + 1 && t.tau_s < 0.1);
        }
        auto fT = [&](double e) { return D(testing::perturbed(*traj_, i, -1, 0, e), p, link, s); };
        if (!near_knot) expect_match(central_difference(fT, h), grad.duration(i), tag + " T" + std::to_string(i));
        for (int row = 0; row < kTrajNumCoeffs; row += 2) {
          for (int col : {0, 1, 2, 5, 7}) {
            auto fc = [&](double e) { return D(testing::perturbed(*traj_, i, row, col, e), p, link, s); };
            expect_match(central_difference(fc, h), grad.coeffs(i)(row, col),
                         tag + " c" + std::to_string(i) + "(" + std::to_string(row) + "," + std::to_string(col) + ")");
          }
        }
      }
    }
    EXPECT_GE(inside, 5) << "filter " << filter;
    EXPECT_GE(outside, 5) << "filter " << filter;
    EXPECT_LE(rough, 0.1 * (checked + rough)) << "filter " << filter;
  }
}

}  // namespace
}  // namespace porter::backend
