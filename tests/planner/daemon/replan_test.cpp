// The re-planning decisions: the first collision on the rest of a trajectory (checked against a
// dense-sampling reference), the hand-off choice, map freshness.
#include <cmath>

#include <gtest/gtest.h>

#include "daemon_fixtures.hpp"
#include "porter/planner_daemon/replan.hpp"

namespace porter::planner_daemon {
namespace {

/// A straight drive along x at constant speed v from x0, for duration_s.
Trajectory straight(double x0, double v, double duration_s) {
  TrajectoryPiece p;
  p.duration_s = duration_s;
  p.coeffs(0, 0) = x0;
  p.coeffs(1, 0) = v;
  return *Trajectory::create({p}, 0.0).trajectory;
}

HandoffParams params() {
  HandoffParams h;
  h.lead_s = 1.5;
  h.latency_s = 0.1;
  h.braking = BrakingLimits{1.0, 1.0, 0.2};
  return h;
}

TEST(ChooseHandoff, NothingToDoWithoutACollision) {
  const auto c = choose_handoff(straight(0, 0.5, 10), 1.0, std::nullopt, params());
  EXPECT_EQ(c.action, HandoffAction::kNone);
}

TEST(ChooseHandoff, ReplansFromLeadAheadWhenABrakeThereStillStopsInTime) {
  // v = 0.5: a brake lasts 1 s and comes to rest at the trajectory's point 0.5 s later.
  const Trajectory t = straight(0, 0.5, 10);
  const auto c = choose_handoff(t, 1.0, 3.5, params());
  EXPECT_EQ(c.action, HandoffAction::kReplan);
  EXPECT_NEAR(c.handoff_s, 2.5, 1e-12);
  EXPECT_NEAR(c.stop_s, 3.0, 1e-12);
  EXPECT_NE(c.reason.find("re-plan"), std::string::npos);
}

TEST(ChooseHandoff, BrakesAtOnceWhenWaitingForAPlanWouldReachTheObstacle) {
  const Trajectory t = straight(0, 0.5, 10);
  // The re-plan's brake would rest at t = 3.0 >= 2.9: brake now (+ latency).
  const auto c = choose_handoff(t, 1.0, 2.9, params());
  EXPECT_EQ(c.action, HandoffAction::kBrake);
  EXPECT_NEAR(c.handoff_s, 1.1, 1e-12);
  EXPECT_NEAR(c.stop_s, 1.6, 1e-12);
  EXPECT_NE(c.reason.find("braking"), std::string::npos);
}

TEST(ChooseHandoff, AHandoffPastTheEndStartsFromTheEnd) {
  const Trajectory t = straight(0, 0.5, 4);
  // Near the end the robot is at rest at t = 4 before the collision at 4.5 (a trajectory ends
  // where it ends; the collision time is past it only in this synthetic case).
  const auto c = choose_handoff(t, 3.0, 4.5, params());
  EXPECT_EQ(c.action, HandoffAction::kReplan);
  EXPECT_NEAR(c.handoff_s, 4.0, 1e-12);
}

TEST(MapAge, FreshOldAndFuture) {
  const std::int64_t now = 1'000'000'000;
  EXPECT_EQ(map_age_problem(now - 1'000'000, now, 2.0), "");
  const std::string old = map_age_problem(now - 3'200'000, now, 2.0);
  EXPECT_NE(old.find("3.20 s old"), std::string::npos) << old;
  EXPECT_NE(old.find("limit 2.00 s"), std::string::npos) << old;
  EXPECT_NE(map_age_problem(now + 5'000'000, now, 2.0).find("future"), std::string::npos);
}

class FirstCollision : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scene_ = new Scene(testing::empty_scene());
    planner_ = testing::make_planner(*scene_).release();
    ASSERT_TRUE(planner_->set_map(voxelize(*scene_)).ok);
    pipeline::PlanRequest r;
    r.start = pipeline::StartState::at_rest(scene_->start);
    r.goal = pipeline::GoalSpec::exact(scene_->goal);
    const auto result = planner_->plan(r);
    ASSERT_TRUE(result.success()) << result.message;
    trajectory_ = new Trajectory(*result.trajectory);
  }
  static void TearDownTestSuite() {
    delete planner_;
    delete trajectory_;
    delete scene_;
  }
  /// Slow reference: every 1 ms from t_from, the first colliding configuration.
  static std::optional<double> reference(const planner::KernelCollisionChecker& c, double t_from) {
    for (double t = t_from; t <= trajectory_->total_duration_s(); t += 1e-3)
      if (c.check(configuration_at(*trajectory_, t)).in_collision) return t;
    return std::nullopt;
  }
  static Scene* scene_;
  static pipeline::Planner* planner_;
  static Trajectory* trajectory_;
};
Scene* FirstCollision::scene_ = nullptr;
pipeline::Planner* FirstCollision::planner_ = nullptr;
Trajectory* FirstCollision::trajectory_ = nullptr;

TEST_F(FirstCollision, NoneOnTheMapItWasPlannedOn) {
  EXPECT_FALSE(first_collision_s(planner_->kernel_checker(), *trajectory_, 0.0, 0.02).has_value());
}

TEST_F(FirstCollision, MatchesDenseSamplingForWallsAtSeveralPlaces) {
  const OccupancyGrid open = voxelize(*scene_);
  planner::KernelCollisionChecker checker(planner_->kernel_checker().robot());
  for (double x_wall : {2.0, 4.5, 7.0}) {
    checker.set_map(testing::with_box(open, x_wall, x_wall + 0.2, -3.0, 3.0));
    for (double t_from : {0.0, 0.3 * trajectory_->total_duration_s()}) {
      const auto ref = reference(checker, t_from);
      const auto got = first_collision_s(checker, *trajectory_, t_from, 0.02);
      ASSERT_EQ(ref.has_value(), got.has_value()) << "wall at " << x_wall << " from " << t_from;
      if (!ref) continue;
      EXPECT_GE(*got, t_from);
      EXPECT_LE(*got, *ref + 0.02 + 1e-9) << "wall at " << x_wall;
      EXPECT_GE(*got, *ref - 0.02 - 1e-9) << "wall at " << x_wall;
    }
  }
}

TEST_F(FirstCollision, AnObstacleBehindTheRobotIsNotAhead) {
  planner::KernelCollisionChecker checker(planner_->kernel_checker().robot());
  checker.set_map(testing::with_box(voxelize(*scene_), 3.0, 3.2, -3.0, 3.0));
  const auto hit = first_collision_s(checker, *trajectory_, 0.0, 0.02);
  ASSERT_TRUE(hit.has_value());
  // Past the wall (plus the body's length), nothing is ahead.
  double t_past = *hit;
  while (t_past < trajectory_->total_duration_s() && trajectory_->position(t_past)[0] < 3.2 + 1.8) t_past += 0.05;
  EXPECT_FALSE(first_collision_s(checker, *trajectory_, t_past, 0.02).has_value());
}

}  // namespace
}  // namespace porter::planner_daemon
