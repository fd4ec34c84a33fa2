#include <gtest/gtest.h>

#include "porter/lcm_bus.hpp"
#include "porter/runtime/heartbeat.hpp"

namespace porter::runtime {
namespace {

TEST(Heartbeat, PublishesFirstThenOnlyWhenDueOrHealthChanges) {
  LcmBus bus("memq://");
  ASSERT_TRUE(bus.good());
  std::vector<porter::process_heartbeat_t> got;
  bus.subscribe(channels::kHeartbeat, [&](const porter::process_heartbeat_t& m) { got.push_back(m); });

  Heartbeat heartbeat(bus, "porter-test", 3600.0);
  EXPECT_TRUE(heartbeat.update(HeartbeatHealth::ok, "", 100.0, 2));
  EXPECT_FALSE(heartbeat.update(HeartbeatHealth::ok, ""));            // not due
  EXPECT_TRUE(heartbeat.update(HeartbeatHealth::error, "bus down"));  // health changed
  bus.handle_pending();
  ASSERT_EQ(got.size(), 2u);
  EXPECT_EQ(got[0].process, "porter-test");
  EXPECT_EQ(got[0].health, porter::process_heartbeat_t::HEALTH_OK);
  EXPECT_DOUBLE_EQ(got[0].loop_rate_hz, 100.0);
  EXPECT_EQ(got[0].loop_overruns, 2);
  EXPECT_GT(got[0].pid, 0);
  EXPECT_EQ(got[1].health, porter::process_heartbeat_t::HEALTH_ERROR);
  EXPECT_EQ(got[1].status, "bus down");
  EXPECT_EQ(heartbeat.published(), 2u);
}

}  // namespace
}  // namespace porter::runtime
