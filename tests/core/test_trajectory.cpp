// Trajectory construction, validation, piece lookup, polynomial evaluation, quintic Hermite
// pieces and C2 continuity, concatenation.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

#include "porter/core/trajectory.hpp"

namespace porter {
namespace {

Trajectory make(std::vector<TrajectoryPiece> pieces, double start_yaw_rad = 0.0) {
  TrajectoryResult r = Trajectory::create(std::move(pieces), start_yaw_rad);
  if (!r.ok()) throw std::runtime_error("unexpected failure: " + r.error);
  return std::move(*r.trajectory);
}

PieceCoeffs random_coeffs(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  PieceCoeffs c;
  for (int k = 0; k < kTrajNumCoeffs; ++k)
    for (int d = 0; d < kTrajDim; ++d) c(k, d) = u(rng);
  return c;
}

// Slow reference: d^r/dtau^r sum_k c_k tau^k term by term with std::pow.
TrajVector reference_derivative(const PieceCoeffs& c, double tau, int r) {
  TrajVector out = TrajVector::Zero();
  for (int k = r; k < kTrajNumCoeffs; ++k) {
    double factor = 1.0;
    for (int m = 0; m < r; ++m) factor *= (k - m);
    out += factor * std::pow(tau, k - r) * c.row(k).transpose();
  }
  return out;
}

TEST(Trajectory, CreateRejectsEmpty) {
  const TrajectoryResult r = Trajectory::create({}, 0.0);
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.error.find("at least one piece"), std::string::npos) << r.error;
}

TEST(Trajectory, CreateRejectsBadDurations) {
  for (double T : {0.0, -1.0, std::numeric_limits<double>::infinity(),
                   std::numeric_limits<double>::quiet_NaN()}) {
    std::vector<TrajectoryPiece> pieces(3);
    for (auto& p : pieces) p.duration_s = 1.0;
    pieces[1].duration_s = T;
    const TrajectoryResult r = Trajectory::create(pieces, 0.0);
    EXPECT_FALSE(r.ok()) << T;
    EXPECT_NE(r.error.find("pieces[1].duration_s"), std::string::npos) << r.error;
  }
}

TEST(Trajectory, CreateRejectsOverlongTotal) {
  std::vector<TrajectoryPiece> pieces(25);
  for (auto& p : pieces) p.duration_s = kTrajMaxPieceDuration_s;
  const TrajectoryResult r = Trajectory::create(pieces, 0.0);
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.error.find("total duration"), std::string::npos) << r.error;
  pieces.resize(24);
  EXPECT_TRUE(Trajectory::create(pieces, 0.0).ok()) << "exactly 24 h";
}

TEST(Trajectory, CreateRejectsDurationsOutsideTheLimits) {
  for (double T : {std::numeric_limits<double>::max(), 3600.5, 1e-300, 0.9e-6}) {
    std::vector<TrajectoryPiece> pieces(2);
    for (auto& p : pieces) p.duration_s = 1.0;
    pieces[1].duration_s = T;
    const TrajectoryResult r = Trajectory::create(pieces, 0.0);
    EXPECT_FALSE(r.ok()) << T;
    EXPECT_NE(r.error.find("pieces[1].duration_s: must be within"), std::string::npos) << r.error;
  }
}

// Huge finite coefficients used to be accepted and sampled to infinity.
TEST(Trajectory, CreateRejectsCoefficientsThatReachTooFar) {
  std::vector<TrajectoryPiece> pieces(1);
  pieces[0].duration_s = 10.0;
  pieces[0].coeffs(5, 0) = 1e300;
  TrajectoryResult r = Trajectory::create(pieces, 0.0);
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.error.find("pieces[0].coeffs[5][0]: |c| T^5"), std::string::npos) << r.error;
  pieces[0].coeffs(5, 0) = 1.01e6 / 1e5;  // 10.1 * 10^5 > 1e6
  EXPECT_FALSE(Trajectory::create(pieces, 0.0).ok());
  pieces[0].coeffs(5, 0) = 0.99e6 / 1e5;
  r = Trajectory::create(pieces, 0.0);
  ASSERT_TRUE(r.ok()) << r.error;
  for (int order = 0; order <= 5; ++order)
    EXPECT_TRUE(r.trajectory->derivative(10.0, order).allFinite()) << order;
  EXPECT_FALSE(Trajectory::create(pieces, 1e11).ok()) << "absurd start yaw";
}

