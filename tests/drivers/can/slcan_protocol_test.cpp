// SLCAN (LAWICEL) lines: encoding every frame kind, parsing adapter replies, reassembling lines
// split across reads, and refusing malformed input.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "porter/can/slcan_protocol.hpp"

namespace porter::can::slcan {
namespace {

CanFrame frame(std::uint32_t id, std::initializer_list<std::uint8_t> bytes, bool extended = false) {
  CanFrame f;
  f.id = id;
  f.extended = extended;
  for (std::uint8_t b : bytes) f.data[f.dlc++] = b;
  return f;
}

std::vector<Item> feed(SlcanDecoder& d, const std::string& bytes) {
  std::vector<Item> out;
  d.feed(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(), out);
  return out;
}

TEST(SlcanProtocol, BitrateCodesFollowLawicel) {
  EXPECT_EQ(bitrate_code(10000), 0);
  EXPECT_EQ(bitrate_code(125000), 4);
  EXPECT_EQ(bitrate_code(500000), 6);
  EXPECT_EQ(bitrate_code(1000000), 8);
  EXPECT_EQ(bitrate_code(83333), -1);
  EXPECT_EQ(bitrate_command(500000), "S6\r");
  EXPECT_EQ(bitrate_command(1000000), "S8\r");
  EXPECT_EQ(bitrate_command(12345), "");
}

TEST(SlcanProtocol, EncodesEveryFrameKind) {
  EXPECT_EQ(encode_frame(frame(0x111, {0x00, 0x96, 0, 0, 0, 0, 0, 0})), "t11180096000000000000\r");
  EXPECT_EQ(encode_frame(frame(0x421, {0x01})), "t421101\r");
  EXPECT_EQ(encode_frame(frame(0x7FF, {})), "t7FF0\r");
  EXPECT_EQ(encode_frame(frame(0x18FEF100, {0xAB, 0xcd}, true)), "T18FEF1002ABCD\r");
  CanFrame remote = frame(0x123, {});
  remote.rtr = true;
  remote.dlc = 4;
  EXPECT_EQ(encode_frame(remote), "r1234\r");
  remote.extended = true;
  EXPECT_EQ(encode_frame(remote), "R000001234\r");
  CanFrame bad = frame(0x800, {});  // 12-bit ID in a standard frame
  EXPECT_EQ(encode_frame(bad), "");
}

TEST(SlcanProtocol, ParsesFramesAndRoundTrips) {
  const CanFrame f = frame(0x2A5, {0x01, 0x02, 0xFE, 0xff});
  const Item item = parse_line("t2A540102FEff");
  ASSERT_EQ(item.kind, ItemKind::frame) << item.text;
  EXPECT_EQ(item.frame, f);
  for (const CanFrame& g : {frame(0x0, {}), frame(0x1FFFFFFF, {1, 2, 3, 4, 5, 6, 7, 8}, true),
                            frame(0x311, {0x80, 0, 0, 1, 0xFF, 0xFF, 0xFF, 0xFE})}) {
    std::string line = encode_frame(g);
    line.pop_back();  // CR
    const Item back = parse_line(line);
    ASSERT_EQ(back.kind, ItemKind::frame) << line;
    EXPECT_EQ(back.frame, g) << line;
  }
}

TEST(SlcanProtocol, AcceptsAnAdapterTimestampSuffix) {
  const Item item = parse_line("t1112AABB1F3C");
  ASSERT_EQ(item.kind, ItemKind::frame) << item.text;
  EXPECT_EQ(item.frame, frame(0x111, {0xAA, 0xBB}));
}

TEST(SlcanProtocol, RepliesAreClassified) {
  EXPECT_EQ(parse_line("").kind, ItemKind::ack);
  EXPECT_EQ(parse_line("z").kind, ItemKind::tx_ack);
  EXPECT_EQ(parse_line("Z").kind, ItemKind::tx_ack);
  const Item version = parse_line("V1013");
  EXPECT_EQ(version.kind, ItemKind::text);
  EXPECT_EQ(version.text, "V1013");
}

TEST(SlcanProtocol, MalformedFrameLinesAreRefusedWithAReason) {
  for (const char* line : {"t11", "t1G180", "t1119", "t1112001", "t111200112", "T1FFFFFFF0x",
                           "T200000000", "t11120011223", "t8000"}) {
    const Item item = parse_line(line);
    EXPECT_EQ(item.kind, ItemKind::malformed) << line;
    EXPECT_FALSE(item.text.empty());
  }
  EXPECT_EQ(parse_line(std::string("V\x01", 2)).kind, ItemKind::malformed);
}

TEST(SlcanDecoderTest, ReassemblesLinesSplitAcrossReads) {
  SlcanDecoder d;
  const std::string line = "t11180096000000000000\r";
  std::vector<Item> all;
  for (char c : line) {
    const auto items = feed(d, std::string(1, c));
    all.insert(all.end(), items.begin(), items.end());
  }
  ASSERT_EQ(all.size(), 1u);
  EXPECT_EQ(all[0].kind, ItemKind::frame);
  EXPECT_EQ(all[0].frame, frame(0x111, {0x00, 0x96, 0, 0, 0, 0, 0, 0}));
  EXPECT_EQ(d.pending(), 0u);
  // Half a line, then the rest with the next reply in the same read.
  EXPECT_TRUE(feed(d, "t2A1").empty());
  EXPECT_EQ(d.pending(), 4u);
  const auto items = feed(d, "1FF\rz\r\r");
  ASSERT_EQ(items.size(), 3u);
  EXPECT_EQ(items[0].frame, frame(0x2A1, {0xFF}));
  EXPECT_EQ(items[1].kind, ItemKind::tx_ack);
  EXPECT_EQ(items[2].kind, ItemKind::ack);
}

TEST(SlcanDecoderTest, BelIsARefusalEvenInsideALine) {
  SlcanDecoder d;
  auto items = feed(d, "\a");
  ASSERT_EQ(items.size(), 1u);
  EXPECT_EQ(items[0].kind, ItemKind::refused);
  items = feed(d, "t11\a");
  ASSERT_EQ(items.size(), 2u);
  EXPECT_EQ(items[0].kind, ItemKind::malformed);
  EXPECT_EQ(items[1].kind, ItemKind::refused);
  EXPECT_EQ(d.pending(), 0u);
}

TEST(SlcanDecoderTest, CrLfEndsOneLineNotTwo) {
  SlcanDecoder d;
  const auto items = feed(d, "t1110\r\nV0101\r\n\r");
  ASSERT_EQ(items.size(), 3u);
  EXPECT_EQ(items[0].kind, ItemKind::frame);
  EXPECT_EQ(items[1].kind, ItemKind::text);
  EXPECT_EQ(items[2].kind, ItemKind::ack);
}

TEST(SlcanDecoderTest, OverlongLinesAreDroppedWithBoundedMemory) {
  SlcanDecoder d;
  const std::string junk(100000, 'A');
  EXPECT_TRUE(feed(d, junk).empty());
  EXPECT_LE(d.pending(), kMaxLineLength);
  auto items = feed(d, "\rt1110\r");
  ASSERT_EQ(items.size(), 2u);
  EXPECT_EQ(items[0].kind, ItemKind::malformed);
  EXPECT_EQ(items[1].kind, ItemKind::frame);
}

}  // namespace
}  // namespace porter::can::slcan
