// SocketCAN: controller error frames in words (pure, runs everywhere); opening fails with a
// message naming the missing kernel support where PF_CAN is absent; frames cross a vcan
// interface where the kernel has one (skipped otherwise, with the reason).
#include <gtest/gtest.h>

#include <linux/can.h>
#include <linux/can/error.h>

#include "porter/can/can_error.hpp"
#include "porter/can/can_transport.hpp"
#include "porter/can/socketcan_bus.hpp"

namespace porter::can {
namespace {

CanFrame error_frame(std::uint32_t classes, std::initializer_list<std::uint8_t> bytes) {
  CanFrame f;
  f.id = classes;
  f.extended = true;
  for (std::uint8_t b : bytes) f.data[f.dlc++] = b;
  return f;
}

TEST(CanErrorFrame, BusOffAndRestart) {
  const ControllerError e = decode_error_frame(error_frame(CAN_ERR_BUSOFF, {0, 0, 0, 0, 0, 0, 0, 0}));
  EXPECT_TRUE(e.bus_off);
  EXPECT_EQ(e.text, "bus-off");
  const ControllerError r = decode_error_frame(error_frame(CAN_ERR_RESTARTED, {}));
  EXPECT_TRUE(r.restarted);
  EXPECT_FALSE(r.bus_off);
}

TEST(CanErrorFrame, ControllerStateProtocolAndCounters) {
  const ControllerError e = decode_error_frame(error_frame(
      CAN_ERR_CRTL | CAN_ERR_PROT | CAN_ERR_CNT | CAN_ERR_ACK,
      {0, CAN_ERR_CRTL_TX_PASSIVE | CAN_ERR_CRTL_RX_OVERFLOW, CAN_ERR_PROT_STUFF | CAN_ERR_PROT_TX,
       CAN_ERR_PROT_LOC_ACK, 0, 0, 130, 7}));
  EXPECT_TRUE(e.error_passive);
  EXPECT_TRUE(e.overflow);
  EXPECT_TRUE(e.no_ack);
  EXPECT_EQ(e.tx_error_count, 130);
  EXPECT_EQ(e.rx_error_count, 7);
  EXPECT_NE(e.text.find("stuff error, during transmission at ACK"), std::string::npos) << e.text;
  EXPECT_NE(e.text.find("error passive"), std::string::npos) << e.text;
  EXPECT_NE(e.text.find("error counters tx 130 rx 7"), std::string::npos) << e.text;
}

TEST(CanErrorFrame, ShortFramesReadNothingPastTheirDlc) {
  CanFrame f = error_frame(CAN_ERR_CNT | CAN_ERR_LOSTARB, {5});
  f.data[6] = 99;  // beyond dlc: must be ignored
  const ControllerError e = decode_error_frame(f);
  EXPECT_EQ(e.tx_error_count, 0);
  EXPECT_NE(e.text.find("lost arbitration at bit 5"), std::string::npos) << e.text;
  EXPECT_EQ(decode_error_frame(error_frame(0, {})).text, "unspecified controller error");
}

TEST(SocketCan, OpeningNamesTheMissingKernelSupportOrTheMissingInterface) {
  std::string reason;
  const bool supported = socketcan_supported(reason);
  auto bus = open_can_bus("socketcan:porter_nope0", "t");
  EXPECT_FALSE(bus->is_open());
  if (!supported) {
    EXPECT_NE(reason.find("no SocketCAN support"), std::string::npos) << reason;
    EXPECT_NE(bus->last_error().find("this kernel has no SocketCAN support"), std::string::npos)
        << bus->last_error();
    EXPECT_NE(bus->last_error().find("modprobe can_raw"), std::string::npos);
  } else {
    EXPECT_NE(bus->last_error().find("no network interface 'porter_nope0'"), std::string::npos)
        << bus->last_error();
  }
  EXPECT_EQ(bus->describe(), "socketcan:porter_nope0");
  CanFrame f;
  EXPECT_EQ(bus->send(f), CanStatus::closed);
  EXPECT_EQ(bus->receive(f, 0), CanStatus::closed);
  EXPECT_FALSE(open_can_bus("socketcan:" + std::string(40, 'x'), "t")->is_open());
}

TEST(SocketCan, FramesCrossAVcanInterface) {
  std::string reason;
  if (!socketcan_supported(reason)) GTEST_SKIP() << reason;
  auto a = SocketCanBus::open("vcan0");
  if (!a->is_open()) GTEST_SKIP() << "no vcan0 interface: " << a->last_error();
  auto b = SocketCanBus::open("vcan0");
  ASSERT_TRUE(b->is_open()) << b->last_error();
  CanFrame f;
  f.id = 0x111;
  f.dlc = 2;
  f.data[1] = 0x96;
  ASSERT_EQ(a->send(f), CanStatus::ok) << a->last_error();
  CanFrame got;
  ASSERT_EQ(b->receive(got, 1000), CanStatus::ok) << b->last_error();
  EXPECT_EQ(got, f);
  EXPECT_GT(got.utime, 0);  // kernel receive timestamp
  f.id = 0x1ABCDEF0;
  f.extended = true;
  ASSERT_EQ(a->send(f), CanStatus::ok);
  ASSERT_EQ(b->receive(got, 1000), CanStatus::ok);
  EXPECT_EQ(got, f);
}

}  // namespace
}  // namespace porter::can
