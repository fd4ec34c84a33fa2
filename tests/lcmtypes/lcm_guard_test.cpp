// The LCM guard (porter/lcm_guard.hpp): its generated schema agrees with lcm-gen's layout for
// every type, it accepts what lcm-gen encodes, and it refuses the datagrams that crash or
// overread the generated decoders; through porter::LcmBus a refused datagram is counted and
// dropped and the bus goes on.

#include <gtest/gtest.h>

#include <climits>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "porter/lcm_bus.hpp"
#include "porter/lcm_guard.hpp"
#include "schema_encoder.hpp"

// Every generated type, for PORTER_LCM_FOR_EACH_TYPE.
#include "porter/arm_cmd_t.hpp"
#include "porter/arm_state_t.hpp"
#include "porter/base_cmd_t.hpp"
#include "porter/base_state_t.hpp"
#include "porter/can_frame_t.hpp"
#include "porter/estop_t.hpp"
#include "porter/imu_t.hpp"
#include "porter/minco_trajectory_t.hpp"
#include "porter/octomap_t.hpp"
#include "porter/payload_t.hpp"
#include "porter/plan_goal_t.hpp"
#include "porter/planner_status_t.hpp"
#include "porter/point_cloud_t.hpp"
#include "porter/pose_t.hpp"
#include "porter/process_heartbeat_t.hpp"
#include "porter/robot_state_t.hpp"
#include "porter/sim_command_t.hpp"
#include "porter/tracker_status_t.hpp"

