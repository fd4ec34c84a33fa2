#pragma once
// The two checksums of the Livox MID-360 Ethernet protocol (its "CRC Algorithm" table):
//   CRC-32  (poly 0x04C11DB7 reflected = 0xEDB88320, init 0xFFFFFFFF, final xor 0xFFFFFFFF,
//            reflected in and out; the zlib / Ethernet CRC, check value of "123456789" is
//            0xCBF43926): point and IMU packets (over timestamp + data) and command data.
//   CRC-16/CCITT-FALSE (poly 0x1021, init 0xFFFF, no final xor, not reflected; check value
//            0x29B1): the 18-byte header of command packets.
// Livox-SDK2 (sdk_core/comm/CRC) uses the same parameters for its command packets. The SDK does
// not check the CRC of point or IMU packets; that a real MID-360 fills the point-packet field
// with this CRC is stated by the protocol document and was not checked against a device.
//
// Thread-safety: pure functions over constant tables.

#include <cstddef>
#include <cstdint>

namespace porter::livox {

/// CRC-32 of `size` bytes. `crc` continues a previous call (pass the previous result).
std::uint32_t crc32(const std::uint8_t* data, std::size_t size, std::uint32_t crc = 0);

/// CRC-16/CCITT-FALSE of `size` bytes.
std::uint16_t crc16_ccitt_false(const std::uint8_t* data, std::size_t size);

}  // namespace porter::livox
