#include <thread>

#include <gtest/gtest.h>

#include "porter/can/memory_bus.hpp"

namespace porter::can {
namespace {

CanFrame make(std::uint32_t id, std::uint8_t first) {
  CanFrame f;
  f.id = id;
  f.dlc = 2;
  f.data[0] = first;
  f.data[1] = 0xAB;
  return f;
}

TEST(MemoryBus, EveryOtherNodeReceivesInOrderAndTheSenderDoesNot) {
  auto a = MemoryBus::open("t_order");
  auto b = MemoryBus::open("t_order");
  auto c = MemoryBus::open("t_order");
  auto other = MemoryBus::open("t_other_bus");
  ASSERT_EQ(a->send(make(0x111, 1)), CanStatus::ok);
  ASSERT_EQ(a->send(make(0x112, 2)), CanStatus::ok);
  for (auto* node : {b.get(), c.get()}) {
    CanFrame f;
    ASSERT_EQ(node->receive(f, 0), CanStatus::ok);
    EXPECT_EQ(f, make(0x111, 1));
    ASSERT_EQ(node->receive(f, 0), CanStatus::ok);
    EXPECT_EQ(f, make(0x112, 2));
    EXPECT_EQ(node->receive(f, 0), CanStatus::timeout);
  }
  CanFrame f;
  EXPECT_EQ(a->receive(f, 0), CanStatus::timeout);
  EXPECT_EQ(other->receive(f, 0), CanStatus::timeout);
  EXPECT_EQ(a->describe(), "memory:t_order");
}

TEST(MemoryBus, RejectsInvalidFrames) {
  auto a = MemoryBus::open("t_invalid");
  CanFrame f = make(0x800, 0);  // 12 bits in a standard frame
  EXPECT_EQ(a->send(f), CanStatus::invalid_frame);
  f.id = 0x7FF;
  f.dlc = 9;
  EXPECT_EQ(a->send(f), CanStatus::invalid_frame);
  f.dlc = 8;
  f.extended = true;
  f.id = 0x1FFFFFFF;
  EXPECT_EQ(a->send(f), CanStatus::ok);
}

TEST(MemoryBus, FullQueueDropsOldestAndCounts) {
  auto a = MemoryBus::open("t_full");
  auto b = MemoryBus::open("t_full", 3);
  for (std::uint8_t i = 0; i < 5; ++i) ASSERT_EQ(a->send(make(0x100, i)), CanStatus::ok);
  EXPECT_EQ(b->dropped(), 2u);
  CanFrame f;
  ASSERT_EQ(b->receive(f, 0), CanStatus::ok);
  EXPECT_EQ(f.data[0], 2);
}

TEST(MemoryBus, DisconnectedNodeNeitherSendsNorReceives) {
  auto a = MemoryBus::open("t_disc");
  auto b = MemoryBus::open("t_disc");
  b->disconnect();
  EXPECT_FALSE(b->is_open());
  EXPECT_EQ(b->send(make(0x1, 0)), CanStatus::io_error);
  EXPECT_FALSE(b->last_error().empty());
  ASSERT_EQ(a->send(make(0x2, 0)), CanStatus::ok);
  CanFrame f;
  EXPECT_EQ(b->receive(f, 0), CanStatus::timeout);
  b->reconnect();
  ASSERT_EQ(a->send(make(0x3, 0)), CanStatus::ok);
  ASSERT_EQ(b->receive(f, 0), CanStatus::ok);
  EXPECT_EQ(f.id, 0x3u);
}

TEST(MemoryBus, BlockingReceiveWakesOnSend) {
  auto a = MemoryBus::open("t_wake");
  auto b = MemoryBus::open("t_wake");
  std::thread sender([&] { a->send(make(0x321, 7)); });
  CanFrame f;
  EXPECT_EQ(b->receive(f, -1), CanStatus::ok);
  EXPECT_EQ(f.id, 0x321u);
  sender.join();
}

}  // namespace
}  // namespace porter::can
