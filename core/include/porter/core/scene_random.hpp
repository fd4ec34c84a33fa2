#pragma once
// Seeded random obstacle generators for scenes. A seed gives the same world on every platform:
// draws come from std::mt19937_64 (fully specified by the C++ standard) and are mapped to
// numbers by the explicit formulas below, not by <random>'s distributions (whose algorithms
// differ between standard libraries).
//
// Thread-safety: PortableRandom is a value with mutable state (one per thread); the generator
// functions are reentrant.

#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "porter/core/geometry.hpp"

namespace porter {

class PortableRandom {
 public:
  explicit PortableRandom(std::uint64_t seed) : engine_(seed) {}
  std::uint64_t next_u64() { return engine_(); }
  /// In [0, 1): the top 53 bits of one draw times 2^-53.
  double uniform01() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  /// In [lo, hi): lo + (hi - lo) * uniform01(); returns lo when hi <= lo.
  double uniform(double lo, double hi) { return hi > lo ? lo + (hi - lo) * uniform01() : lo; }

 private:
  std::mt19937_64 engine_;
};

/// Vertical columns standing on the ground, placed one at a time by rejection sampling.
struct ColumnFieldSpec {
  int count = 0;
  Eigen::Vector2d region_min_W = Eigen::Vector2d::Zero();  ///< the whole disc stays inside
  Eigen::Vector2d region_max_W = Eigen::Vector2d::Zero();
  double radius_min_m = 0.1;
  double radius_max_m = 0.1;
  double height_m = 2.0;          ///< columns span z in [0, height]
  double min_clearance_m = 0.5;   ///< gap from keep-clear points and from other footprints
  int max_attempts = 1000;        ///< per column
  std::string name_prefix = "column";  ///< column k is named "<prefix>[k]"
  /// Distance tests allowed in all (keep-clear points, obstacles as footprint_cost counts them,
  /// placed columns): an attempt is made only when its tests cannot take the total above this.
  std::int64_t max_footprint_tests = std::numeric_limits<std::int64_t>::max();
};

struct ColumnFieldResult {
  std::vector<CollisionShape> columns;  ///< the ones placed, in order
  bool complete = false;                ///< all `count` columns were placed
  std::int64_t footprint_tests = 0;     ///< distance tests made
  bool out_of_tests = false;            ///< stopped by max_footprint_tests
};

/// Per column: draw radius r = uniform(rmin, rmax), then centre x, y = uniform over the region
/// shrunk by r (x drawn before y), and keep it when its surface is at least min_clearance_m from
/// every keep-clear point and from the footprint (footprint_distance) of every obstacle in
/// `existing_W` and every column placed before; otherwise redraw, up to max_attempts draws of
/// (r, x, y). Stops at the first column that cannot be placed (complete = false), or before an
/// attempt whose tests could take the total past max_footprint_tests (out_of_tests = true).
ColumnFieldResult place_columns(const ColumnFieldSpec& spec, const std::vector<CollisionShape>& existing_W,
                                const std::vector<Eigen::Vector2d>& keep_clear_xy_W, PortableRandom& rng);

}  // namespace porter
