// The daemon's loop on the empty scene with a real Planner: refusals (no map, stale map, no
// state, goal in collision), a plan and its arrival, a re-plan around an obstacle seen ahead that
// starts in the executed state, brakes when the way ahead is blocked.
#include <algorithm>
#include <stdexcept>

#include <gtest/gtest.h>

#include "daemon_fixtures.hpp"
#include "porter/planner_daemon/goal_loop.hpp"

namespace porter::planner_daemon {
namespace {

/// lead_s: long enough for a plan on a loaded test machine (a plan finishing after its hand-off
/// is replaced by a brake, which the re-plan test would see instead).
GoalLoopParams params() {
  GoalLoopParams p;
  p.max_map_age_s = 2.0;
  p.max_state_age_s = 0.5;
  p.handoff.lead_s = 4.0;
  p.handoff.latency_s = 0.1;
  p.handoff.braking = BrakingLimits{1.0, 1.0, 0.3};
  p.collision_step_s = 0.02;
  p.max_attempts = 3;
  return p;
}

class GoalLoopTest : public ::testing::Test {
 protected:
  void SetUp() override {
    scene_ = testing::empty_scene();
    open_ = voxelize(scene_);
    loop_ = std::make_unique<GoalLoop>(testing::make_planner(scene_), params(), clock_);
  }
  std::optional<MeasuredState> state_at(const RobotConfiguration& c) const {
    MeasuredState s;
    s.utime = clock_();
    s.config = c;
    s.valid = true;
    return s;
  }
  Goal goal(std::int64_t id = 7) const {
    Goal g;
    g.goal_id = id;
    g.spec = pipeline::GoalSpec::exact(scene_.goal);
    return g;
  }
  static bool has_state(const Outcome& o, GoalLoopState s) {
    return std::any_of(o.reports.begin(), o.reports.end(), [&](const Report& r) { return r.state == s; });
  }
  static std::string reasons(const Outcome& o) {
    std::string all;
    for (const auto& r : o.reports) all += std::string(to_string(r.state)) + ": " + r.reason + "\n";
    return all;
  }
  /// Plans the scene's goal from its start on the open map and returns the publication.
  /// (Throws when no trajectory was published: the test fails with the reasons.)
  Publication plan_open() {
    EXPECT_FALSE(loop_->on_map(open_, clock_()).publication.has_value());
    const Outcome o = loop_->on_goal(goal(), state_at(scene_.start));
    if (!o.publication) throw std::runtime_error("no trajectory published: " + reasons(o));
    return *o.publication;
  }
  Scene scene_;
  OccupancyGrid open_;
  testing::TestClock clock_;
  std::unique_ptr<GoalLoop> loop_;
};

TEST_F(GoalLoopTest, RefusesAGoalWithoutAMap) {
  const Outcome o = loop_->on_goal(goal(), state_at(scene_.start));
  EXPECT_FALSE(o.publication);
  ASSERT_EQ(o.reports.size(), 1u);
  EXPECT_EQ(o.reports[0].state, GoalLoopState::kNoMap);
  EXPECT_EQ(o.reports[0].goal_id, 7);
  EXPECT_FALSE(loop_->has_goal());
}

TEST_F(GoalLoopTest, RefusesToPlanOnAStaleMapSayingHowOld) {
  loop_->on_map(open_, clock_() - 5'000'000);
  const Outcome o = loop_->on_goal(goal(), state_at(scene_.start));
  EXPECT_FALSE(o.publication);
  ASSERT_EQ(o.reports.size(), 1u);
  EXPECT_EQ(o.reports[0].state, GoalLoopState::kNoMap);
  EXPECT_NE(o.reports[0].reason.find("old, limit 2.00 s"), std::string::npos) << o.reports[0].reason;
  EXPECT_EQ(loop_->stats().plans, 0);
  // The same map stamped now is planned on.
  loop_->on_map(open_, clock_());
  EXPECT_TRUE(loop_->on_goal(goal(), state_at(scene_.start)).publication.has_value());
}

TEST_F(GoalLoopTest, RefusesWithoutAFreshState) {
  loop_->on_map(open_, clock_());
  Outcome o = loop_->on_goal(goal(), std::nullopt);
  ASSERT_EQ(o.reports.size(), 1u);
  EXPECT_EQ(o.reports[0].state, GoalLoopState::kNoState);
  auto old = state_at(scene_.start);
  old->utime -= 2'000'000;
  o = loop_->on_goal(goal(), old);
  ASSERT_EQ(o.reports.size(), 1u);
  EXPECT_EQ(o.reports[0].state, GoalLoopState::kNoState);
  EXPECT_NE(o.reports[0].reason.find("old"), std::string::npos);
}

TEST_F(GoalLoopTest, RefusesAGoalInCollisionSayingWhy) {
  loop_->on_map(testing::with_box(open_, 7.6, 8.4, -0.4, 0.4), clock_());
  const Outcome o = loop_->on_goal(goal(), state_at(scene_.start));
  EXPECT_FALSE(o.publication);
  ASSERT_FALSE(o.reports.empty());
  EXPECT_EQ(o.reports.back().state, GoalLoopState::kFailed);
  EXPECT_NE(o.reports.back().reason.find("invalid_goal"), std::string::npos) << o.reports.back().reason;
  EXPECT_FALSE(loop_->has_goal());
}

TEST_F(GoalLoopTest, PlansWithStageTimesAndReportsTheEndOfTheTrajectory) {
  const std::int64_t before = clock_();
  const Publication p = plan_open();
  ASSERT_GT(p.trajectory.total_duration_s(), 1.0);
  EXPECT_FALSE(p.braking);
  EXPECT_GE(p.start_utime, before);
  EXPECT_LE(p.start_utime, clock_() + 200'000);
  // Ends at the goal.
  EXPECT_NEAR(p.trajectory.position(p.trajectory.total_duration_s())[0], scene_.goal.base.x_m, 1e-3);
  EXPECT_TRUE(loop_->on_tick(state_at(scene_.start)).reports.empty());  // still executing
  clock_.advance_to(p.start_utime + static_cast<std::int64_t>(p.trajectory.total_duration_s() * 1e6) + 1000);
  const Outcome end = loop_->on_tick(state_at(scene_.goal));
  ASSERT_EQ(end.reports.size(), 1u);
  EXPECT_EQ(end.reports[0].state, GoalLoopState::kIdle);
  EXPECT_FALSE(loop_->has_goal());
}

// A trajectory that ended with the robot short of the goal (the tracker stopped on a fault) is
// followed by a plan from where the robot stands; at the goal the goal is done.
TEST_F(GoalLoopTest, ATrajectoryEndedShortOfTheGoalIsPlannedAgainFromWhereTheRobotStands) {
  const Publication p = plan_open();
  clock_.advance_to(p.start_utime + static_cast<std::int64_t>(p.trajectory.total_duration_s() * 1e6) + 1000);
  RobotConfiguration stuck = scene_.start;
  stuck.base.x_m += 1.0;
  EXPECT_TRUE(loop_->on_tick(state_at(stuck)).reports.empty()) << "plans only on a fresh map";
  loop_->on_map(open_, clock_());
  const Outcome again = loop_->on_tick(state_at(stuck));
  ASSERT_TRUE(has_state(again, GoalLoopState::kPlanning)) << reasons(again);
  EXPECT_NE(again.reports.front().reason.find("from the goal"), std::string::npos) << reasons(again);
  ASSERT_TRUE(again.publication.has_value()) << reasons(again);
  EXPECT_NEAR(again.publication->trajectory.position(0.0)[0], stuck.base.x_m, 1e-6);
  EXPECT_TRUE(loop_->has_goal());
  const Publication& q = *again.publication;
  clock_.advance_to(q.start_utime + static_cast<std::int64_t>(q.trajectory.total_duration_s() * 1e6) + 1000);
  const Outcome end = loop_->on_tick(state_at(scene_.goal));
  ASSERT_TRUE(has_state(end, GoalLoopState::kIdle)) << reasons(end);
  EXPECT_FALSE(loop_->has_goal());
}

// While a trajectory executes, a new goal is planned from the state at now + lead on it; the
// result takes over exactly there, or, when the pipeline cannot plan from that moving state, a
// brake from now is published and said why (the pipeline's moving starts are often refused on
// the wheel-acceleration limit at the hand-off: the daemon must be correct in both cases).
TEST_F(GoalLoopTest, ANewGoalWhileMovingIsPlannedFromTheHandoffStateOrBrakedFor) {
  GoalLoopParams p = params();
  p.handoff.lead_s = 3.0;
  loop_ = std::make_unique<GoalLoop>(testing::make_planner(scene_), p, clock_);
  const Publication first = plan_open();
  Goal again = goal(8);
  again.spec.arm_q_rad.reset();  // the same pose with the arm free: a new goal id, planned again
  const Outcome o = loop_->on_goal(again, state_at(scene_.start));
  EXPECT_EQ(loop_->stats().plans, 2);
  ASSERT_TRUE(o.publication.has_value()) << reasons(o);
  const Publication& next = *o.publication;
  EXPECT_EQ(next.plan_id, first.plan_id + 1);
  const double th = static_cast<double>(next.start_utime - first.start_utime) * 1e-6;
  for (int order = 0; order <= 2; ++order)
    EXPECT_LT((next.trajectory.derivative(0.0, order) - first.trajectory.derivative(th, order)).norm(), 1e-6)
        << "order " << order;
  if (!next.braking) {
    EXPECT_GE(th, p.handoff.lead_s);
    EXPECT_LE(th, p.handoff.lead_s + 1.0);
    EXPECT_NEAR(next.trajectory.position(next.trajectory.total_duration_s())[0], 8.0, 1e-3);
  } else {
    ASSERT_TRUE(has_state(o, GoalLoopState::kFailed)) << reasons(o);
    EXPECT_EQ(o.reports[1].reason.find("invalid_start"), std::string::npos) << reasons(o);
    EXPECT_LT(th, p.handoff.lead_s);
    EXPECT_LT(next.trajectory.velocity(next.trajectory.total_duration_s()).norm(), 1e-9);
  }
}

TEST_F(GoalLoopTest, AnObstacleSeenAheadIsReplannedFromTheHandoffOrBrakedFor) {
  GoalLoopParams p = params();
  p.handoff.lead_s = 3.0;
  loop_ = std::make_unique<GoalLoop>(testing::make_planner(scene_), p, clock_);
  const Publication first = plan_open();
  // A box on the right half of the straight path, 5.5 m ahead: beyond the hand-off.
  const double box_x = 5.5;
  const OccupancyGrid blocked = testing::with_box(open_, box_x, box_x + 0.2, -0.2, 0.1);
  const Outcome o = loop_->on_map(blocked, clock_());
  EXPECT_EQ(loop_->stats().blocked_checks, 1);
  EXPECT_EQ(loop_->stats().replans, 1);
  EXPECT_EQ(loop_->stats().plans, 2);
  ASSERT_TRUE(has_state(o, GoalLoopState::kReplanning)) << reasons(o);
  EXPECT_NE(o.reports.front().reason.find("re-plan from"), std::string::npos) << reasons(o);
  // The re-plan may take the time until its hand-off, less latency and reserve (the back-end
  // takes it when that is longer than its budget). The hand-off is lead_s into the executing
  // trajectory, which starts at most latency_s after now.
  ASSERT_GE(o.reports.size(), 2u) << reasons(o);
  EXPECT_GT(o.reports[1].time_available_s, 0.0) << reasons(o);
  EXPECT_LE(o.reports[1].time_available_s, p.handoff.lead_s - p.handoff_reserve_s);
  ASSERT_TRUE(o.publication.has_value()) << reasons(o);
  const Publication& next = *o.publication;
  const double th = static_cast<double>(next.start_utime - first.start_utime) * 1e-6;
  for (int order = 0; order <= 2; ++order)
    EXPECT_LT((next.trajectory.derivative(0.0, order) - first.trajectory.derivative(th, order)).norm(), 1e-6)
        << "order " << order;
  planner::KernelCollisionChecker check(loop_->planner().kernel_checker().robot());
  check.set_map(blocked);
  if (!next.braking) {
    // The re-plan: taken over at the hand-off, clear of the box.
    EXPECT_GE(th, p.handoff.lead_s);
    EXPECT_FALSE(check.check_trajectory(next.trajectory).in_collision);
  } else {
    // The re-plan failed (said on the status): a brake from now that stops short of the box.
    EXPECT_TRUE(has_state(o, GoalLoopState::kFailed)) << reasons(o);
    EXPECT_LT(th, p.handoff.lead_s);
    const Trajectory& b = next.trajectory;
    EXPECT_LT(b.velocity(b.total_duration_s()).norm(), 1e-9);
    EXPECT_LT(b.position(b.total_duration_s())[0], box_x);
    EXPECT_TRUE(loop_->has_goal());  // planned again from rest once stopped
  }
}

TEST_F(GoalLoopTest, BrakesAtOnceWhenTheObstacleIsTooCloseToReplan) {
  const Publication first = plan_open();
  const Trajectory& t = first.trajectory;
  // Move to where the robot is at x = 3 (under way), then a wall 1.7 m ahead of the base's origin:
  // a re-plan would take over only after it.
  double t_now = 0.0;
  while (t_now < t.total_duration_s() && t.position(t_now)[0] < 3.0) t_now += 0.01;
  ASSERT_GT(t.velocity(t_now).head<2>().norm(), 0.1) << "the fixture must be driving there";
  clock_.advance_to(first.start_utime + static_cast<std::int64_t>(t_now * 1e6));
  const Outcome o = loop_->on_map(testing::with_box(open_, 4.7, 4.9, -3.0, 3.0), clock_());
  ASSERT_TRUE(o.publication.has_value()) << reasons(o);
  EXPECT_TRUE(o.publication->braking);
  EXPECT_EQ(loop_->stats().plans, 1);  // no plan tried
  EXPECT_EQ(loop_->stats().brakes, 1);
  const double tb = static_cast<double>(o.publication->start_utime - first.start_utime) * 1e-6;
  // now + latency; now is read after the map update (its time counts).
  EXPECT_GE(tb, t_now + params().handoff.latency_s);
  EXPECT_LE(tb, t_now + params().handoff.latency_s + 0.5);
  const Trajectory& b = o.publication->trajectory;
  EXPECT_LT((b.position(0.0) - t.position(tb)).norm(), 1e-6);
  EXPECT_LT((b.velocity(0.0) - t.velocity(tb)).norm(), 1e-6);
  EXPECT_LT(b.velocity(b.total_duration_s()).norm(), 1e-9);
  EXPECT_LT(b.position(b.total_duration_s())[0], 4.7);
  // The goal is kept: once the brake has ended, the next tick plans again from rest (the wall
  // spans the map: that plan fails and the goal is given up).
  EXPECT_TRUE(loop_->has_goal());
  clock_.advance_to(o.publication->start_utime + static_cast<std::int64_t>(b.total_duration_s() * 1e6) + 1000);
  RobotConfiguration stopped = scene_.start;
  stopped.base.x_m = b.position(b.total_duration_s())[0];
  loop_->on_map(testing::with_box(open_, 4.7, 4.9, -3.0, 3.0), clock_());
  const Outcome retry = loop_->on_tick(state_at(stopped));
  EXPECT_EQ(loop_->stats().plans, 2) << reasons(retry);
  EXPECT_TRUE(has_state(retry, GoalLoopState::kFailed)) << reasons(retry);
  EXPECT_FALSE(loop_->has_goal());
}

}  // namespace
}  // namespace porter::planner_daemon
