#pragma once
// Test support: encodes random messages straight from a guard schema (porter/lcm_schema.hpp),
// without the generated code, so tests can check the schema against lcm-gen's decoder (a
// schema that disagrees with the generated layout decodes to a different size or re-encodes to
// different bytes). Counts are 0..max_count, strings are printable ASCII without NUL, booleans
// are 0 or 1 (what lcm-gen's encoder writes back), numbers are random bits.

#include <cstdint>
#include <random>
#include <vector>

#include "porter/lcm_guard_schema.hpp"

namespace porter::test {

inline void put_be(std::vector<std::uint8_t>& out, std::uint64_t v, int width) {
  for (int i = width - 1; i >= 0; --i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}

inline std::vector<std::uint8_t> encode_random(const LcmSchema& schema, std::int64_t hash,
                                               std::mt19937_64& rng, int max_count = 5) {
  std::vector<std::uint8_t> out;
  put_be(out, static_cast<std::uint64_t>(hash), 8);
  std::vector<std::int64_t> counts(static_cast<std::size_t>(schema.num_fields), 0);
  // A member that counts an array gets its value up front; every array it sizes uses it.
  std::vector<bool> is_count(static_cast<std::size_t>(schema.num_fields), false);
  for (int f = 0; f < schema.num_fields; ++f)
    if (schema.fields[f].count_field >= 0) is_count[static_cast<std::size_t>(schema.fields[f].count_field)] = true;
  for (int f = 0; f < schema.num_fields; ++f) {
    const LcmField& field = schema.fields[f];
    const std::int64_t n = field.count_field >= 0 ? counts[static_cast<std::size_t>(field.count_field)] : 1;
    for (std::int64_t i = 0; i < n; ++i) {
      const std::uint64_t bits = rng();
      switch (field.kind) {
        case LcmKind::kInt8:
        case LcmKind::kInt16:
        case LcmKind::kInt32:
        case LcmKind::kInt64: {
          const int width = field.kind == LcmKind::kInt8    ? 1
                            : field.kind == LcmKind::kInt16 ? 2
                            : field.kind == LcmKind::kInt32 ? 4
                                                            : 8;
          std::uint64_t v = bits;
          if (is_count[static_cast<std::size_t>(f)] && field.count_field < 0) {
            v = rng() % static_cast<std::uint64_t>(max_count + 1);
            counts[static_cast<std::size_t>(f)] = static_cast<std::int64_t>(v);
          }
          put_be(out, v, width);
          break;
        }
        case LcmKind::kFloat: put_be(out, bits, 4); break;
        case LcmKind::kDouble: put_be(out, bits, 8); break;
        case LcmKind::kBoolean: put_be(out, bits & 1u, 1); break;
        case LcmKind::kByte: put_be(out, bits, 1); break;
        case LcmKind::kString: {
          const int len = static_cast<int>(rng() % 12);
          put_be(out, static_cast<std::uint64_t>(len + 1), 4);
          for (int c = 0; c < len; ++c) out.push_back(static_cast<std::uint8_t>(0x20 + rng() % 95));
          out.push_back(0);
          break;
        }
      }
    }
  }
  return out;
}

}  // namespace porter::test
