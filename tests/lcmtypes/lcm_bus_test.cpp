// porter::LcmBus over the in-process memq:// provider: typed delivery, channel separation,
// unsubscribe, and failures counted instead of thrown or printed.

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "porter/lcm_bus.hpp"

namespace porter {
namespace {

robot_state_t make_state(double x_m) {
  robot_state_t s{};
  s.utime = 1'000'000 + static_cast<std::int64_t>(x_m * 1000);
  s.frame_id = "world";
  s.x_m = x_m;
  s.y_m = -x_m;
  s.yaw_rad = 0.25;
  s.num_joints = 6;
  s.q_rad = {0.1, 0.2, 0.3, 0.4, 0.5, 0.6};
  s.qd_radps = {1, 2, 3, 4, 5, 6};
  s.pose_source = robot_state_t::POSE_SIM_TRUTH;
  s.base_valid = true;
  return s;
}

can_frame_t make_frame(const std::string& bus, int id, std::vector<std::uint8_t> data) {
  can_frame_t f{};
  f.utime = 5;
  f.bus = bus;
  f.sender = "test";
  f.id = id;
  f.dlc = static_cast<std::int8_t>(data.size());
  f.data = std::move(data);
  return f;
}

TEST(LcmBus, PublishedMessageArrivesTyped) {
  LcmBus bus("memq://");
  ASSERT_TRUE(bus.good());
  std::vector<robot_state_t> received;
  const auto id = bus.subscribe(channels::kRobotState,
                                [&](const robot_state_t& s) { received.push_back(s); });
  EXPECT_NE(id, 0u);
  ASSERT_TRUE(bus.publish(channels::kRobotState, make_state(1.5)));
  ASSERT_TRUE(bus.publish(channels::kRobotState, make_state(2.5)));
  EXPECT_EQ(bus.handle_pending(), 2);
  ASSERT_EQ(received.size(), 2u);
  EXPECT_EQ(received[0].x_m, 1.5);
  EXPECT_EQ(received[1].x_m, 2.5);
  EXPECT_EQ(received[1].y_m, -2.5);
  EXPECT_EQ(received[1].q_rad, make_state(2.5).q_rad);
  EXPECT_EQ(received[1].frame_id, "world");
  EXPECT_EQ(bus.decode_failures(), 0u);
  EXPECT_EQ(bus.handle_pending(), 0) << "nothing left";
}

TEST(LcmBus, ChannelsOfTheSameTypeStaySeparate) {
  LcmBus bus("memq://");
  std::vector<can_frame_t> base_frames, arm_frames;
  bus.subscribe(channels::kCanBase, [&](const can_frame_t& f) { base_frames.push_back(f); });
  bus.subscribe(channels::kCanArm, [&](const can_frame_t& f) { arm_frames.push_back(f); });
  ASSERT_TRUE(bus.publish(channels::kCanArm, make_frame("arm", 0x155, {1, 2, 3, 4, 5, 6, 7, 8})));
  ASSERT_TRUE(bus.publish(channels::kCanBase, make_frame("base", 0x111, {0, 0x96})));
  ASSERT_TRUE(bus.publish(channels::kCanArm, make_frame("arm", 0x156, {9})));
  bus.handle_pending();
  ASSERT_EQ(base_frames.size(), 1u);
  ASSERT_EQ(arm_frames.size(), 2u);
  EXPECT_EQ(base_frames[0].id, 0x111);
  EXPECT_EQ(arm_frames[0].id, 0x155);
  EXPECT_EQ(arm_frames[1].id, 0x156);
  EXPECT_EQ(arm_frames[1].data, std::vector<std::uint8_t>{9});
}

TEST(LcmBus, EmptyArrayAfterFullOneIsEmpty) {
  // lcm-gen 1.3.1 skips resizing a vector whose count is 0; each message must start fresh.
  LcmBus bus("memq://");
  std::vector<can_frame_t> frames;
  bus.subscribe(channels::kCanBase, [&](const can_frame_t& f) { frames.push_back(f); });
  bus.publish(channels::kCanBase, make_frame("base", 0x111, {1, 2, 3, 4, 5, 6, 7, 8}));
  bus.publish(channels::kCanBase, make_frame("base", 0x421, {}));
  bus.handle_pending();
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_EQ(frames[0].data.size(), 8u);
  EXPECT_EQ(frames[1].dlc, 0);
  EXPECT_TRUE(frames[1].data.empty());
}

TEST(LcmBus, EverySubscriberReceivesAndUnsubscribeStopsDelivery) {
  LcmBus bus("memq://");
  int first = 0, second = 0;
  const auto id1 = bus.subscribe(channels::kEstop, [&](const estop_t&) { ++first; });
  const auto id2 = bus.subscribe(channels::kEstop, [&](const estop_t&) { ++second; });
  EXPECT_NE(id1, id2);
  estop_t stop{};
  stop.active = true;
  stop.source = "test";
  bus.publish(channels::kEstop, stop);
  bus.handle_pending();
  EXPECT_EQ(first, 1);
  EXPECT_EQ(second, 1);
  EXPECT_TRUE(bus.unsubscribe(id1));
  EXPECT_FALSE(bus.unsubscribe(id1)) << "already removed";
  EXPECT_FALSE(bus.unsubscribe(0));
  bus.publish(channels::kEstop, stop);
  bus.handle_pending();
  EXPECT_EQ(first, 1);
  EXPECT_EQ(second, 2);
}

TEST(LcmBus, WrongTypeOnAChannelIsCountedNotDelivered) {
  LcmBus bus("memq://");
  int delivered = 0;
  bus.subscribe(channels::kRobotState, [&](const robot_state_t&) { ++delivered; });
  // Simulate a misbehaving publisher that bypasses the typed API.
  base_cmd_t wrong{};
  wrong.source = "rogue";
  ASSERT_EQ(bus.lcm().publish(std::string(channels::kRobotState.name()), &wrong), 0);
  const std::uint8_t garbage[3] = {1, 2, 3};
  ASSERT_EQ(bus.lcm().publish(std::string(channels::kRobotState.name()), garbage, 3), 0);
  bus.handle_pending();
  EXPECT_EQ(delivered, 0);
  EXPECT_EQ(bus.decode_failures(), 2u);
  EXPECT_NE(bus.last_error().find("robot_state_t"), std::string::npos) << bus.last_error();
  // The bus keeps working.
  bus.publish(channels::kRobotState, make_state(0.5));
  bus.handle_pending();
  EXPECT_EQ(delivered, 1);
}

TEST(LcmBus, ThrowingCallbackIsCountedAndTheBusContinues) {
  LcmBus bus("memq://");
  int calls = 0;
  bus.subscribe(channels::kHeartbeat, [&](const process_heartbeat_t& hb) {
    ++calls;
    if (hb.pid == 13) throw std::runtime_error("unlucky pid");
  });
  process_heartbeat_t hb{};
  hb.process = "porter-test";
  hb.pid = 13;
  bus.publish(channels::kHeartbeat, hb);
  hb.pid = 14;
  bus.publish(channels::kHeartbeat, hb);
  EXPECT_EQ(bus.handle_pending(), 2);
  EXPECT_EQ(calls, 2);
  EXPECT_EQ(bus.callback_failures(), 1u);
  EXPECT_NE(bus.last_error().find("unlucky pid"), std::string::npos) << bus.last_error();
}

TEST(LcmBus, HandleTimeoutReturnsZeroWhenIdle) {
  LcmBus bus("memq://");
  bus.subscribe(channels::kRobotState, [](const robot_state_t&) {});
  EXPECT_EQ(bus.handle_timeout(1), 0);
  EXPECT_GE(bus.fileno(), 0);
}

TEST(LcmBus, BorrowedInstanceWorks) {
  lcm::LCM lcm("memq://");
  ASSERT_TRUE(lcm.good());
  LcmBus bus(lcm);
  int got = 0;
  bus.subscribe(channels::kBaseCmd, [&](const base_cmd_t& c) { got += c.v_mps > 0 ? 1 : 0; });
  base_cmd_t cmd{};
  cmd.v_mps = 0.3;
  bus.publish(channels::kBaseCmd, cmd);
  EXPECT_EQ(bus.handle_pending(), 1);
  EXPECT_EQ(got, 1);
}

TEST(LcmBus, BadUrlGivesABusThatFailsQuietly) {
  LcmBus bus("nosuchprovider://");
  EXPECT_FALSE(bus.good());
  EXPECT_FALSE(bus.publish(channels::kEstop, estop_t{}));
  EXPECT_EQ(bus.subscribe(channels::kEstop, [](const estop_t&) {}), 0u);
  EXPECT_LT(bus.handle_timeout(0), 0);
  EXPECT_EQ(bus.handle_pending(), -1);
  EXPECT_EQ(bus.fileno(), -1);
}

}  // namespace
}  // namespace porter
