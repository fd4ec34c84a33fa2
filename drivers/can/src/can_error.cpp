#include "porter/can/can_error.hpp"

#include <linux/can.h>
#include <linux/can/error.h>

namespace porter::can {
namespace {

void add(std::string& text, const std::string& part) {
  if (!text.empty()) text += "; ";
  text += part;
}

std::string protocol_type(std::uint8_t bits) {
  std::string s;
  auto flag = [&](std::uint8_t mask, const char* name) {
    if ((bits & mask) != 0) s += (s.empty() ? "" : ", ") + std::string(name);
  };
  flag(CAN_ERR_PROT_BIT, "bit error");
  flag(CAN_ERR_PROT_FORM, "form error");
  flag(CAN_ERR_PROT_STUFF, "stuff error");
  flag(CAN_ERR_PROT_BIT0, "cannot send dominant bit");
  flag(CAN_ERR_PROT_BIT1, "cannot send recessive bit");
  flag(CAN_ERR_PROT_OVERLOAD, "bus overload");
  flag(CAN_ERR_PROT_ACTIVE, "active error announcement");
  flag(CAN_ERR_PROT_TX, "during transmission");
  return s.empty() ? "unspecified" : s;
}

const char* protocol_location(std::uint8_t loc) {
  switch (loc) {
    case CAN_ERR_PROT_LOC_SOF: return "start of frame";
    case CAN_ERR_PROT_LOC_ID28_21:
    case CAN_ERR_PROT_LOC_ID20_18:
    case CAN_ERR_PROT_LOC_ID17_13:
    case CAN_ERR_PROT_LOC_ID12_05:
    case CAN_ERR_PROT_LOC_ID04_00: return "identifier";
    case CAN_ERR_PROT_LOC_SRTR:
    case CAN_ERR_PROT_LOC_RTR: return "RTR bit";
    case CAN_ERR_PROT_LOC_IDE: return "IDE bit";
    case CAN_ERR_PROT_LOC_RES0:
    case CAN_ERR_PROT_LOC_RES1: return "reserved bit";
    case CAN_ERR_PROT_LOC_DLC: return "DLC";
    case CAN_ERR_PROT_LOC_DATA: return "data";
    case CAN_ERR_PROT_LOC_CRC_SEQ:
    case CAN_ERR_PROT_LOC_CRC_DEL: return "CRC";
    case CAN_ERR_PROT_LOC_ACK:
    case CAN_ERR_PROT_LOC_ACK_DEL: return "ACK";
    case CAN_ERR_PROT_LOC_EOF: return "end of frame";
    case CAN_ERR_PROT_LOC_INTERM: return "intermission";
    default: return nullptr;
  }
}

}  // namespace

ControllerError decode_error_frame(const CanFrame& frame) {
  ControllerError e;
  std::uint8_t d[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  const int n = frame.dlc > 8 ? 8 : frame.dlc;
  for (int i = 0; i < n; ++i) d[i] = frame.data[i];
  e.classes = frame.id & CAN_ERR_MASK;
  const std::uint32_t c = e.classes;

  if (c & CAN_ERR_BUSOFF) {
    e.bus_off = true;
    add(e.text, "bus-off");
  }
  if (c & CAN_ERR_RESTARTED) {
    e.restarted = true;
    add(e.text, "controller restarted");
  }
  if (c & CAN_ERR_TX_TIMEOUT) add(e.text, "transmit timeout");
  if (c & CAN_ERR_ACK) {
    e.no_ack = true;
    add(e.text, "no ACK on transmission (is another node on the bus, at the same bitrate?)");
  }
  if (c & CAN_ERR_LOSTARB) {
    add(e.text, d[0] == CAN_ERR_LOSTARB_UNSPEC
                    ? std::string("lost arbitration")
                    : "lost arbitration at bit " + std::to_string(d[0]));
  }
  if (c & CAN_ERR_CRTL) {
    const std::uint8_t s = d[1];
    std::string part = "controller:";
    if (s & (CAN_ERR_CRTL_RX_OVERFLOW | CAN_ERR_CRTL_TX_OVERFLOW)) {
      e.overflow = true;
      if (s & CAN_ERR_CRTL_RX_OVERFLOW) part += " rx buffer overflow";
      if (s & CAN_ERR_CRTL_TX_OVERFLOW) part += " tx buffer overflow";
    }
    if (s & (CAN_ERR_CRTL_RX_WARNING | CAN_ERR_CRTL_TX_WARNING)) {
      e.warning = true;
      part += " error warning";
    }
    if (s & (CAN_ERR_CRTL_RX_PASSIVE | CAN_ERR_CRTL_TX_PASSIVE)) {
      e.error_passive = true;
      part += " error passive";
    }
    if (s & CAN_ERR_CRTL_ACTIVE) {
      e.back_to_active = true;
      part += " back to error active";
    }
    if (part == "controller:") part += " unspecified";
    add(e.text, part);
  }
  if (c & CAN_ERR_PROT) {
    std::string part = "protocol violation: " + protocol_type(d[2]);
    if (const char* where = protocol_location(d[3])) part += std::string(" at ") + where;
    add(e.text, part);
  }
  if (c & CAN_ERR_TRX) {
    add(e.text, d[4] == CAN_ERR_TRX_UNSPEC ? std::string("transceiver error")
                                           : "transceiver error (wiring code " +
                                                 std::to_string(d[4]) + ")");
  }
  if (c & CAN_ERR_BUSERROR) add(e.text, "bus error");
  if (c & CAN_ERR_CNT) {
    e.tx_error_count = d[6];
    e.rx_error_count = d[7];
    add(e.text, "error counters tx " + std::to_string(d[6]) + " rx " + std::to_string(d[7]));
  }
  if (e.text.empty()) e.text = "unspecified controller error";
  return e;
}

}  // namespace porter::can
