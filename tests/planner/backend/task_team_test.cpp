// TaskTeam: every participant runs each task exactly once, the caller as participant 0, and run()
// returns only after all have finished; many short phases in a row (the safety term's pattern),
// a team of one, and destruction with helpers asleep.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

#include "porter/backend/task_team.hpp"

namespace porter::backend {
namespace {

TEST(TaskTeam, EveryParticipantRunsEachTaskOnceAndRunWaitsForAll) {
  TaskTeam team(3);
  ASSERT_EQ(team.size(), 3);
  std::vector<std::atomic<int>> calls(3);
  std::vector<std::thread::id> ids(3);
  for (int phase = 0; phase < 2000; ++phase) {
    std::vector<int> done(3, 0);
    team.run([&](int i) {
      calls[static_cast<std::size_t>(i)].fetch_add(1);
      ids[static_cast<std::size_t>(i)] = std::this_thread::get_id();
      done[static_cast<std::size_t>(i)] = phase + 1;  // each slot written by its own participant
    });
    for (int i = 0; i < 3; ++i) ASSERT_EQ(done[static_cast<std::size_t>(i)], phase + 1) << "phase " << phase;
  }
  for (int i = 0; i < 3; ++i) EXPECT_EQ(calls[static_cast<std::size_t>(i)].load(), 2000);
  EXPECT_EQ(ids[0], std::this_thread::get_id());
  EXPECT_NE(ids[1], ids[0]);
  EXPECT_NE(ids[2], ids[1]);
}

TEST(TaskTeam, SlowHelperIsWaitedFor) {
  TaskTeam team(2, 0);  // no spinning: helpers sleep between phases
  std::atomic<int> finished{0};
  team.run([&](int i) {
    if (i == 1) std::this_thread::sleep_for(std::chrono::milliseconds(20));
    finished.fetch_add(1);
  });
  EXPECT_EQ(finished.load(), 2);
}

TEST(TaskTeam, TeamOfOneRunsOnTheCaller) {
  TaskTeam team(1);
  EXPECT_EQ(team.size(), 1);
  std::thread::id id;
  team.run([&](int i) {
    EXPECT_EQ(i, 0);
    id = std::this_thread::get_id();
  });
  EXPECT_EQ(id, std::this_thread::get_id());
  TaskTeam zero(0);
  EXPECT_EQ(zero.size(), 1);
}

TEST(TaskTeam, DestroyedWhileHelpersSleep) {
  std::atomic<int> calls{0};
  for (int k = 0; k < 20; ++k) {
    TaskTeam team(2, 0);
    team.run([&](int) { calls.fetch_add(1); });
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }  // the destructor wakes and joins them (a hang here is the failure)
  EXPECT_EQ(calls.load(), 40);
}

}  // namespace
}  // namespace porter::backend
