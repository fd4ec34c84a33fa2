#pragma once
// Strict YAML reading for Porter's config files (porter::core_io; processes use it for their own
// configs, so every config error reads the same way).
//
// Every accessor names the file and the full key path in its LoadError, e.g.
//   "config/robots/x/robot.yaml: key 'base.wheel_radius_m': expected a number, got 'abc'".
// Unknown keys are rejected by expect_keys(); a missing key by get(). load_file() and parse()
// also refuse what yaml-cpp would accept silently: a key repeated in one map (yaml-cpp keeps
// both and get() would see the first), a key that is not a plain scalar, nesting deeper than
// kMaxDepth, more than kMaxNodes nodes (aliases counted at each use), and files larger than
// kMaxFileBytes; a path that is a directory is "not a regular file".

#include <initializer_list>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <yaml-cpp/yaml.h>

#include "porter/core/load_error.hpp"

namespace porter::yaml {

class Reader {
 public:
  Reader(YAML::Node node, std::string file, std::string path = "")
      : node_(std::move(node)), file_(std::move(file)), path_(std::move(path)) {}

  /// Largest config file read, bytes (the largest shipped config is a few kB).
  static constexpr std::size_t kMaxFileBytes = std::size_t{16} << 20;
  /// Most YAML nodes one document may hold, aliases counted at each use.
  static constexpr std::size_t kMaxNodes = 1'000'000;
  /// Deepest nesting of maps and sequences.
  static constexpr int kMaxDepth = 64;

  /// Parses a file; throws LoadError when it is missing, not a regular file, too large, not
  /// YAML, or breaks the rules above.
  static Reader load_file(const std::string& file);
  /// Parses YAML held in memory with the same checks; `file_label` names it in errors.
  static Reader parse(const std::string& text, const std::string& file_label);

  const std::string& file() const { return file_; }
  const std::string& path() const { return path_; }
  const YAML::Node& node() const { return node_; }

  bool has(const std::string& key) const;
  /// Required child; throws when missing.
  Reader get(const std::string& key) const;
  /// Element i of a sequence.
  Reader at(std::size_t i) const;
  std::size_t size() const;  ///< sequence length; throws when not a sequence
  bool is_map() const { return node_.IsMap(); }
  bool is_sequence() const { return node_.IsSequence(); }
  bool is_scalar() const { return node_.IsScalar(); }
  /// Keys of a map, in file order; throws when not a map.
  std::vector<std::string> keys() const;
  /// Throws on the first key not in `allowed` (also checks this node is a map).
  void expect_keys(std::initializer_list<const char*> allowed) const;

  double as_double() const;
  double as_positive() const;      ///< > 0
  double as_nonnegative() const;   ///< >= 0
  /// A number in [lo, hi] (in (lo, hi] when `open_low`). Every number a process config holds is
  /// read this way: the bounds keep products with rates and periods, conversions to integers and
  /// allocations sized from it well defined. `unit` is named in the error, e.g.
  /// "key 'loop.rate_hz': 1e+308 Hz is out of range [1, 1000]".
  double as_in(double lo, double hi, const char* unit = "", bool open_low = false) const;
  int as_int() const;
  bool as_bool() const;
  std::string as_string() const;
  std::vector<double> as_doubles(std::size_t expected_size = 0) const;  ///< 0 = any length
  std::vector<std::string> as_strings() const;
  Eigen::Vector3d as_vec3() const;
  /// {xyz: [..], rpy: [..]} (both optional, default zero) -> transform (URDF rpy convention);
  /// xyz within 1e4 m on each axis, rpy within [-2 pi, 2 pi].
  Eigen::Isometry3d as_pose() const;

  [[noreturn]] void fail(const std::string& reason) const;

 private:
  YAML::Node node_;
  std::string file_;
  std::string path_;
};

/// URDF convention: R = Rz(yaw) * Ry(pitch) * Rx(roll).
Eigen::Matrix3d rpy_to_matrix(double roll, double pitch, double yaw);

/// Resolves `relative` against the directory of `file` (absolute paths are returned as is).
std::string resolve_path(const std::string& file, const std::string& relative);

}  // namespace porter::yaml