TEST(Trajectory, CreateRejectsBadEta) {
  for (int eta : {0, 2, -2}) {
    std::vector<TrajectoryPiece> pieces(2);
    for (auto& p : pieces) p.duration_s = 1.0;
    pieces[1].eta = eta;
    const TrajectoryResult r = Trajectory::create(pieces, 0.0);
    EXPECT_FALSE(r.ok()) << eta;
    EXPECT_NE(r.error.find("pieces[1].eta"), std::string::npos) << r.error;
  }
}

TEST(Trajectory, CreateRejectsNonFiniteCoefficientsAndYaw) {
  std::vector<TrajectoryPiece> pieces(2);
  for (auto& p : pieces) p.duration_s = 1.0;
  pieces[0].coeffs(4, 6) = std::numeric_limits<double>::quiet_NaN();
  TrajectoryResult r = Trajectory::create(pieces, 0.0);
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.error.find("pieces[0].coeffs[4][6]"), std::string::npos) << r.error;

  pieces[0].coeffs(4, 6) = 0.0;
  r = Trajectory::create(pieces, std::numeric_limits<double>::infinity());
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.error.find("start_yaw_rad"), std::string::npos) << r.error;

  r = Trajectory::create(pieces, 0.25);
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_TRUE(r.error.empty());
  EXPECT_EQ(r.trajectory->num_pieces(), 2);
}

TEST(Trajectory, DurationsAndPieceStarts) {
  std::vector<TrajectoryPiece> pieces(3);
  pieces[0].duration_s = 0.5;
  pieces[1].duration_s = 1.25;
  pieces[2].duration_s = 2.0;
  const Trajectory traj = make(pieces, 0.3);
  EXPECT_EQ(traj.num_pieces(), 3);
  EXPECT_DOUBLE_EQ(traj.total_duration_s(), 3.75);
  EXPECT_DOUBLE_EQ(traj.piece_start_time_s(0), 0.0);
  EXPECT_DOUBLE_EQ(traj.piece_start_time_s(1), 0.5);
  EXPECT_DOUBLE_EQ(traj.piece_start_time_s(2), 1.75);
  EXPECT_DOUBLE_EQ(traj.piece_start_time_s(3), 3.75);
  EXPECT_DOUBLE_EQ(traj.start_yaw_rad(), 0.3);
}

TEST(Trajectory, LocateUsesStartingPieceAtKnotsAndClamps) {
  std::vector<TrajectoryPiece> pieces(4);
  const double T[4] = {0.5, 1.0, 0.25, 2.0};
  for (int i = 0; i < 4; ++i) pieces[static_cast<size_t>(i)].duration_s = T[i];
  const Trajectory traj = make(pieces);
  double tau = -1.0;
  EXPECT_EQ(traj.locate(0.0, &tau), 0);
  EXPECT_DOUBLE_EQ(tau, 0.0);
  EXPECT_EQ(traj.locate(0.25, &tau), 0);
  EXPECT_DOUBLE_EQ(tau, 0.25);
  EXPECT_EQ(traj.locate(0.5, &tau), 1);  // knot: the piece that starts there
  EXPECT_DOUBLE_EQ(tau, 0.0);
  EXPECT_EQ(traj.locate(1.6, &tau), 2);
  EXPECT_NEAR(tau, 0.1, 1e-15);
  EXPECT_EQ(traj.locate(1.75, &tau), 3);
  EXPECT_DOUBLE_EQ(tau, 0.0);
  EXPECT_EQ(traj.locate(3.75, &tau), 3);  // the end belongs to the last piece
  EXPECT_DOUBLE_EQ(tau, 2.0);
  EXPECT_EQ(traj.locate(10.0, &tau), 3);  // clamped
  EXPECT_DOUBLE_EQ(tau, 2.0);
  EXPECT_EQ(traj.locate(-3.0, &tau), 0);
  EXPECT_DOUBLE_EQ(tau, 0.0);
  EXPECT_EQ(traj.locate(std::numeric_limits<double>::quiet_NaN(), &tau), 0);
  EXPECT_DOUBLE_EQ(tau, 0.0);
}

