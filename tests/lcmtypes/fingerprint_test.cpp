// minco_trajectory_t is a contract between the planner and the tracker: its fields, their order
// and types are fixed. Two independent checks against the written specification:
//   1. a slow reference of lcm-gen's fingerprint algorithm applied to the spec's field list must
//      equal the generated type's fingerprint;
//   2. bytes written by hand from the spec (LCM wire format: big-endian, strings as int32 length
//      including the NUL, then the bytes) must equal what the generated encoder produces.

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "porter/minco_trajectory_t.hpp"
#include "roundtrip_support.hpp"

namespace porter {
namespace {

// ---- reference fingerprint (lcmgen.c: hash_update / hash_string_update / lcm_struct_hash) ------
struct FieldSpec {
  std::string name;
  std::string type;       // primitive lcm type
  std::string dimension;  // "" = scalar, else the name of the count field (variable size)
};

std::int64_t hash_update(std::int64_t v, char c) {
  const std::uint64_t shifted = static_cast<std::uint64_t>(v) << 8;
  const std::int64_t high = v >> 55;  // arithmetic shift, as lcm-gen's signed int64_t does
  return static_cast<std::int64_t>((shifted ^ static_cast<std::uint64_t>(high)) +
                                   static_cast<std::uint64_t>(static_cast<std::int64_t>(c)));
}

std::int64_t hash_string_update(std::int64_t v, const std::string& s) {
  v = hash_update(v, static_cast<char>(s.size()));
  for (char c : s) v = hash_update(v, c);
  return v;
}

std::int64_t reference_fingerprint(const std::vector<FieldSpec>& fields) {
  constexpr char kVariableDimension = 1;  // lcm_dimension_mode_t: LCM_CONST = 0, LCM_VAR = 1
  std::int64_t v = 0x12345678;
  for (const FieldSpec& f : fields) {
    v = hash_string_update(v, f.name);
    v = hash_string_update(v, f.type);  // every field here is primitive
    if (f.dimension.empty()) {
      v = hash_update(v, 0);
    } else {
      v = hash_update(v, 1);
      v = hash_update(v, kVariableDimension);
      v = hash_string_update(v, f.dimension);
    }
  }
  // The generated _computeHash() rotates the struct hash left by one bit.
  const auto u = static_cast<std::uint64_t>(v);
  return static_cast<std::int64_t>((u << 1) + ((u >> 63) & 1));
}

const std::vector<FieldSpec>& minco_spec() {
  static const std::vector<FieldSpec> spec = {
      {"utime", "int64_t", ""},          {"start_utime", "int64_t", ""},
      {"plan_id", "int64_t", ""},        {"frame_id", "string", ""},
      {"payload_id", "string", ""},      {"dimension", "int32_t", ""},
      {"order", "int32_t", ""},          {"start_yaw_rad", "double", ""},
      {"num_pieces", "int32_t", ""},     {"durations_s", "double", "num_pieces"},
      {"eta", "int8_t", "num_pieces"},   {"num_coeffs", "int32_t", ""},
      {"coeffs", "double", "num_coeffs"},
  };
  return spec;
}

TEST(LcmFingerprint, MincoTrajectoryMatchesTheSpecifiedLayout) {
  EXPECT_EQ(minco_trajectory_t::getHash(), reference_fingerprint(minco_spec()));
}

TEST(LcmFingerprint, ReferenceIsSensitiveToOrderNamesAndTypes) {
  // The reference must tell layouts apart, or test 1 could not fail.
  const std::int64_t base = reference_fingerprint(minco_spec());
  std::vector<FieldSpec> swapped = minco_spec();
  std::swap(swapped[0], swapped[1]);
  EXPECT_NE(reference_fingerprint(swapped), base);
  std::vector<FieldSpec> renamed = minco_spec();
  renamed[7].name = "start_yaw";
  EXPECT_NE(reference_fingerprint(renamed), base);
  std::vector<FieldSpec> retyped = minco_spec();
  retyped[10].type = "int32_t";
  EXPECT_NE(reference_fingerprint(retyped), base);
}

// ---- hand-written wire bytes ---------------------------------------------------------------------
class WireWriter {
 public:
  void i8(std::int8_t v) { bytes.push_back(static_cast<std::uint8_t>(v)); }
  void i32(std::int32_t v) { be(static_cast<std::uint64_t>(static_cast<std::uint32_t>(v)), 4); }
  void i64(std::int64_t v) { be(static_cast<std::uint64_t>(v), 8); }
  void f64(double v) {
    std::uint64_t u = 0;
    std::memcpy(&u, &v, sizeof u);
    be(u, 8);
  }
  void str(const std::string& s) {
    i32(static_cast<std::int32_t>(s.size() + 1));
    bytes.insert(bytes.end(), s.begin(), s.end());
    bytes.push_back(0);
  }
  std::vector<std::uint8_t> bytes;

 private:
  void be(std::uint64_t v, int n) {
    for (int i = n - 1; i >= 0; --i) bytes.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  }
};

TEST(LcmFingerprint, MincoTrajectoryWireBytesFollowTheSpec) {
  minco_trajectory_t m{};
  m.utime = 0x0102030405060708;
  m.start_utime = 1'000'000;
  m.plan_id = -2;
  m.frame_id = "world";
  m.payload_id = "arc";
  m.dimension = 2;
  m.order = 1;
  m.start_yaw_rad = 0.5;
  m.num_pieces = 2;
  m.durations_s = {1.5, 2.5};
  m.eta = {1, -1};
  m.num_coeffs = m.num_pieces * m.dimension * (m.order + 1);
  m.coeffs = {1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0};

  WireWriter w;
  w.i64(minco_trajectory_t::getHash());
  w.i64(m.utime);
  w.i64(m.start_utime);
  w.i64(m.plan_id);
  w.str(m.frame_id);
  w.str(m.payload_id);
  w.i32(m.dimension);
  w.i32(m.order);
  w.f64(m.start_yaw_rad);
  w.i32(m.num_pieces);
  for (double d : m.durations_s) w.f64(d);
  for (std::int8_t e : m.eta) w.i8(e);
  w.i32(m.num_coeffs);
  for (double c : m.coeffs) w.f64(c);

  EXPECT_EQ(test::encode(m), w.bytes);
}

}  // namespace
}  // namespace porter
