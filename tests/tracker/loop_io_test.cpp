// porter-tracker's hand-over between its threads (tracker/app/loop_io.hpp): the lock-free
// single-producer single-consumer ring (order, capacity, a two-thread run checked element by
// element) and apply_input, which must feed the Tracker exactly as the LCM callbacks did: in
// arrival order, an ESTOP acted on at the very next step, an e-stop engaged and released within
// one period leaving the tracker IDLE without a trajectory.

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <thread>
#include <vector>

#include "loop_io.hpp"
#include "trajectory_fixtures.hpp"

namespace porter::tracker_app {
namespace {

constexpr std::int64_t kT0 = 1'700'000'000'000'000;
constexpr std::int64_t kPeriod = 10'000;

tracker::TrackerParams params() {
  tracker::TrackerParams p;
  p.base_limits = test::scout_limits();
  p.joint_velocity_max_radps = JointVector::Constant(1.0);
  return p;
}

tracker::MeasuredState valid_state() {
  tracker::MeasuredState s;
  s.pose_valid = s.base_valid = s.arm_valid = true;
  s.num_joints = kNumArmJoints;
  return s;
}

TrajectoryInput trajectory_input(std::int64_t plan_id, std::int64_t start, std::int64_t received) {
  return {{test::straight(0.4, 2.0, +1), start, start, plan_id, "world"}, received};
}

TEST(SpscRing, FillsToCapacityInOrderAndRefusesWhenFull) {
  EXPECT_THROW(SpscRing<int>(0), std::invalid_argument);
  SpscRing<int> ring(3);
  EXPECT_EQ(ring.front(), nullptr);
  for (int i = 0; i < 3; ++i) {
    int* slot = ring.slot_to_fill();
    ASSERT_NE(slot, nullptr);
    *slot = i;
    ring.push_filled();
  }
  EXPECT_EQ(ring.slot_to_fill(), nullptr);  // full
  ASSERT_NE(ring.front(), nullptr);
  EXPECT_EQ(*ring.front(), 0);
  ring.pop();
  int* slot = ring.slot_to_fill();  // one slot free again (the wrap-around)
  ASSERT_NE(slot, nullptr);
  *slot = 3;
  ring.push_filled();
  for (int expected = 1; expected <= 3; ++expected) {
    ASSERT_NE(ring.front(), nullptr);
    EXPECT_EQ(*ring.front(), expected);
    ring.pop();
  }
  EXPECT_EQ(ring.front(), nullptr);
}

// One producer and one consumer thread: every element arrives once, in order, intact (each
// element is a vector whose contents depend on its sequence number, so a slot read while being
// written would show).
TEST(SpscRing, TwoThreadsPassEveryElementInOrder) {
  constexpr std::uint64_t kCount = 200'000;
  SpscRing<std::vector<std::uint64_t>> ring(8);
  std::thread producer([&] {
    std::mt19937 rng(7);
    for (std::uint64_t i = 0; i < kCount; ++i) {
      std::vector<std::uint64_t>* slot = nullptr;
      while ((slot = ring.slot_to_fill()) == nullptr) std::this_thread::yield();
      slot->assign(1 + rng() % 5, i);
      ring.push_filled();
    }
  });
  std::uint64_t next = 0, mismatches = 0;
  while (next < kCount) {
    std::vector<std::uint64_t>* e = ring.front();
    if (e == nullptr) {
      std::this_thread::yield();
      continue;
    }
    if (e->empty() || e->size() > 5) ++mismatches;
    for (std::uint64_t v : *e) mismatches += v != next;
    ring.pop();
    ++next;
  }
  producer.join();
  EXPECT_EQ(mismatches, 0u);
  EXPECT_EQ(ring.front(), nullptr);
}

TEST(ApplyInput, EstopIsActedOnAtTheNextStep) {
  tracker::Tracker tracker(params());
  std::vector<LogLine> log;
  std::int64_t now = kT0;
  InputEvent state = StateInput{valid_state(), now};
  apply_input(tracker, state, log);
  InputEvent traj = trajectory_input(1, now, now);
  apply_input(tracker, traj, log);
  ASSERT_EQ(log.size(), 1u);
  EXPECT_EQ(log[0].level, runtime::LogLevel::info);
  EXPECT_NE(log[0].text.find("plan 1 accepted: "), std::string::npos) << log[0].text;
  EXPECT_EQ(tracker.step(now).state, tracker::TrackerState::tracking);

  now += kPeriod;
  log.clear();
  InputEvent estop = EstopInput{true, "operator", "bumper", now - 1000};
  InputEvent fresh = StateInput{valid_state(), now - 500};
  apply_input(tracker, estop, log);
  apply_input(tracker, fresh, log);
  const auto& out = tracker.step(now);
  EXPECT_EQ(out.state, tracker::TrackerState::estop);
  EXPECT_FALSE(out.base_enabled);
  EXPECT_FALSE(out.arm_enabled);
  ASSERT_EQ(log.size(), 1u);
  EXPECT_EQ(log[0].level, runtime::LogLevel::warn);
  EXPECT_EQ(log[0].text, "ESTOP engaged by operator (bumper)");

  // A second ESTOP while latched is not logged again; a trajectory is refused (logged).
  log.clear();
  now += kPeriod;
  InputEvent again = EstopInput{true, "operator", "", now};
  InputEvent refused = trajectory_input(2, now, now);
  apply_input(tracker, again, log);
  apply_input(tracker, refused, log);
  ASSERT_EQ(log.size(), 1u);
  EXPECT_NE(log[0].text.find("plan 2 refused: e-stop engaged"), std::string::npos) << log[0].text;
}

// Engaged and released between two steps (both events drained in one period): the e-stop never
// shows as a state, but its release still drops the trajectory, as with one callback each.
TEST(ApplyInput, EventsOfOnePeriodApplyInArrivalOrder) {
  tracker::Tracker tracker(params());
  std::vector<LogLine> log;
  std::int64_t now = kT0;
  std::vector<InputEvent> events;
  events.emplace_back(StateInput{valid_state(), now});
  events.emplace_back(trajectory_input(1, now, now));
  for (auto& e : events) apply_input(tracker, e, log);
  EXPECT_EQ(tracker.step(now).state, tracker::TrackerState::tracking);

  now += kPeriod;
  events.clear();
  log.clear();
  events.emplace_back(EstopInput{true, "operator", "", now - 2000});
  events.emplace_back(EstopInput{false, "operator", "", now - 1000});
  events.emplace_back(StateInput{valid_state(), now - 500});
  for (auto& e : events) apply_input(tracker, e, log);
  const auto& out = tracker.step(now);
  EXPECT_EQ(out.state, tracker::TrackerState::idle);
  EXPECT_FALSE(tracker.has_trajectory());
  ASSERT_EQ(log.size(), 2u);
  EXPECT_EQ(log[0].text, "ESTOP engaged by operator");
  EXPECT_EQ(log[1].text, "ESTOP released by operator");

  // The same two in the other order: the release comes first (nothing latched), then the
  // e-stop latches.
  now += kPeriod;
  events.clear();
  log.clear();
  events.emplace_back(EstopInput{false, "operator", "", now - 2000});
  events.emplace_back(EstopInput{true, "operator", "", now - 1000});
  for (auto& e : events) apply_input(tracker, e, log);
  EXPECT_EQ(tracker.step(now).state, tracker::TrackerState::estop);
  ASSERT_EQ(log.size(), 1u);
  EXPECT_EQ(log[0].text, "ESTOP engaged by operator");
}

TEST(ApplyInput, InvalidTrajectoryAndNothingEvents) {
  tracker::Tracker tracker(params());
  std::vector<LogLine> log;
  InputEvent nothing;  // std::monostate: a drained slot
  apply_input(tracker, nothing, log);
  EXPECT_TRUE(log.empty());
  InputEvent bad = InvalidTrajectoryInput{7, "dimension 3, expected 8"};
  apply_input(tracker, bad, log);
  ASSERT_EQ(log.size(), 1u);
  EXPECT_EQ(log[0].level, runtime::LogLevel::warn);
  EXPECT_EQ(log[0].text, tracker.last_refusal());
  EXPECT_NE(log[0].text.find("dimension 3, expected 8"), std::string::npos) << log[0].text;
  EXPECT_FALSE(tracker.has_trajectory());
  EXPECT_FALSE(tracker.has_pending());
}

TEST(StateChangeLine, LevelFollowsTheState) {
  tracker::TrackerOutput out;
  out.state = tracker::TrackerState::tracking;
  out.plan_id = 4;
  EXPECT_EQ(state_change_line(out).level, runtime::LogLevel::info);
  EXPECT_EQ(state_change_line(out).text, "state TRACKING (plan 4)");
  out.state = tracker::TrackerState::stale_state;
  out.message = "no ROBOT_STATE for 0.100 s";
  EXPECT_EQ(state_change_line(out).level, runtime::LogLevel::warn);
  EXPECT_EQ(state_change_line(out).text, "state STALE_STATE: no ROBOT_STATE for 0.100 s (plan 4)");
}

}  // namespace
}  // namespace porter::tracker_app
