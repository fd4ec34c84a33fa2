// SlcanBus over a pseudo-terminal pair against a simulated LAWICEL adapter: the open sequence,
// refused and missing replies, frames both ways, lines split across reads, BEL during a run,
// a hang-up, and the close command.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "porter/can/can_transport.hpp"
#include "porter/can/slcan_bus.hpp"
#include "slcan_adapter_sim.hpp"

namespace porter::can {
namespace {

using test::SimulatedSlcanAdapter;

CanFrame frame(std::uint32_t id, std::initializer_list<std::uint8_t> bytes) {
  CanFrame f;
  f.id = id;
  for (std::uint8_t b : bytes) f.data[f.dlc++] = b;
  return f;
}

std::unique_ptr<SlcanBus> open_on(const SimulatedSlcanAdapter& adapter, std::uint32_t bitrate,
                                  int reply_timeout_ms = 500) {
  SlcanOptions options;
  options.device = adapter.path();
  options.bitrate = bitrate;
  options.reply_timeout_ms = reply_timeout_ms;
  return SlcanBus::open(options, "slcan:" + adapter.path() + "@" + std::to_string(bitrate));
}

TEST(SlcanBus, OpensWithCloseBitrateOpenAndClosesOnDestruction) {
  SimulatedSlcanAdapter adapter;
  ASSERT_FALSE(adapter.path().empty());
  {
    auto bus = open_on(adapter, 500000);
    ASSERT_TRUE(bus->is_open()) << bus->last_error();
    EXPECT_TRUE(adapter.channel_open());
    EXPECT_EQ(adapter.commands(), (std::vector<std::string>{"C", "S6", "O"}));
  }
  ASSERT_EQ(adapter.wait_commands(4, 2000), 4u);
  EXPECT_EQ(adapter.commands().back(), "C");
  EXPECT_FALSE(adapter.channel_open());
}

TEST(SlcanBus, ARefusedBitrateFailsNamingTheCommand) {
  SimulatedSlcanAdapter::Options options;
  options.refused_bitrates = {8};
  SimulatedSlcanAdapter adapter(options);
  auto bus = open_on(adapter, 1000000);
  EXPECT_FALSE(bus->is_open());
  EXPECT_NE(bus->last_error().find("refused the bitrate command 'S8'"), std::string::npos)
      << bus->last_error();
  CanFrame f;
  EXPECT_EQ(bus->send(frame(1, {})), CanStatus::closed);
  EXPECT_EQ(bus->receive(f, 0), CanStatus::closed);
}

TEST(SlcanBus, ASilentDeviceFailsWithATimeout) {
  SimulatedSlcanAdapter::Options options;
  options.silent = true;
  SimulatedSlcanAdapter adapter(options);
  auto bus = open_on(adapter, 500000, 100);
  EXPECT_FALSE(bus->is_open());
  EXPECT_NE(bus->last_error().find("no reply"), std::string::npos) << bus->last_error();
  EXPECT_NE(bus->last_error().find(adapter.path()), std::string::npos) << bus->last_error();
}

TEST(SlcanBus, MissingDeviceAndNonTtyFailClearly) {
  SlcanOptions options;
  options.device = "/nonexistent/ttyACM9";
  auto bus = SlcanBus::open(options, "slcan:/nonexistent/ttyACM9@500000");
  EXPECT_FALSE(bus->is_open());
  EXPECT_NE(bus->last_error().find("cannot open '/nonexistent/ttyACM9'"), std::string::npos);
  options.device = "/dev/null";
  bus = SlcanBus::open(options, "slcan:/dev/null@500000");
  EXPECT_FALSE(bus->is_open());
  EXPECT_NE(bus->last_error().find("not a serial port"), std::string::npos) << bus->last_error();
}

TEST(SlcanBus, SendsFramesAsLinesAndAcksAreConsumed) {
  SimulatedSlcanAdapter adapter;
  auto bus = open_on(adapter, 500000);
  ASSERT_TRUE(bus->is_open()) << bus->last_error();
  const CanFrame cmd = frame(0x111, {0x00, 0x96, 0, 0, 0, 0, 0, 0});
  ASSERT_EQ(bus->send(cmd), CanStatus::ok);
  ASSERT_EQ(bus->send(frame(0x421, {0x01})), CanStatus::ok);
  ASSERT_EQ(adapter.wait_transmitted(2, 2000), 2u);
  EXPECT_EQ(adapter.transmitted()[0], cmd);
  EXPECT_EQ(adapter.transmitted()[1], frame(0x421, {0x01}));
  // The 'z' acknowledgements are replies, not frames.
  CanFrame got;
  EXPECT_EQ(bus->receive(got, 100), CanStatus::timeout);
  EXPECT_EQ(bus->refused(), 0u);
}

TEST(SlcanBus, ReceivesFramesSplitAcrossReads) {
  SimulatedSlcanAdapter adapter;
  auto bus = open_on(adapter, 500000);
  ASSERT_TRUE(bus->is_open()) << bus->last_error();
  std::thread writer([&] {
    adapter.inject("t2218012C00C8000000", 5, 20);  // 0x221 in pieces, not yet terminated
    adapter.inject("00\rt3118000000010000000", 7, 10);
    adapter.inject("2\r");
  });
  CanFrame got;
  ASSERT_EQ(bus->receive(got, 3000), CanStatus::ok) << bus->last_error();
  EXPECT_EQ(got, frame(0x221, {0x01, 0x2C, 0x00, 0xC8, 0, 0, 0, 0}));
  EXPECT_GT(got.utime, 0);
  ASSERT_EQ(bus->receive(got, 3000), CanStatus::ok) << bus->last_error();
  EXPECT_EQ(got, frame(0x311, {0, 0, 0, 1, 0, 0, 0, 2}));
  writer.join();
}

TEST(SlcanBus, ARefusedFrameIsReportedOnceAndTheBusContinues) {
  SimulatedSlcanAdapter adapter;
  auto bus = open_on(adapter, 500000);
  ASSERT_TRUE(bus->is_open()) << bus->last_error();
  adapter.refuse_next_frame();
  ASSERT_EQ(bus->send(frame(0x111, {0, 0, 0, 0, 0, 0, 0, 0})), CanStatus::ok);
  CanFrame got;
  EXPECT_EQ(bus->receive(got, 2000), CanStatus::io_error);
  EXPECT_NE(bus->last_error().find("BEL"), std::string::npos) << bus->last_error();
  EXPECT_EQ(bus->refused(), 1u);
  adapter.inject("t2611000\r");  // a frame with a malformed line before it
  adapter.inject("t26120102\r");
  EXPECT_EQ(bus->receive(got, 2000), CanStatus::ok);
  EXPECT_EQ(got.id, 0x261u);
  EXPECT_EQ(bus->malformed(), 1u);
}

TEST(SlcanBus, AHangUpClosesTheBus) {
  SimulatedSlcanAdapter adapter;
  auto bus = open_on(adapter, 250000);
  ASSERT_TRUE(bus->is_open()) << bus->last_error();
  adapter.hang_up();
  CanFrame got;
  CanStatus status = CanStatus::timeout;
  for (int i = 0; i < 50 && status == CanStatus::timeout; ++i) status = bus->receive(got, 20);
  EXPECT_EQ(status, CanStatus::closed);
  EXPECT_FALSE(bus->is_open());
  EXPECT_NE(bus->last_error().find("hung up"), std::string::npos) << bus->last_error();
}

TEST(SlcanBus, OpenCanBusParsesTheSpec) {
  SimulatedSlcanAdapter adapter;
  auto bus = open_can_bus("slcan:" + adapter.path() + "@125000?baud=921600", "t");
  ASSERT_TRUE(bus->is_open()) << bus->last_error();
  EXPECT_EQ(adapter.commands()[1], "S4");
  for (const std::string spec : {"slcan:/dev/ttyACM0", "slcan:/dev/ttyACM0@12345",
                                 "slcan:/dev/ttyACM0@fast", "slcan:/dev/ttyACM0@500000?baud=7",
                                 "slcan:/dev/ttyACM0@500000?parity=even", "slcan:@500000"}) {
    auto failed = open_can_bus(spec, "t");
    EXPECT_FALSE(failed->is_open()) << spec;
    EXPECT_NE(failed->last_error().find(spec), std::string::npos) << failed->last_error();
  }
}

}  // namespace
}  // namespace porter::can
