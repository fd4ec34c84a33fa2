#pragma once
// The serial-line CAN protocol (SLCAN, after LAWICEL's CAN232/CANUSB ASCII protocol) spoken by
// USB-CAN adapters that appear as serial ports (CANable, CANtact, USBtin, Lawicel). Pure: no
// file descriptors; SlcanBus (slcan_bus.hpp) moves the bytes.
//
// Host -> adapter commands, each ended by CR (0x0D):
//   Sn      bitrate n (S0 10k, S1 20k, S2 50k, S3 100k, S4 125k, S5 250k, S6 500k, S7 800k,
//           S8 1M)
//   O / C   open / close the CAN channel
//   tiiildd..      standard data frame: 3 hex ID digits, 1 DLC digit, 2 hex digits per byte
//   Tiiiiiiiildd.. extended data frame: 8 hex ID digits
//   riiil / Riiiiiiiil  remote frames (no data)
// Adapter -> host:
//   CR             command accepted; 'z' CR / 'Z' CR: t / T frame queued for transmission
//   BEL (0x07)     command refused (unknown command, bad bitrate, channel closed, buffer full)
//   t/T/r/R lines  received frames, optionally followed by a 4-hex-digit timestamp (ms, when the
//                  adapter's timestamps are on; ignored here, the host stamps frames itself)
//   other lines    replies to V (version), N (serial number), F (status flags)
// Hex digits are accepted in either case; encoders write upper case.
//
// SlcanDecoder never trusts its input: a line longer than any valid reply is discarded up to its
// terminator, bad hex or a DLC above 8 or a length that does not match the DLC makes a
// `malformed` item; memory is bounded by kMaxLineLength.
//
// Thread-safety: the free functions are reentrant; a decoder belongs to one thread.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "porter/can/can_frame.hpp"

namespace porter::can::slcan {

/// Longest valid adapter line: 'T' + 8 ID + 1 DLC + 16 data + 4 timestamp = 30 characters.
inline constexpr std::size_t kMaxLineLength = 30;

/// The Sn command digit for a CAN bitrate in bit/s, or -1 when the protocol has no code for it.
int bitrate_code(std::uint32_t bitrate);

/// "S6\r" for 500000; "" when bitrate_code() is -1.
std::string bitrate_command(std::uint32_t bitrate);

/// The command line (with its CR) that transmits `frame`; "" when !frame.valid().
std::string encode_frame(const CanFrame& frame);

/// What one adapter reply is.
enum class ItemKind {
  frame,      ///< a received frame (item.frame)
  ack,        ///< CR alone: the last command was accepted
  tx_ack,     ///< 'z' / 'Z': a transmit command was accepted
  refused,    ///< BEL: the last command was refused
  text,       ///< any other well-formed reply line (version, serial, status flags): item.text
  malformed,  ///< a frame line with bad hex, DLC or length, or an overlong line: item.text says why
};

const char* to_string(ItemKind kind);

struct Item {
  ItemKind kind = ItemKind::ack;
  CanFrame frame;     ///< valid when kind == frame (utime 0: the caller stamps it)
  std::string text;   ///< the line (text), or the reason (malformed)
};

/// Parses one line without its terminator. An empty line is an ack.
Item parse_line(std::string_view line);

/// Splits the adapter's byte stream into items. A reply may arrive in any number of pieces;
/// an item is produced when its terminator (CR, or LF, for adapters that send CR LF) or a BEL
/// arrives.
class SlcanDecoder {
 public:
  /// Appends the items completed by `data` to `out`.
  void feed(const std::uint8_t* data, std::size_t size, std::vector<Item>& out);
  /// Forgets a partial line (after reopening the port).
  void reset();
  /// Characters of the line being received.
  std::size_t pending() const { return line_.size(); }

 private:
  std::string line_;
  bool overflow_ = false;
  bool last_was_cr_ = false;
};

}  // namespace porter::can::slcan
