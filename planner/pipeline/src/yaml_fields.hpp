#pragma once
// Private to porter::pipeline_io: reading one YAML map into struct fields with range checks, every
// error a LoadError naming the file and the key (porter::yaml::Reader).

#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <optional>
#include <string>

#include "porter/core/yaml_reader.hpp"
#include "porter/midend/midend_settings.hpp"

namespace porter::pipeline::detail {

// Upper bounds of the planner's settings by unit: 1 km, an hour, a turn, 1 km/s; weights, costs,
// factors and tolerances up to 1e12 (the shipped ones are 1e-9 to 1e6). Beyond them a setting
// plans no robot, and the bounds keep the products and counts made from settings finite.
inline constexpr double kMaxLength_m = 1000.0;
inline constexpr double kMaxTime_s = 3600.0;
inline constexpr double kMaxAngle_rad = 6.283185307179586;
inline constexpr double kMaxSpeed = 1000.0;  ///< m/s, m/s^3
inline constexpr double kMaxWeight = 1e12;
// Smallest cells and steps of the grids and samplings the settings size: below them a scene's
// cells or a trajectory's samples outnumber memory (the shipped ones are 0.5 mm-0.3 m, 20 ms).
inline constexpr double kMinCell_m = 1e-4;
inline constexpr double kMinStep_s = 1e-4;
inline constexpr double kMinStep_rad = 1e-4;

/// A map whose keys must be exactly the given ones (unknown: LoadError; missing: LoadError when
/// read).
class Fields {
 public:
  Fields(const yaml::Reader& map, std::initializer_list<const char*> keys) : r_(map) { r_.expect_keys(keys); }

  yaml::Reader section(const char* key) const { return r_.get(key); }

  /// A finite number in [lo, hi] (in (lo, hi] with lo_open): yaml::Reader::as_in.
  void number(const char* key, double& out, double lo, double hi, bool lo_open = false) const {
    out = r_.get(key).as_in(lo, hi, "", lo_open);
  }
  /// (0, hi]
  void positive(const char* key, double& out, double hi) const { number(key, out, 0.0, hi, true); }
  /// [0, hi]
  void nonnegative(const char* key, double& out, double hi) const { number(key, out, 0.0, hi); }
  /// 0 (off, or derived from other settings) or in [lo, hi]: between 0 and lo a step or a cell
  /// would make its count explode.
  void zero_or_in(const char* key, double& out, double lo, double hi) const {
    number(key, out, 0.0, hi);
    if (out > 0.0 && out < lo) r_.get(key).fail("must be 0 or in " + interval(lo, hi) + ", got " + r_.get(key).node().Scalar());
  }
  /// (0, 1]
  void fraction(const char* key, double& out) const { number(key, out, 0.0, 1.0, true); }
  /// [0, 1]
  void probability(const char* key, double& out) const { number(key, out, 0.0, 1.0); }
  void integer(const char* key, int& out, int lo, int hi = std::numeric_limits<int>::max()) const {
    const yaml::Reader v = r_.get(key);
    const int x = v.as_int();
    if (x < lo || x > hi)
      v.fail("must be in " + interval(lo, hi == std::numeric_limits<int>::max() ? kInf : hi) + ", got " +
             v.node().Scalar());
    out = x;
  }
  void integer(const char* key, std::int64_t& out, int lo, int hi = std::numeric_limits<int>::max()) const {
    int x = 0;
    integer(key, x, lo, hi);
    out = x;
  }
  void flag(const char* key, bool& out) const { out = r_.get(key).as_bool(); }
  /// One of the names `parse` accepts ("expected one of: <choices>" otherwise).
  template <class T, class Parse>
  void choice(const char* key, T& out, Parse parse, const char* choices) const {
    const yaml::Reader v = r_.get(key);
    const std::optional<T> x = parse(v.as_string());
    if (!x) v.fail(std::string("expected one of: ") + choices + ", got " + v.node().Scalar());
    out = *x;
  }

 private:
  static constexpr double kInf = std::numeric_limits<double>::infinity();
  static std::string bound(double v) {
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    std::string s = std::to_string(v);
    s.erase(s.find_last_not_of('0') + 1);
    if (!s.empty() && s.back() == '.') s.pop_back();
    return s;
  }
  static std::string interval(double lo, double hi) {
    return "[" + bound(lo) + ", " + bound(hi) + (std::isinf(hi) ? ")" : "]");
  }
  yaml::Reader r_;
};

inline std::optional<midend::LineSearch> parse_line_search(const std::string& s) {
  if (s == "more_thuente") return midend::LineSearch::kMoreThuente;
  if (s == "backtracking_wolfe") return midend::LineSearch::kBacktrackingWolfe;
  if (s == "backtracking_strong_wolfe") return midend::LineSearch::kBacktrackingStrongWolfe;
  if (s == "backtracking_armijo") return midend::LineSearch::kBacktrackingArmijo;
  return std::nullopt;
}
inline constexpr const char* kLineSearches =
    "more_thuente, backtracking_wolfe, backtracking_strong_wolfe, backtracking_armijo";

/// A stage's own cross-field validation (validate(&why)), a failure reported against the file.
template <class Validate>
void check(const std::string& file, Validate validate) {
  std::string why;
  if (!validate(&why)) throw LoadError(file, "", why);
}

}  // namespace porter::pipeline::detail
