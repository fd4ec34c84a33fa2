#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

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

TEST(Heartbeat, CarriesTheDatagramsTheGuardDropped) {
  LcmBus bus("memq://");
  ASSERT_TRUE(bus.good());
  std::vector<porter::process_heartbeat_t> got;
  bus.subscribe(channels::kHeartbeat, [&](const porter::process_heartbeat_t& m) { got.push_back(m); });
  // A datagram on HEARTBEAT that is 4 bytes short of an int64: refused by the guard.
  porter::process_heartbeat_t cut{};
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(cut.getEncodedSize()));
  ASSERT_EQ(cut.encode(bytes.data(), 0, static_cast<int>(bytes.size())), static_cast<int>(bytes.size()));
  const std::string channel(channels::kHeartbeat.name());
  ASSERT_EQ(bus.lcm().publish(channel, bytes.data(), static_cast<unsigned>(bytes.size() - 4)), 0);
  EXPECT_EQ(bus.handle_pending(), 1);
  ASSERT_EQ(bus.decode_failures(), 1u);

  Heartbeat heartbeat(bus, "porter-test", 3600.0);
  ASSERT_TRUE(heartbeat.update(HeartbeatHealth::ok, ""));
  bus.handle_pending();
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].dropped_datagrams, static_cast<std::int64_t>(LcmBus::process_decode_failures()));
  EXPECT_GE(got[0].dropped_datagrams, 1);
}

}  // namespace
}  // namespace porter::runtime
