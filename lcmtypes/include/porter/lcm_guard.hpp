#pragma once
// A check of a datagram against a message type's wire layout, run before lcm-gen's decoder.
//
// The decoders lcm-gen 1.3.1 generates trust the lengths written in the bytes: a string length
// of 0 or INT32_MIN makes std::string::assign throw or read gigabytes past the datagram; an array
// count of 2^29 doubles overflows the decoder's int size check and reads 4 GiB past it; a
// negative count asks vector::resize for 2^64 elements. The guard walks the bytes once and
// accepts a datagram only when the hash is the type's, every string length is in
// [1, bytes left], every array count is in [0, bytes left / element size] (strings: each element
// checked in turn), and the last member ends exactly at the end of the datagram. A datagram it
// accepts decodes without reading past its end, with allocations bounded by its size.
//
//   const porter::LcmGuardResult g = porter::lcm_guard_check<porter::estop_t>(data, size);
//   if (!g.ok) log(g.describe());
//
// Thread-safety: reentrant. No allocation, no exception, except describe() (formats the reason).

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

#include "porter/lcm_guard_schema.hpp"
#include "porter/lcm_schema.hpp"

namespace porter {

struct LcmGuardResult {
  bool ok = true;
  const char* problem = "";  ///< what is wrong, e.g. "string length out of range"; "" when ok
  const char* field = "";    ///< member the problem was found at ("" for the whole datagram)
  std::int64_t value = 0;    ///< the offending length or count (or size) when there is one
  std::size_t offset = 0;    ///< byte offset in the datagram where the member starts
  std::size_t left = 0;      ///< bytes left at that offset

  /// e.g. "field 'source' at byte 17: string length -2147483648 outside [1, 23]".
  std::string describe() const {
    if (ok) return "ok";
    std::string s;
    if (*field != '\0') s += std::string("field '") + field + "' at byte " + std::to_string(offset) + ": ";
    s += problem;
    s += " (value " + std::to_string(value) + ", " + std::to_string(left) + " bytes left)";
    return s;
  }
};

namespace lcm_guard_detail {

inline std::size_t element_size(LcmKind kind) {
  switch (kind) {
    case LcmKind::kInt8:
    case LcmKind::kBoolean:
    case LcmKind::kByte: return 1;
    case LcmKind::kInt16: return 2;
    case LcmKind::kInt32:
    case LcmKind::kFloat: return 4;
    case LcmKind::kInt64:
    case LcmKind::kDouble: return 8;
    case LcmKind::kString: return 4;  // at least the length word
  }
  return 1;
}

inline bool is_integer(LcmKind kind) {
  return kind == LcmKind::kInt8 || kind == LcmKind::kInt16 || kind == LcmKind::kInt32 ||
         kind == LcmKind::kInt64;
}

inline std::int64_t read_signed(const std::uint8_t* p, std::size_t n) {
  std::uint64_t v = 0;
  for (std::size_t i = 0; i < n; ++i) v = (v << 8) | p[i];
  if (n < 8 && (v >> (8 * n - 1)) != 0) v |= ~std::uint64_t{0} << (8 * n);  // sign-extend
  std::int64_t out;
  std::memcpy(&out, &v, sizeof out);
  return out;
}

inline LcmGuardResult fail(const char* problem, const char* field, std::int64_t value,
                           std::size_t offset, std::size_t left) {
  LcmGuardResult r;
  r.ok = false;
  r.problem = problem;
  r.field = field;
  r.value = value;
  r.offset = offset;
  r.left = left;
  return r;
}

}  // namespace lcm_guard_detail

/// Checks `size` bytes at `data` as one encoded message of the type `schema` describes, whose
/// fingerprint is `hash` (T::getHash()).
inline LcmGuardResult lcm_guard_check(const LcmSchema& schema, std::int64_t hash, const void* data,
                                      std::size_t size) {
  using namespace lcm_guard_detail;
  constexpr int kMaxFields = 64;
  constexpr std::size_t kMaxDatagram = 0x7fffffff;  // lcm-gen decoders index with int
  const auto* bytes = static_cast<const std::uint8_t*>(data);
  if (size > kMaxDatagram)
    return fail("datagram larger than 2^31 - 1 bytes", "", static_cast<std::int64_t>(size), 0, size);
  if (schema.num_fields > kMaxFields || schema.num_fields < 0)
    return fail("message type has too many members for the guard", "", schema.num_fields, 0, size);
  if (size < 8 || bytes == nullptr)
    return fail("shorter than the 8-byte type fingerprint", "", static_cast<std::int64_t>(size), 0, size);
  if (read_signed(bytes, 8) != hash)
    return fail("fingerprint is not this type's", "", read_signed(bytes, 8), 0, size);

  std::int64_t values[kMaxFields] = {};  // integer members, for the arrays they count
  std::size_t pos = 8;
  for (int f = 0; f < schema.num_fields; ++f) {
    const LcmField& field = schema.fields[f];
    const std::size_t left = size - pos;
    std::int64_t count = 1;
    if (field.count_field >= 0) {
      if (field.count_field >= f || schema.fields[field.count_field].count_field >= 0 ||
          !is_integer(schema.fields[field.count_field].kind))
        return fail("array sized by a member that is not an earlier integer", field.name, 0, pos, left);
      count = values[field.count_field];
      if (count < 0) return fail("negative array count", field.name, count, pos, left);
    }
    if (field.kind == LcmKind::kString) {
      if (static_cast<std::uint64_t>(count) > left / 4)
        return fail("string array count exceeds the bytes left", field.name, count, pos, left);
      for (std::int64_t i = 0; i < count; ++i) {
        const std::size_t here = size - pos;
        if (here < 4) return fail("string length word cut off", field.name, 0, pos, here);
        const std::int64_t len = read_signed(bytes + pos, 4);
        if (len < 1 || static_cast<std::uint64_t>(len) > here - 4)
          return fail("string length outside [1, bytes left]", field.name, len, pos, here - 4);
        pos += 4 + static_cast<std::size_t>(len);
      }
      continue;
    }
    const std::size_t width = element_size(field.kind);
    if (static_cast<std::uint64_t>(count) > left / width)
      return fail(field.count_field >= 0 ? "array count exceeds the bytes left" : "message cut off",
                  field.name, count, pos, left);
    if (field.count_field < 0) {
      if (is_integer(field.kind)) values[f] = read_signed(bytes + pos, width);
    }
    pos += static_cast<std::size_t>(count) * width;
  }
  if (pos != size)
    return fail("bytes left over after the last member", "", static_cast<std::int64_t>(size - pos), pos,
                size - pos);
  return LcmGuardResult{};
}

/// The guard for a generated type T (needs LcmSchemaOf<T>, from porter/lcm_schema.hpp).
template <class T>
LcmGuardResult lcm_guard_check(const void* data, std::size_t size) {
  return lcm_guard_check(LcmSchemaOf<T>::kSchema, T::getHash(), data, size);
}

}  // namespace porter
