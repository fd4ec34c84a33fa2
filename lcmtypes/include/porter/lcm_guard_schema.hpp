#pragma once
// The wire layout of an lcm message type, as the guard (porter/lcm_guard.hpp) reads it. The
// tables for Porter's types are generated from lcmtypes/*.lcm (porter/lcm_schema.hpp).

#include <cstdint>

namespace porter {

/// Wire kind of one member (LCM encodes every number big-endian).
enum class LcmKind : std::uint8_t {
  kInt8, kInt16, kInt32, kInt64, kFloat, kDouble, kBoolean, kByte, kString
};

/// One member in wire order. `count_field` is the index of the earlier member holding the
/// element count of this array, or -1 for a single value.
struct LcmField {
  const char* name;
  LcmKind kind;
  int count_field;
};

struct LcmSchema {
  const char* type_name;  ///< e.g. "porter.estop_t"
  const LcmField* fields;
  int num_fields;
};

/// Specialised for every generated type in porter/lcm_schema.hpp (kSchema).
template <class T>
struct LcmSchemaOf;

}  // namespace porter