namespace porter {
namespace {

using Bytes = std::vector<std::uint8_t>;

template <class T>
Bytes encode(const T& msg) {
  Bytes buf(static_cast<std::size_t>(msg.getEncodedSize()));
  EXPECT_EQ(msg.encode(buf.data(), 0, static_cast<int>(buf.size())), static_cast<int>(buf.size()));
  return buf;
}

void put_be32(Bytes& b, std::size_t at, std::int32_t v) {
  const auto u = static_cast<std::uint32_t>(v);
  for (int i = 0; i < 4; ++i) b[at + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(u >> (24 - 8 * i));
}

// Random messages encoded from the schema alone decode with lcm-gen to exactly their size and
// re-encode to the same bytes: the schema is the generated layout. The guard accepts them, and
// refuses every strict prefix and every extension by one byte.
template <class T>
void check_schema_matches_generated_code(std::mt19937_64& rng) {
  const LcmSchema& schema = LcmSchemaOf<T>::kSchema;
  EXPECT_EQ(std::string(schema.type_name), std::string("porter.") + T::getTypeName());
  for (int trial = 0; trial < 200; ++trial) {
    const Bytes bytes = test::encode_random(schema, T::getHash(), rng);
    SCOPED_TRACE(std::string(T::getTypeName()) + " trial " + std::to_string(trial));
    const LcmGuardResult g = lcm_guard_check<T>(bytes.data(), bytes.size());
    ASSERT_TRUE(g.ok) << g.describe();
    T msg;
    ASSERT_EQ(msg.decode(bytes.data(), 0, static_cast<int>(bytes.size())), static_cast<int>(bytes.size()));
    EXPECT_EQ(encode(msg), bytes);
    if (trial < 10) {
      for (std::size_t cut = 0; cut < bytes.size(); ++cut)
        EXPECT_FALSE(lcm_guard_check<T>(bytes.data(), cut).ok) << "prefix of " << cut << " bytes";
      Bytes longer = bytes;
      longer.push_back(0);
      EXPECT_FALSE(lcm_guard_check<T>(longer.data(), longer.size()).ok);
    }
  }
}

TEST(LcmGuard, SchemaOfEveryTypeMatchesTheGeneratedCode) {
  std::mt19937_64 rng(25);
#define PORTER_CHECK_TYPE(T) check_schema_matches_generated_code<T>(rng);
  PORTER_LCM_FOR_EACH_TYPE(PORTER_CHECK_TYPE)
#undef PORTER_CHECK_TYPE
}

// Mutated datagrams: whatever the guard accepts, lcm-gen decodes to exactly its size.
template <class T>
void check_mutations(std::mt19937_64& rng) {
  const LcmSchema& schema = LcmSchemaOf<T>::kSchema;
  for (int trial = 0; trial < 300; ++trial) {
    Bytes bytes = test::encode_random(schema, T::getHash(), rng);
    const int edits = 1 + static_cast<int>(rng() % 3);
    for (int e = 0; e < edits && bytes.size() > 8; ++e) {
      const std::size_t at = 8 + rng() % (bytes.size() - 8);
      if (rng() % 2 == 0) {
        bytes[at] = static_cast<std::uint8_t>(rng());
      } else if (at + 4 <= bytes.size()) {
        put_be32(bytes, at, static_cast<std::int32_t>(rng()));
      }
    }
    if (!lcm_guard_check<T>(bytes.data(), bytes.size()).ok) continue;
    T msg;
    EXPECT_EQ(msg.decode(bytes.data(), 0, static_cast<int>(bytes.size())), static_cast<int>(bytes.size()))
        << T::getTypeName() << " trial " << trial;
  }
}

TEST(LcmGuard, WhatTheGuardAcceptsDecodesToItsSize) {
  std::mt19937_64 rng(2025);
#define PORTER_CHECK_TYPE(T) check_mutations<T>(rng);
  PORTER_LCM_FOR_EACH_TYPE(PORTER_CHECK_TYPE)
#undef PORTER_CHECK_TYPE
}

// The 40-byte ESTOP datagram whose string length is INT32_MIN: the generated decoder passes its
// `len > maxlen - pos` check and std::string::assign reads ~2 GiB past the buffer.
Bytes estop_with_source_length(std::int32_t length) {
  estop_t stop{};
  stop.utime = 1;
  stop.active = true;
  stop.source = "operator12345";  // 13 characters: a 40-byte datagram
  stop.reason = "";
  Bytes b = encode(stop);
  put_be32(b, 8 + 8 + 1, length);  // hash, utime, active, then the length of `source`
  return b;
}

TEST(LcmGuard, RefusesStringLengthsTheDatagramCannotHold) {
  for (const std::int32_t length : {INT32_MIN, -1, 0, 1000, INT32_MAX}) {
    const Bytes b = estop_with_source_length(length);
    const LcmGuardResult g = lcm_guard_check<estop_t>(b.data(), b.size());
    EXPECT_FALSE(g.ok) << length;
    EXPECT_STREQ(g.field, "source");
    EXPECT_EQ(g.value, length);
    EXPECT_NE(g.describe().find("string length"), std::string::npos) << g.describe();
  }
  EXPECT_EQ(estop_with_source_length(INT32_MIN).size(), 40u) << "the datagram of the report";
  EXPECT_TRUE(lcm_guard_check<estop_t>(estop_with_source_length(14).data(), 40).ok) << "the true length";
}

// An array count of 2^29 doubles: 8 * 2^29 overflows the decoder's int size check to 0 and it
// reads 4 GiB past the buffer; a negative count asks vector::resize for 2^64 elements.
TEST(LcmGuard, RefusesArrayCountsTheDatagramCannotHold) {
  robot_state_t s{};
  s.frame_id = "world";
  s.num_joints = 2;
  s.q_rad = {0.1, 0.2};
  s.qd_radps = {0.0, 0.0};
  const Bytes good = encode(s);
  ASSERT_TRUE(lcm_guard_check<robot_state_t>(good.data(), good.size()).ok);
  // num_joints follows hash, utime, frame_id and five doubles.
  const std::size_t at = 8 + 8 + 4 + 6 + 5 * 8;
  for (const std::int32_t count : {1 << 29, -1, INT32_MIN, 1 << 20}) {
    Bytes bad = good;
    put_be32(bad, at, count);
    const LcmGuardResult g = lcm_guard_check<robot_state_t>(bad.data(), bad.size());
    EXPECT_FALSE(g.ok) << count;
    EXPECT_STREQ(g.field, "q_rad") << g.describe();
    EXPECT_EQ(g.value, count);
  }
  // The int8 count of can_frame_t.data: -1 would be 2^64 - 1 bytes for resize.
  can_frame_t f{};
  f.bus = "base";
  f.sender = "x";
  f.dlc = 2;
  f.data = {1, 2};
  Bytes frame = encode(f);
  frame[frame.size() - 3] = 0xFF;
  EXPECT_FALSE(lcm_guard_check<can_frame_t>(frame.data(), frame.size()).ok);
}

TEST(LcmGuard, RefusesAnotherTypeAndShortDatagrams) {
  base_cmd_t cmd{};
  cmd.source = "x";
  const Bytes b = encode(cmd);
  EXPECT_FALSE(lcm_guard_check<estop_t>(b.data(), b.size()).ok);
  EXPECT_FALSE(lcm_guard_check<estop_t>(nullptr, 0).ok);
  EXPECT_FALSE(lcm_guard_check<estop_t>(b.data(), 7).ok);
}

TEST(LcmGuard, BusCountsAndDropsAHostileDatagramAndGoesOn) {
  LcmBus bus("memq://");
  ASSERT_TRUE(bus.good());
  std::vector<estop_t> received;
  bus.subscribe(channels::kEstop, [&](const estop_t& e) { received.push_back(e); });
  const Bytes hostile = estop_with_source_length(INT32_MIN);
  const std::string channel(channels::kEstop.name());
  ASSERT_EQ(bus.lcm().publish(channel, hostile.data(), static_cast<unsigned>(hostile.size())), 0);
  EXPECT_EQ(bus.handle_pending(), 1);
  EXPECT_TRUE(received.empty());
  EXPECT_EQ(bus.decode_failures(), 1u);
  EXPECT_NE(bus.last_error().find("'source'"), std::string::npos) << bus.last_error();
  EXPECT_NE(bus.last_error().find(channel), std::string::npos) << bus.last_error();

  estop_t stop{};
  stop.active = true;
  stop.source = "operator";
  stop.reason = "test";
  ASSERT_TRUE(bus.publish(channels::kEstop, stop));
  EXPECT_EQ(bus.handle_pending(), 1);
  ASSERT_EQ(received.size(), 1u);
  EXPECT_EQ(received[0].source, "operator");
  EXPECT_EQ(bus.decode_failures(), 1u);
}

// The HEARTBEAT reports drops of every bus in the process (an lcm: CAN bus owns its own LcmBus),
// including buses that are gone.
TEST(LcmGuard, ProcessCountSumsEveryBus) {
  const std::uint64_t before = LcmBus::process_decode_failures();
  const Bytes hostile = estop_with_source_length(INT32_MIN);
  const std::string channel(channels::kEstop.name());
  LcmBus kept("memq://");
  kept.subscribe(channels::kEstop, [](const estop_t&) {});
  {
    LcmBus gone("memq://");
    gone.subscribe(channels::kEstop, [](const estop_t&) {});
    for (int i = 0; i < 2; ++i)
      ASSERT_EQ(gone.lcm().publish(channel, hostile.data(), static_cast<unsigned>(hostile.size())), 0);
    EXPECT_EQ(gone.handle_pending(), 2);
    EXPECT_EQ(gone.decode_failures(), 2u);
  }
  ASSERT_EQ(kept.lcm().publish(channel, hostile.data(), 7), 0);  // shorter than a fingerprint
  EXPECT_EQ(kept.handle_pending(), 1);
  EXPECT_EQ(kept.decode_failures(), 1u);
  EXPECT_EQ(LcmBus::process_decode_failures() - before, 3u);
}

}  // namespace
}  // namespace porter
