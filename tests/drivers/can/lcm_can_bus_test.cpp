// The LCM-carried CAN bus over a private udpm port: frames cross between endpoints, an endpoint
// skips its own frames, malformed messages are counted and dropped, bad specs fail clearly.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "porter/can/can_transport.hpp"
#include "porter/can/lcm_can_bus.hpp"
#include "porter/lcm_bus.hpp"
#include "private_lcm_url.hpp"

namespace porter::can {
namespace {

// A port no other process uses, so parallel runs (this suite's and other build trees') do not
// cross.
const std::string kUrl = test::private_lcm_url();

CanFrame frame(std::uint32_t id, std::initializer_list<std::uint8_t> bytes) {
  CanFrame f;
  f.id = id;
  for (std::uint8_t b : bytes) f.data[f.dlc++] = b;
  return f;
}

TEST(LcmCanBus, FramesCrossBetweenNodesAndSkipTheSender) {
  auto driver = open_can_bus("lcm:CAN_BASE@" + kUrl, "porter-base");
  auto firmware = open_can_bus("lcm:CAN_BASE@" + kUrl, "porter-sim");
  ASSERT_TRUE(driver->is_open()) << driver->last_error();
  ASSERT_TRUE(firmware->is_open()) << firmware->last_error();
  ASSERT_EQ(driver->send(frame(0x111, {0x00, 0x96, 0, 0, 0, 0, 0, 0})), CanStatus::ok);
  CanFrame got;
  ASSERT_EQ(firmware->receive(got, 2000), CanStatus::ok);
  EXPECT_EQ(got, frame(0x111, {0x00, 0x96, 0, 0, 0, 0, 0, 0}));
  EXPECT_NE(got.utime, 0);
  // The driver's own frame came back over multicast and was skipped.
  EXPECT_EQ(driver->receive(got, 100), CanStatus::timeout);
  ASSERT_EQ(firmware->send(frame(0x211, {0, 1})), CanStatus::ok);
  ASSERT_EQ(driver->receive(got, 2000), CanStatus::ok);
  EXPECT_EQ(got.id, 0x211u);
  EXPECT_EQ(got.dlc, 2);
}

TEST(LcmCanBus, MalformedMessagesAreCountedAndDropped) {
  LcmCanBus node(channels::kCanArm.info, kUrl, "porter-arm");
  ASSERT_TRUE(node.is_open());
  LcmBus raw(kUrl);
  porter::can_frame_t bad;  // LCM 1.3.1's generated types leave scalar fields uninitialised
  bad.utime = 0;
  bad.bus = "arm";
  bad.extended = false;
  bad.rtr = false;
  bad.sender = "intruder";
  bad.id = 0x155;
  bad.dlc = 3;
  bad.data = {1, 2, 3};
  bad.id = 0x900;  // too large for a standard ID
  ASSERT_TRUE(raw.publish(channels::kCanArm, bad));
  bad.id = 0x155;
  bad.extended = true;
  bad.id = -5;
  ASSERT_TRUE(raw.publish(channels::kCanArm, bad));
  bad.extended = false;
  bad.id = 0x2A5;
  ASSERT_TRUE(raw.publish(channels::kCanArm, bad));  // valid
  CanFrame got;
  ASSERT_EQ(node.receive(got, 2000), CanStatus::ok);
  EXPECT_EQ(got.id, 0x2A5u);
  EXPECT_EQ(node.malformed(), 2u);
}

TEST(LcmCanBus, PollSeesFramesWaitingBehindTheNodesOwnEchoes) {
  // Own port: this test's echoes must not reach the others.
  const std::string url = porter::test::private_lcm_url();
  auto driver = open_can_bus("lcm:CAN_ARM@" + url, "porter-arm");
  auto firmware = open_can_bus("lcm:CAN_ARM@" + url, "porter-sim");
  ASSERT_TRUE(driver->is_open() && firmware->is_open());
  for (int i = 0; i < 5; ++i) ASSERT_EQ(driver->send(frame(0x155, {1, 2, 3, 4, 5, 6, 7, 8})), CanStatus::ok);
  ASSERT_EQ(firmware->send(frame(0x2A1, {1})), CanStatus::ok);
  CanFrame got;
  ASSERT_EQ(firmware->receive(got, 2000), CanStatus::ok);  // all six are on the wire by now
  for (int i = 0; i < 4; ++i) ASSERT_EQ(firmware->receive(got, 2000), CanStatus::ok);
  // LCM moves datagrams from the socket to its queue on its own thread: give it time to.
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  // The driver's five echoes come first; one poll must still find the firmware's frame.
  ASSERT_EQ(driver->receive(got, 0), CanStatus::ok);
  EXPECT_EQ(got.id, 0x2A1u);
  EXPECT_EQ(driver->receive(got, 0), CanStatus::timeout);
}

TEST(CanTransport, BadSpecsGiveClosedBusesThatSayWhy) {
  for (const char* spec : {"", "can0", "bogus:x", "lcm:", "lcm:ROBOT_STATE", "lcm:NOPE"}) {
    auto bus = open_can_bus(spec, "t");
    EXPECT_FALSE(bus->is_open()) << spec;
    EXPECT_NE(bus->last_error().find('\''), std::string::npos) << bus->last_error();
    CanFrame f;
    EXPECT_EQ(bus->send(frame(1, {})), CanStatus::closed);
    EXPECT_EQ(bus->receive(f, 0), CanStatus::closed);
  }
  auto mem = open_can_bus("memory:spec_test", "t");
  EXPECT_TRUE(mem->is_open());
  EXPECT_EQ(mem->describe(), "memory:spec_test");
}

}  // namespace
}  // namespace porter::can