TEST(Trajectory, KnownPolynomialValues) {
  // Piece 1 of a two-piece trajectory: z_0 = 1 + 2 tau + 3 tau^2 + 4 tau^3 + 5 tau^4 + 6 tau^5.
  std::vector<TrajectoryPiece> pieces(2);
  pieces[0].duration_s = 1.0;
  pieces[1].duration_s = 2.0;
  for (int k = 0; k < kTrajNumCoeffs; ++k) pieces[1].coeffs(k, 0) = k + 1.0;
  pieces[1].coeffs(1, 5) = -0.5;  // z_5 = -0.5 tau
  const Trajectory traj = make(pieces);
  const double t = 1.5;  // tau = 0.5
  EXPECT_NEAR(traj.position(t)[0], 1 + 1 + 0.75 + 0.5 + 0.3125 + 0.1875, 1e-12);
  EXPECT_NEAR(traj.velocity(t)[0], 2 + 3 + 3 + 2.5 + 1.875, 1e-12);
  EXPECT_NEAR(traj.acceleration(t)[0], 6 + 12 + 15 + 15, 1e-12);
  EXPECT_NEAR(traj.jerk(t)[0], 24 + 60 + 90, 1e-12);
  EXPECT_NEAR(traj.snap(t)[0], 120 + 360, 1e-12);
  EXPECT_NEAR(traj.derivative(t, 5)[0], 720, 1e-12);
  EXPECT_EQ(traj.derivative(t, 6), TrajVector::Zero());
  EXPECT_EQ(traj.derivative(t, -1), traj.position(t));
  EXPECT_NEAR(traj.position(t)[5], -0.25, 1e-15);
  EXPECT_NEAR(traj.velocity(t)[5], -0.5, 1e-15);
  EXPECT_EQ(traj.acceleration(t)[5], 0.0);
  EXPECT_EQ(traj.position(t)[1], 0.0);
}

TEST(Trajectory, DerivativesMatchSlowReference) {
  std::mt19937 rng(7);
  std::vector<TrajectoryPiece> pieces(5);
  const double T[5] = {0.3, 1.7, 0.9, 2.2, 0.6};
  for (int i = 0; i < 5; ++i) {
    pieces[static_cast<size_t>(i)].duration_s = T[i];
    pieces[static_cast<size_t>(i)].coeffs = random_coeffs(rng);
  }
  const Trajectory traj = make(pieces);
  std::uniform_real_distribution<double> ut(-0.5, traj.total_duration_s() + 0.5);
  for (int s = 0; s < 200; ++s) {
    const double t = ut(rng);
    double tau = 0.0;
    const int i = traj.locate(t, &tau);
    const double tc = std::min(std::max(t, 0.0), traj.total_duration_s());
    EXPECT_NEAR(traj.piece_start_time_s(i) + tau, tc, 1e-14);
    ASSERT_TRUE(tc >= traj.piece_start_time_s(i) && tc <= traj.piece_start_time_s(i + 1));
    for (int r = 0; r <= 7; ++r) {
      const TrajVector ref = reference_derivative(pieces[static_cast<size_t>(i)].coeffs, tau, r);
      const TrajVector got = traj.derivative(t, r);
      for (int d = 0; d < kTrajDim; ++d) {
        EXPECT_NEAR(got[d], ref[d], 1e-12 * std::max(1.0, std::abs(ref[d]))) << t << " " << r;
      }
    }
  }
}

TEST(QuinticHermite, MatchesBoundaryStates) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  auto vec = [&] {
    TrajVector v;
    for (int d = 0; d < kTrajDim; ++d) v[d] = u(rng);
    return v;
  };
  for (double T : {0.2, 1.0, 3.7}) {
    const TrajVector p0 = vec(), v0 = vec(), a0 = vec(), p1 = vec(), v1 = vec(), a1 = vec();
    const PieceCoeffs c = quintic_hermite(p0, v0, a0, p1, v1, a1, T);
    const TrajVector* start[3] = {&p0, &v0, &a0};
    const TrajVector* end[3] = {&p1, &v1, &a1};
    for (int r = 0; r < 3; ++r) {
      EXPECT_LT((piece_derivative(c, 0.0, r) - *start[r]).cwiseAbs().maxCoeff(), 1e-12);
      EXPECT_LT((piece_derivative(c, T, r) - *end[r]).cwiseAbs().maxCoeff(), 1e-11) << T << r;
    }
  }
}

TEST(QuinticHermite, ReproducesQuintics) {
  // A quintic is its own Hermite interpolant.
  std::mt19937 rng(11);
  const PieceCoeffs c = random_coeffs(rng);
  const double T = 1.3;
  const PieceCoeffs h = quintic_hermite(piece_derivative(c, 0, 0), piece_derivative(c, 0, 1),
                                        piece_derivative(c, 0, 2), piece_derivative(c, T, 0),
                                        piece_derivative(c, T, 1), piece_derivative(c, T, 2), T);
  EXPECT_LT((h - c).cwiseAbs().maxCoeff(), 1e-11);
}

