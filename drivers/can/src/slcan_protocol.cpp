#include "porter/can/slcan_protocol.hpp"

namespace porter::can::slcan {
namespace {

constexpr char kHex[] = "0123456789ABCDEF";
constexpr char kCr = '\r';
constexpr char kLf = '\n';
constexpr char kBel = '\a';

int hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return -1;
}

// Reads `digits` hex digits at `at`; false on a non-hex character.
bool read_hex(std::string_view s, std::size_t at, std::size_t digits, std::uint32_t& value) {
  value = 0;
  for (std::size_t i = 0; i < digits; ++i) {
    const int v = hex_value(s[at + i]);
    if (v < 0) return false;
    value = (value << 4) | static_cast<std::uint32_t>(v);
  }
  return true;
}

Item malformed(std::string_view line, const char* why) {
  Item item;
  item.kind = ItemKind::malformed;
  item.text = std::string(why) + ": '" + std::string(line.substr(0, kMaxLineLength)) + "'";
  return item;
}

Item parse_frame_line(std::string_view line) {
  const char kind = line[0];
  const bool extended = kind == 'T' || kind == 'R';
  const bool rtr = kind == 'r' || kind == 'R';
  const std::size_t id_digits = extended ? 8 : 3;
  if (line.size() < 1 + id_digits + 1) return malformed(line, "frame line too short");
  std::uint32_t id = 0;
  if (!read_hex(line, 1, id_digits, id)) return malformed(line, "bad hex in the ID");
  if (id > (extended ? 0x1FFFFFFFu : 0x7FFu)) return malformed(line, "ID out of range");
  const int dlc = hex_value(line[1 + id_digits]);
  if (dlc < 0 || dlc > 8) return malformed(line, "DLC is not 0..8");
  const std::size_t data_at = 2 + id_digits;
  const std::size_t data_chars = rtr ? 0 : 2 * static_cast<std::size_t>(dlc);
  const std::size_t rest = line.size() - data_at;
  // Exactly the data, or the data and a 4-digit timestamp.
  if (rest != data_chars && rest != data_chars + 4) {
    return malformed(line, "length does not match the DLC");
  }
  Item item;
  item.kind = ItemKind::frame;
  item.frame.id = id;
  item.frame.extended = extended;
  item.frame.rtr = rtr;
  item.frame.dlc = static_cast<std::uint8_t>(dlc);
  for (std::size_t i = 0; i < data_chars / 2; ++i) {
    std::uint32_t byte = 0;
    if (!read_hex(line, data_at + 2 * i, 2, byte)) return malformed(line, "bad hex in the data");
    item.frame.data[i] = static_cast<std::uint8_t>(byte);
  }
  if (rest == data_chars + 4) {
    std::uint32_t stamp = 0;
    if (!read_hex(line, data_at + data_chars, 4, stamp)) {
      return malformed(line, "bad hex in the timestamp");
    }
  }
  return item;
}

}  // namespace

int bitrate_code(std::uint32_t bitrate) {
  switch (bitrate) {
    case 10000: return 0;
    case 20000: return 1;
    case 50000: return 2;
    case 100000: return 3;
    case 125000: return 4;
    case 250000: return 5;
    case 500000: return 6;
    case 800000: return 7;
    case 1000000: return 8;
    default: return -1;
  }
}

std::string bitrate_command(std::uint32_t bitrate) {
  const int code = bitrate_code(bitrate);
  if (code < 0) return {};
  return std::string("S") + static_cast<char>('0' + code) + kCr;
}

std::string encode_frame(const CanFrame& frame) {
  if (!frame.valid()) return {};
  std::string line;
  line.reserve(kMaxLineLength + 1);
  line += frame.extended ? (frame.rtr ? 'R' : 'T') : (frame.rtr ? 'r' : 't');
  const int digits = frame.extended ? 8 : 3;
  for (int i = digits - 1; i >= 0; --i) line += kHex[(frame.id >> (4 * i)) & 0xF];
  line += kHex[frame.dlc];
  if (!frame.rtr) {
    for (int i = 0; i < frame.dlc; ++i) {
      line += kHex[frame.data[i] >> 4];
      line += kHex[frame.data[i] & 0xF];
    }
  }
  line += kCr;
  return line;
}

const char* to_string(ItemKind kind) {
  switch (kind) {
    case ItemKind::frame: return "frame";
    case ItemKind::ack: return "ack";
    case ItemKind::tx_ack: return "tx_ack";
    case ItemKind::refused: return "refused";
    case ItemKind::text: return "text";
    case ItemKind::malformed: return "malformed";
  }
  return "unknown";
}

Item parse_line(std::string_view line) {
  Item item;
  if (line.empty()) return item;  // ack
  switch (line[0]) {
    case 't':
    case 'T':
    case 'r':
    case 'R':
      return parse_frame_line(line);
    case 'z':
    case 'Z':
      if (line.size() == 1) {
        item.kind = ItemKind::tx_ack;
        return item;
      }
      break;
    default:
      break;
  }
  for (char c : line) {
    if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) > 0x7E) {
      return malformed(line, "non-printable character in a reply");
    }
  }
  item.kind = ItemKind::text;
  item.text = std::string(line);
  return item;
}

void SlcanDecoder::feed(const std::uint8_t* data, std::size_t size, std::vector<Item>& out) {
  for (std::size_t i = 0; i < size; ++i) {
    const char c = static_cast<char>(data[i]);
    if (c == kBel) {
      // A refusal ends whatever was being received (adapters send it alone).
      if (!line_.empty() || overflow_) out.push_back(malformed(line_, "line cut by BEL"));
      line_.clear();
      overflow_ = false;
      last_was_cr_ = false;
      Item item;
      item.kind = ItemKind::refused;
      out.push_back(item);
      continue;
    }
    if (c == kCr || c == kLf) {
      const bool lf_after_cr = c == kLf && last_was_cr_;
      last_was_cr_ = c == kCr;
      if (overflow_) {
        out.push_back(malformed(line_, "line longer than any SLCAN reply"));
      } else if (!line_.empty()) {
        out.push_back(parse_line(line_));
      } else if (!lf_after_cr && c == kCr) {
        out.push_back(Item{});  // CR alone: ack
      }
      line_.clear();
      overflow_ = false;
      continue;
    }
    last_was_cr_ = false;
    if (overflow_) continue;
    if (line_.size() >= kMaxLineLength) {
      overflow_ = true;
      continue;
    }
    line_ += c;
  }
}

void SlcanDecoder::reset() {
  line_.clear();
  overflow_ = false;
  last_was_cr_ = false;
}

}  // namespace porter::can::slcan
