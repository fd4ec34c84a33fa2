// State fusion, stepped with explicit time: odometry only, LIO + odometry propagation between
// LIO stamps against a known path, staleness flags, restarts of inputs, LIO jumps, e-stop.

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "porter/state/fusion.hpp"
#include "porter/state/pose2.hpp"

namespace porter::state {
namespace {

constexpr std::int64_t kT0 = 1'700'000'000'000'000;

// The true path: a base driving a figure of varying curvature, T_W_B(t) integrated finely.
struct TruePath {
  double v(double t) const { return 0.4 + 0.1 * std::sin(0.5 * t); }
  double w(double t) const { return 0.3 * std::sin(0.3 * t); }
  BasePose start{2.0, -1.0, 0.4};
};

std::int64_t us(double t) { return kT0 + static_cast<std::int64_t>(std::llround(t * 1e6)); }

double position_error(const BasePose& a, const BasePose& b) {
  return std::hypot(a.x_m - b.x_m, a.y_m - b.y_m);
}

FusionParams params() {
  FusionParams p;
  p.start_pose = {1.0, 2.0, 0.5};
  return p;
}

TEST(Pose2, ComposeInverseBetween) {
  const BasePose a{1.0, 2.0, 0.7}, b{-0.5, 0.3, -2.9};
  const BasePose ab = compose(a, b);
  const BasePose back = between(a, ab);
  EXPECT_NEAR(back.x_m, b.x_m, 1e-12);
  EXPECT_NEAR(back.y_m, b.y_m, 1e-12);
  EXPECT_NEAR(back.yaw_rad, b.yaw_rad, 1e-12);
  const BasePose id = compose(a, inverse(a));
  EXPECT_NEAR(std::hypot(id.x_m, id.y_m), 0.0, 1e-12);
  EXPECT_NEAR(id.yaw_rad, 0.0, 1e-12);
  // Interpolation takes the short way round the angle.
  EXPECT_NEAR(interpolate({0, 0, 3.0}, {0, 0, -3.0}, 0.5).yaw_rad, M_PI, 0.15);
  // An arc: a quarter circle of radius 1.
  const BasePose q = integrate_unicycle({}, 1.0, 1.0, 0.5 * M_PI);
  EXPECT_NEAR(q.x_m, 1.0, 1e-12);
  EXPECT_NEAR(q.y_m, 1.0, 1e-12);
  EXPECT_NEAR(q.yaw_rad, 0.5 * M_PI, 1e-12);
}

TEST(StateFusion, NothingYet) {
  StateFusion f(params());
  const FusedState s = f.output(kT0);
  EXPECT_EQ(s.pose_source, PoseSource::none);
  EXPECT_FALSE(s.pose_valid);
  EXPECT_FALSE(s.base_valid);
  EXPECT_FALSE(s.arm_valid);
  EXPECT_EQ(s.base_utime, 0);
  EXPECT_FALSE(s.has_arm);
}

TEST(StateFusion, OdometryOnlyIsAnchoredAtTheStartPose) {
  StateFusion f(params());
  // The driver's odometry frame starts somewhere arbitrary.
  const BasePose odom0{5.0, 5.0, -1.0};
  ASSERT_TRUE(f.on_odometry({us(0), odom0, 0.0, 0.0, false}, us(0)).first);
  FusedState s = f.output(us(0));
  EXPECT_EQ(s.pose_source, PoseSource::wheel_odom);
  EXPECT_TRUE(s.pose_valid);
  EXPECT_TRUE(s.base_valid);
  EXPECT_NEAR(s.T_W_B.x_m, 1.0, 1e-12);
  EXPECT_NEAR(s.T_W_B.y_m, 2.0, 1e-12);
  EXPECT_NEAR(s.T_W_B.yaw_rad, 0.5, 1e-12);
  // Drive 0.4 m forward in the odometry frame: the world pose moves 0.4 m along its heading.
  const BasePose odom1 = compose(odom0, BasePose{0.4, 0.0, 0.0});
  f.on_odometry({us(0.8), odom1, 0.5, 0.0, false}, us(0.8));
  s = f.output(us(0.8));
  EXPECT_NEAR(s.T_W_B.x_m, 1.0 + 0.4 * std::cos(0.5), 1e-12);
  EXPECT_NEAR(s.T_W_B.y_m, 2.0 + 0.4 * std::sin(0.5), 1e-12);
  EXPECT_EQ(s.pose_utime, us(0.8));
  EXPECT_EQ(s.base_utime, us(0.8));
  EXPECT_DOUBLE_EQ(s.v_mps, 0.5);
}

TEST(StateFusion, OutputExtrapolatesTheNewestOdometryBoundedly) {
  FusionParams p = params();
  p.start_pose = {};
  p.max_extrapolation_s = 0.02;
  StateFusion f(p);
  f.on_odometry({us(0), {}, 1.0, 0.0, false}, us(0));
  FusedState s = f.output(us(0.01));
  EXPECT_NEAR(s.T_W_B.x_m, 0.01, 1e-12);
  EXPECT_EQ(s.utime, us(0.01));
  s = f.output(us(0.05));  // beyond the bound: 20 ms at most
  EXPECT_NEAR(s.T_W_B.x_m, 0.02, 1e-12);
  EXPECT_EQ(s.utime, us(0.02));
}

// Odometry at 50 Hz from a drifting wheel model (2 % scale error, a yaw-rate bias), LIO at
// 10 Hz stamped with the true pose, arriving 60 ms late; output at 100 Hz compared with the
// true pose at the instant each output refers to.
struct FusionRun {
  double max_error_m = 0.0;
  double max_yaw_error_rad = 0.0;
  double max_step_m = 0.0;  ///< largest change of the output between consecutive outputs
};

FusionRun run_path(bool with_lio, double duration_s) {
  const TruePath path;
  FusionParams p = params();
  p.start_pose = path.start;
  StateFusion f(p);
  BasePose odom{};  // the driver's frame
  FusionRun r;
  std::vector<std::pair<double, BasePose>> lio_queue;  // (arrival time, sample)
  BasePose truth = path.start;
  std::vector<BasePose> truth_ms;  // the true pose at every millisecond
  BasePose last_out;
  bool have_out = false;
  for (int ms = 0; ms <= static_cast<int>(duration_s * 1000); ++ms) {
    const double t = ms * 1e-3;
    if (ms > 0) {
      const double tm = t - 0.5e-3;
      truth = integrate_unicycle(truth, path.v(tm), path.w(tm), 1e-3);
      odom = integrate_unicycle(odom, 1.02 * path.v(tm), path.w(tm) + 0.02, 1e-3);
    }
    truth_ms.push_back(truth);
    if (ms % 20 == 0) f.on_odometry({us(t), odom, 1.02 * path.v(t), path.w(t) + 0.02, false}, us(t));
    if (with_lio && ms % 100 == 0) lio_queue.push_back({t + 0.06, truth});
    if (with_lio && !lio_queue.empty() && t >= lio_queue.front().first - 1e-9) {
      const auto [arrival, pose] = lio_queue.front();
      lio_queue.erase(lio_queue.begin());
      const LioUpdate u = f.on_lio({us(arrival - 0.06), pose}, us(t));
      EXPECT_TRUE(u.used);
      EXPECT_FALSE(u.jumped);
    }
    if (ms % 10 == 0 && t > 0.5) {
      const FusedState s = f.output(us(t));
      EXPECT_TRUE(s.pose_valid);
      EXPECT_EQ(s.pose_source, with_lio ? PoseSource::lio : PoseSource::wheel_odom);
      // Outputs refer to odometry stamps plus an extrapolation: whole milliseconds here.
      const std::int64_t at_us = s.utime - kT0;
      EXPECT_EQ(at_us % 1000, 0);
      const BasePose ref = truth_ms.at(static_cast<std::size_t>(at_us / 1000));
      r.max_error_m = std::max(r.max_error_m, position_error(s.T_W_B, ref));
      r.max_yaw_error_rad =
          std::max(r.max_yaw_error_rad, std::abs(wrap_angle(s.T_W_B.yaw_rad - ref.yaw_rad)));
      if (have_out) r.max_step_m = std::max(r.max_step_m, position_error(s.T_W_B, last_out));
      last_out = s.T_W_B;
      have_out = true;
    }
  }
  return r;
}

TEST(StateFusion, LioPropagatedByOdometryFollowsTheTruePath) {
  const FusionRun with = run_path(true, 20.0);
  const FusionRun without = run_path(false, 20.0);
  // Between LIO stamps only ~160 ms of odometry drift accumulates.
  EXPECT_LT(with.max_error_m, 0.005);
  EXPECT_LT(with.max_yaw_error_rad, 0.005);
  // Odometry alone drifts far more over 20 s.
  EXPECT_GT(without.max_error_m, 0.3);
  // Smooth at 100 Hz: no output step larger than the motion in 10 ms plus the small LIO
  // corrections (speed <= 0.5 m/s: 5 mm per output).
  EXPECT_LT(with.max_step_m, 0.0065);
}

TEST(StateFusion, LioJumpIsTakenAndCounted) {
  FusionParams p = params();
  p.start_pose = {};
  StateFusion f(p);
  f.on_odometry({us(0), {}, 0.0, 0.0, false}, us(0));
  EXPECT_FALSE(f.on_lio({us(0), {0.05, 0.0, 0.0}}, us(0)).jumped);  // first LIO: re-anchors
  f.on_odometry({us(0.1), {}, 0.0, 0.0, false}, us(0.1));
  LioUpdate u = f.on_lio({us(0.1), {0.06, 0.0, 0.0}}, us(0.1));
  EXPECT_TRUE(u.used);
  EXPECT_FALSE(u.jumped);
  f.on_odometry({us(0.2), {}, 0.0, 0.0, false}, us(0.2));
  u = f.on_lio({us(0.2), {0.56, 0.0, 0.0}}, us(0.2));  // 0.5 m jump
  EXPECT_TRUE(u.jumped);
  EXPECT_NEAR(u.jump_m, 0.5, 1e-9);
  EXPECT_EQ(f.counters().lio_jumps, 1u);
  EXPECT_NEAR(f.output(us(0.2)).T_W_B.x_m, 0.56, 1e-12);  // LIO is the truth
  // A stamp older than the previous LIO pose is ignored.
  u = f.on_lio({us(0.15), {9.0, 0.0, 0.0}}, us(0.21));
  EXPECT_FALSE(u.used);
  EXPECT_EQ(f.counters().lio_ignored, 1u);
}

TEST(StateFusion, LioIgnoredWhenDisabled) {
  FusionParams p = params();
  p.use_lio = false;
  StateFusion f(p);
  f.on_odometry({us(0), {}, 0.0, 0.0, false}, us(0));
  EXPECT_FALSE(f.on_lio({us(0), {7.0, 7.0, 0.0}}, us(0)).used);
  const FusedState s = f.output(us(0));
  EXPECT_EQ(s.pose_source, PoseSource::wheel_odom);
  EXPECT_NEAR(s.T_W_B.x_m, 1.0, 1e-12);
}

TEST(StateFusion, StalenessFlagsAndRecovery) {
  StateFusion f(params());
  ArmSample arm;
  arm.utime = us(0);
  arm.q_rad.setConstant(0.3);
  f.on_arm(arm, us(0));
  f.on_odometry({us(0), {}, 0.0, 0.0, false}, us(0));
  f.on_lio({us(0), {3.0, 3.0, 0.0}}, us(0));
  FusedState s = f.output(us(0.04));
  EXPECT_TRUE(s.arm_valid && s.base_valid && s.pose_valid);
  EXPECT_EQ(s.pose_source, PoseSource::lio);
  // Arm stale after 50 ms, base after 100 ms, LIO after 300 ms; last values kept.
  s = f.output(us(0.06));
  EXPECT_FALSE(s.arm_valid);
  EXPECT_TRUE(s.has_arm);
  EXPECT_DOUBLE_EQ(s.q_rad[0], 0.3);
  EXPECT_TRUE(s.base_valid);
  s = f.output(us(0.11));
  EXPECT_FALSE(s.base_valid);
  EXPECT_TRUE(s.pose_valid);  // LIO still fresh
  EXPECT_EQ(s.pose_source, PoseSource::lio);
  s = f.output(us(0.31));
  EXPECT_FALSE(s.pose_valid);
  EXPECT_EQ(s.pose_source, PoseSource::wheel_odom);
  EXPECT_NEAR(s.T_W_B.x_m, 3.0, 1e-12);
  // The inputs come back: fresh again at once.
  f.on_odometry({us(0.5), {0.1, 0.0, 0.0}, 0.0, 0.0, false}, us(0.5));
  f.on_arm(arm, us(0.5));
  s = f.output(us(0.5));
  EXPECT_TRUE(s.base_valid && s.arm_valid && s.pose_valid);
  EXPECT_EQ(s.pose_source, PoseSource::wheel_odom);  // LIO still stale: odometry carries on
  EXPECT_NEAR(s.T_W_B.x_m, 3.1, 1e-12);
  f.on_lio({us(0.5), {3.2, 3.0, 0.0}}, us(0.5));
  EXPECT_EQ(f.output(us(0.5)).pose_source, PoseSource::lio);
}

TEST(StateFusion, RestartedOdometryContinuesThePose) {
  FusionParams p = params();
  p.start_pose = {};
  StateFusion f(p);
  BasePose odom{};
  for (int i = 0; i <= 50; ++i) {  // 1 s forward at 1 m/s
    odom = {0.02 * i, 0.0, 0.0};
    f.on_odometry({us(0.02 * i), odom, 1.0, 0.0, false}, us(0.02 * i));
  }
  const BasePose before = f.output(us(1.0)).T_W_B;
  EXPECT_NEAR(before.x_m, 1.0, 1e-9);
  // The driver restarts 0.5 s later: its odometry begins again at zero (and its clock may
  // restart too), and the base moves on.
  EXPECT_FALSE(f.output(us(1.5)).base_valid);
  const OdometryUpdate u = f.on_odometry({us(1.5), {}, 0.0, 0.0, false}, us(1.5));
  EXPECT_TRUE(u.reset);
  EXPECT_EQ(f.counters().odometry_resets, 1u);
  FusedState s = f.output(us(1.5));
  EXPECT_TRUE(s.base_valid);
  EXPECT_NEAR(s.T_W_B.x_m, before.x_m, 1e-9);
  f.on_odometry({us(1.52), {0.01, 0.0, 0.0}, 0.5, 0.0, false}, us(1.52));
  EXPECT_NEAR(f.output(us(1.52)).T_W_B.x_m, 1.01, 1e-9);
  // A stamp far in the past (a restarted clock) is a restart too, not an out-of-order sample.
  EXPECT_TRUE(f.on_odometry({us(-100.0), {0.02, 0.0, 0.0}, 0.0, 0.0, false}, us(1.54)).reset);
  EXPECT_NEAR(f.output(us(1.54)).T_W_B.x_m, 1.01, 1e-9);
}

TEST(StateFusion, ReorderedOdometryIsIgnored) {
  StateFusion f(params());
  f.on_odometry({us(1.0), {1.0, 0.0, 0.0}, 0.0, 0.0, false}, us(1.0));
  const OdometryUpdate u = f.on_odometry({us(0.98), {0.99, 0.0, 0.0}, 0.0, 0.0, false}, us(1.0));
  EXPECT_TRUE(u.out_of_order);
  EXPECT_EQ(f.counters().odometry_out_of_order, 1u);
  EXPECT_EQ(f.output(us(1.0)).base_utime, us(1.0));
}

TEST(StateFusion, LioBeforeOdometryAnchorsIt) {
  StateFusion f(params());
  f.on_lio({us(0), {4.0, -1.0, 1.0}}, us(0));
  FusedState s = f.output(us(0));
  EXPECT_EQ(s.pose_source, PoseSource::lio);
  EXPECT_TRUE(s.pose_valid);
  EXPECT_FALSE(s.base_valid);
  f.on_odometry({us(0.01), {10.0, 10.0, 2.0}, 0.0, 0.0, false}, us(0.01));
  s = f.output(us(0.01));
  EXPECT_NEAR(s.T_W_B.x_m, 4.0, 1e-12);
  EXPECT_NEAR(s.T_W_B.yaw_rad, 1.0, 1e-12);
}

TEST(StateFusion, EstopPassesThrough) {
  StateFusion f(params());
  f.on_odometry({us(0), {}, 0.0, 0.0, false}, us(0));
  EXPECT_FALSE(f.output(us(0)).estop_active);
  f.on_estop(true);
  EXPECT_TRUE(f.output(us(0)).estop_active);
  f.on_estop(false);
  EXPECT_FALSE(f.output(us(0)).estop_active);
  // A driver reporting its own e-stop counts while it is fresh.
  f.on_odometry({us(0.02), {}, 0.0, 0.0, true}, us(0.02));
  EXPECT_TRUE(f.output(us(0.02)).estop_active);
}

TEST(StateFusion, InvalidParamsThrow) {
  FusionParams p = params();
  p.base_timeout_s = 0.0;
  EXPECT_THROW(StateFusion{p}, std::invalid_argument);
  p = params();
  p.start_pose.x_m = std::nan("");
  EXPECT_THROW(StateFusion{p}, std::invalid_argument);
}

}  // namespace
}  // namespace porter::state