// A smooth 8-D function and its first two derivatives.
struct Smooth {
  TrajVector p(double t) const {
    TrajVector z;
    for (int d = 0; d < kTrajDim; ++d) z[d] = std::sin((d + 1) * 0.4 * t + d) + 0.1 * d * t;
    return z;
  }
  TrajVector v(double t) const {
    TrajVector z;
    for (int d = 0; d < kTrajDim; ++d)
      z[d] = (d + 1) * 0.4 * std::cos((d + 1) * 0.4 * t + d) + 0.1 * d;
    return z;
  }
  TrajVector a(double t) const {
    TrajVector z;
    for (int d = 0; d < kTrajDim; ++d) {
      const double w = (d + 1) * 0.4;
      z[d] = -w * w * std::sin(w * t + d);
    }
    return z;
  }
};

Trajectory hermite_from(const Smooth& f, const std::vector<double>& knots) {
  std::vector<TrajectoryPiece> pieces;
  for (size_t i = 0; i + 1 < knots.size(); ++i) {
    TrajectoryPiece p;
    p.duration_s = knots[i + 1] - knots[i];
    p.coeffs = quintic_hermite(f.p(knots[i]), f.v(knots[i]), f.a(knots[i]), f.p(knots[i + 1]),
                               f.v(knots[i + 1]), f.a(knots[i + 1]), p.duration_s);
    pieces.push_back(p);
  }
  return make(pieces);
}

TEST(QuinticHermite, PiecewiseTrajectoryIsC2AndApproximatesTheFunction) {
  const Smooth f;
  std::vector<double> knots = {0.0};
  for (int i = 0; i < 12; ++i) knots.push_back(knots.back() + 0.15 + 0.05 * (i % 3));
  const Trajectory traj = hermite_from(f, knots);
  ASSERT_EQ(traj.num_pieces(), 12);
  for (int i = 0; i + 1 < traj.num_pieces(); ++i) {
    const TrajectoryPiece& a = traj.piece(i);
    const TrajectoryPiece& b = traj.piece(i + 1);
    for (int r = 0; r <= 2; ++r) {
      const TrajVector left = piece_derivative(a.coeffs, a.duration_s, r);
      const TrajVector right = piece_derivative(b.coeffs, 0.0, r);
      EXPECT_LT((left - right).cwiseAbs().maxCoeff(), 1e-11) << "knot " << i << " order " << r;
    }
    // Just either side of the knot through the public API.
    const double tk = traj.piece_start_time_s(i + 1);
    EXPECT_LT((traj.position(tk - 1e-9) - traj.position(tk)).norm(), 1e-7);
    EXPECT_LT((traj.velocity(tk - 1e-9) - traj.velocity(tk)).norm(), 1e-7);
    EXPECT_LT((traj.acceleration(tk - 1e-9) - traj.acceleration(tk)).norm(), 1e-6);
  }
  for (double t = 0.0; t <= traj.total_duration_s(); t += 0.013) {
    EXPECT_LT((traj.position(t) - f.p(t)).cwiseAbs().maxCoeff(), 1e-5) << t;
    EXPECT_LT((traj.velocity(t) - f.v(t)).cwiseAbs().maxCoeff(), 1e-3) << t;
  }
}

TEST(Trajectory, ConcatenateShiftsTheSecond) {
  std::mt19937 rng(5);
  std::vector<TrajectoryPiece> a(2), b(3);
  for (auto* v : {&a, &b})
    for (auto& p : *v) {
      p.duration_s = 0.4 + 0.1 * v->size();
      p.coeffs = random_coeffs(rng);
    }
  b[1].eta = -1;
  const Trajectory ta = make(a, 0.7), tb = make(b, -1.0);
  const Trajectory ab = Trajectory::concatenate(ta, tb);
  EXPECT_EQ(ab.num_pieces(), 5);
  EXPECT_DOUBLE_EQ(ab.start_yaw_rad(), 0.7);
  EXPECT_DOUBLE_EQ(ab.total_duration_s(), ta.total_duration_s() + tb.total_duration_s());
  EXPECT_EQ(ab.piece(3).eta, -1);
  for (double t = 0.0; t < tb.total_duration_s(); t += 0.07) {
    EXPECT_LT((ab.position(ta.total_duration_s() + t) - tb.position(t)).norm(), 1e-12) << t;
  }
  for (double t = 0.0; t < ta.total_duration_s(); t += 0.07) {
    EXPECT_EQ(ab.jerk(t), ta.jerk(t)) << t;
  }
}

}  // namespace
}  // namespace porter
