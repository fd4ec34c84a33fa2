// Trajectory <-> minco_trajectory_t: layout, round trip (in memory and through LCM's encoding),
// and every reason from_msg rejects a message.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "porter/msg/trajectory_msg.hpp"

namespace porter {
namespace {

Trajectory random_trajectory(unsigned seed, int n) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  std::vector<TrajectoryPiece> pieces(static_cast<size_t>(n));
  for (auto& p : pieces) {
    p.duration_s = 0.05 + std::abs(u(rng));
    p.eta = u(rng) > 0 ? 1 : -1;
    for (int k = 0; k < kTrajNumCoeffs; ++k)
      for (int d = 0; d < kTrajDim; ++d) p.coeffs(k, d) = u(rng);
  }
  TrajectoryResult r = Trajectory::create(pieces, 0.3);
  EXPECT_TRUE(r.ok()) << r.error;
  return std::move(*r.trajectory);
}

void expect_identical(const Trajectory& a, const Trajectory& b) {
  ASSERT_EQ(a.num_pieces(), b.num_pieces());
  EXPECT_EQ(a.start_yaw_rad(), b.start_yaw_rad());
  for (int i = 0; i < a.num_pieces(); ++i) {
    EXPECT_EQ(a.piece(i).duration_s, b.piece(i).duration_s) << i;
    EXPECT_EQ(a.piece(i).eta, b.piece(i).eta) << i;
    EXPECT_EQ(a.piece(i).coeffs, b.piece(i).coeffs) << i;
  }
}

TEST(TrajectoryMsg, LayoutFollowsTheMessageDefinition) {
  const Trajectory traj = random_trajectory(1, 3);
  const minco_trajectory_t msg = to_msg(traj, 1'700'000'000'000'000, 42, "world", "t_bar");
  EXPECT_EQ(msg.utime, 1'700'000'000'000'000);
  EXPECT_EQ(msg.start_utime, 1'700'000'000'000'000);
  EXPECT_EQ(msg.plan_id, 42);
  EXPECT_EQ(msg.frame_id, "world");
  EXPECT_EQ(msg.payload_id, "t_bar");
  EXPECT_EQ(msg.dimension, 8);
  EXPECT_EQ(msg.order, 5);
  EXPECT_EQ(msg.start_yaw_rad, 0.3);
  EXPECT_EQ(msg.num_pieces, 3);
  ASSERT_EQ(msg.durations_s.size(), 3u);
  ASSERT_EQ(msg.eta.size(), 3u);
  EXPECT_EQ(msg.num_coeffs, 3 * 8 * 6);
  ASSERT_EQ(msg.coeffs.size(), 144u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(msg.durations_s[static_cast<size_t>(i)], traj.piece(i).duration_s);
    EXPECT_EQ(msg.eta[static_cast<size_t>(i)], traj.piece(i).eta);
    for (int d = 0; d < 8; ++d)
      for (int k = 0; k < 6; ++k)
        EXPECT_EQ(msg.coeffs[static_cast<size_t>((i * 8 + d) * 6 + k)], traj.piece(i).coeffs(k, d));
  }
}

TEST(TrajectoryMsg, RoundTripThroughLcmEncoding) {
  const Trajectory traj = random_trajectory(2, 9);
  minco_trajectory_t msg = to_msg(traj, 123456789, -7, "map", "");
  msg.utime = 123999999;
  std::vector<uint8_t> buf(static_cast<size_t>(msg.getEncodedSize()));
  ASSERT_EQ(msg.encode(buf.data(), 0, static_cast<int>(buf.size())), static_cast<int>(buf.size()));
  minco_trajectory_t decoded;
  ASSERT_EQ(decoded.decode(buf.data(), 0, static_cast<int>(buf.size())),
            static_cast<int>(buf.size()));
  const TrajectoryMsgResult r = from_msg(decoded);
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_TRUE(r.error.empty());
  expect_identical(traj, r.value->trajectory);
  EXPECT_EQ(r.value->utime, 123999999);
  EXPECT_EQ(r.value->start_utime, 123456789);
  EXPECT_EQ(r.value->plan_id, -7);
  EXPECT_EQ(r.value->frame_id, "map");
  EXPECT_EQ(r.value->payload_id, "");
  for (double t = 0.0; t < traj.total_duration_s(); t += 0.1) {
    EXPECT_EQ(r.value->trajectory.position(t), traj.position(t));
    EXPECT_EQ(r.value->trajectory.yaw_rad(t), traj.yaw_rad(t));
  }
}

// A valid message with one field changed must be refused with a reason naming the field.
template <typename Mutate>
void expect_rejected(Mutate mutate, const std::string& fragment) {
  minco_trajectory_t msg = to_msg(random_trajectory(3, 4), 10, 1, "world", "");
  ASSERT_TRUE(from_msg(msg).ok());
  mutate(msg);
  const TrajectoryMsgResult r = from_msg(msg);
  EXPECT_FALSE(r.ok()) << fragment;
  EXPECT_NE(r.error.find(fragment), std::string::npos) << "error: " << r.error;
}

TEST(TrajectoryMsg, RejectsInconsistentMessages) {
  using M = minco_trajectory_t;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  expect_rejected([](M& m) { m.dimension = 3; }, "dimension: expected 8 (got 3)");
  expect_rejected([](M& m) { m.order = 7; }, "order: expected 5 (got 7)");
  expect_rejected([](M& m) { m.num_pieces = 0; }, "num_pieces: must be >= 1");
  expect_rejected([](M& m) { m.num_pieces = -2; }, "num_pieces: must be >= 1");
  expect_rejected([](M& m) { m.num_pieces = 5; }, "durations_s: has 4 entries but num_pieces is 5");
  expect_rejected([](M& m) { m.eta.pop_back(); }, "eta: has 3 entries but num_pieces is 4");
  expect_rejected([](M& m) { m.num_coeffs -= 1; },
                  "num_coeffs: expected num_pieces * dimension * (order + 1) = 192 (got 191)");
  expect_rejected([](M& m) { m.coeffs.pop_back(); },
                  "coeffs: has 191 entries but num_coeffs is 192");
  expect_rejected([](M& m) { m.durations_s[2] = 0.0; }, "durations_s[2]: must be finite and > 0");
  expect_rejected([](M& m) { m.durations_s[1] = -0.5; }, "durations_s[1]: must be finite and > 0");
  expect_rejected([nan](M& m) { m.durations_s[0] = nan; },
                  "durations_s[0]: must be finite and > 0");
  expect_rejected([](M& m) { m.durations_s[3] = std::numeric_limits<double>::infinity(); },
                  "durations_s[3]: must be finite and > 0");
  expect_rejected([](M& m) { m.eta[3] = 0; }, "eta[3]: must be +1 or -1 (got 0)");
  expect_rejected([](M& m) { m.eta[0] = 2; }, "eta[0]: must be +1 or -1 (got 2)");
  expect_rejected([nan](M& m) { m.coeffs[(1 * 8 + 4) * 6 + 5] = nan; },
                  "coeffs[77] (piece 1, d 4, k 5): must be finite");
  expect_rejected([nan](M& m) { m.start_yaw_rad = nan; }, "start_yaw_rad: must be finite");
  expect_rejected(
      [](M& m) {
        for (double& T : m.durations_s) T = std::numeric_limits<double>::max();
      },
      "pieces[0].duration_s: must be within");
  expect_rejected(
      [](M& m) {
        for (double& T : m.durations_s) T = 3500.0;
        for (double& c : m.coeffs) c = 0.0;
        m.num_pieces = 30;
        m.durations_s.assign(30, 3500.0);
        m.eta.assign(30, 1);
        m.num_coeffs = 30 * 48;
        m.coeffs.assign(30 * 48, 0.0);
      },
      "total duration");
  // Huge finite coefficients used to be accepted and sampled to infinity.
  expect_rejected([](M& m) { m.coeffs[(2 * 8 + 1) * 6 + 3] = 1e300; }, "pieces[2].coeffs[3][1]: |c| T^3");
}

}  // namespace
}  // namespace porter
