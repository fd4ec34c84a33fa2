// The pipeline's shared vocabulary (planner/common): the one status enum and its tokens, the
// deadline with its cancellation flag, the angle-wrapping helper.
#include <chrono>
#include <limits>
#include <cmath>
#include <set>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "porter/planner/angle.hpp"
#include "porter/planner/deadline.hpp"
#include "porter/planner/status.hpp"

namespace porter::planner {
namespace {

TEST(PlannerStatus, EveryValueHasItsOwnShortToken) {
  std::set<std::string> seen;
  for (int k = 0; k <= static_cast<int>(Status::kNotRun); ++k) {
    const std::string token = to_string(static_cast<Status>(k));
    EXPECT_NE(token, "unknown") << k;
    EXPECT_EQ(token.find(' '), std::string::npos) << token;
    EXPECT_TRUE(seen.insert(token).second) << token;
  }
  EXPECT_EQ(std::string(to_string(Status::kTimeout)), "timeout");
  EXPECT_TRUE(has_trajectory(Status::kTimeout));
  EXPECT_FALSE(has_trajectory(Status::kCanceled));
  EXPECT_FALSE(has_trajectory(Status::kSuccess));  // the front-end's success is a path
}

TEST(PlannerDeadline, ExpiresWithTimeOrCancellation) {
  EXPECT_TRUE(Deadline(0.0).expired());
  EXPECT_TRUE(Deadline(std::nan("")).expired());
  const Deadline long_one(60.0);
  EXPECT_FALSE(long_one.expired());
  EXPECT_GT(long_one.remaining_s(), 59.0);
  EXPECT_NEAR(long_one.budget_s(), 60.0, 1e-6);

  CancelFlag flag;
  const Deadline d(60.0, &flag);
  const Deadline part = d.within(30.0);
  EXPECT_FALSE(part.expired());
  std::thread other([&flag] { flag.request(); });  // another thread cancels
  other.join();
  EXPECT_TRUE(d.canceled());
  EXPECT_TRUE(d.expired());
  EXPECT_TRUE(part.expired());  // a stage's share sees its parent's flag
  EXPECT_EQ(part.remaining_s(), 0.0);
  flag.reset();
  EXPECT_FALSE(d.expired());
}

TEST(PlannerDeadline, AShareEndsNoLaterThanItsParent) {
  const Deadline parent(0.05);
  const Deadline share = parent.within(60.0);
  EXPECT_LE(share.remaining_s(), 0.05 + 1e-9);
  std::this_thread::sleep_for(std::chrono::milliseconds(60));
  EXPECT_TRUE(parent.expired());
  EXPECT_TRUE(share.expired());
  // from_now() keeps the end and restarts the clock.
  const Deadline later = Deadline(60.0).from_now();
  EXPECT_LT(later.elapsed_s(), 1.0);
}

TEST(PlannerDeadline, AHugeBudgetIsCappedNotExpired) {
  // 1e12 s (a budget given in ms where s were meant, or +inf for "no limit") must not overflow
  // the clock into a deadline that is already over.
  for (const double b : {1e9, 1e12, 1e300, std::numeric_limits<double>::infinity()}) {
    const Deadline d(b);
    EXPECT_FALSE(d.expired()) << b;
    EXPECT_NEAR(d.budget_s(), Deadline::kMaxBudgetS, 1.0) << b;
  }
  EXPECT_TRUE(Deadline(-1.0).expired());
}

TEST(PlannerAngle, WrapsToTheHalfOpenInterval) {
  constexpr double kPi = 3.14159265358979323846;
  EXPECT_DOUBLE_EQ(wrap_angle_rad(kPi), kPi);
  EXPECT_DOUBLE_EQ(wrap_angle_rad(-kPi), kPi);
  EXPECT_NEAR(wrap_angle_rad(3.0 * kPi / 2.0), -kPi / 2.0, 1e-15);
  EXPECT_NEAR(wrap_angle_rad(-7.0), -7.0 + 2.0 * kPi, 1e-15);
  EXPECT_NEAR(angle_difference_rad(3.1, -3.1), 6.2 - 2.0 * kPi, 1e-12);
  EXPECT_NEAR(angle_difference_rad(-3.1, 3.1), 2.0 * kPi - 6.2, 1e-12);
  EXPECT_TRUE(std::isnan(wrap_angle_rad(std::nan(""))));
  for (double a = -20.0; a < 20.0; a += 0.37) {
    const double w = wrap_angle_rad(a);
    EXPECT_GT(w, -kPi);
    EXPECT_LE(w, kPi);
    EXPECT_NEAR(std::remainder(w - a, 2.0 * kPi), 0.0, 1e-12);
  }
}

}  // namespace
}  // namespace porter::planner
