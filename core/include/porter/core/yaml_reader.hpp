#pragma once
// Strict YAML reading for Porter's config files (porter::core_io; processes use it for their own
// configs, so every config error reads the same way).
//
// Every accessor names the file and the full key path in its LoadError, e.g.
//   "config/robots/x/robot.yaml: key 'base.wheel_radius_m': expected a number, got 'abc'".
// Unknown keys are rejected by expect_keys(); a missing key by get().

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

  /// Parses a file; throws LoadError when it is missing or not YAML.
  static Reader load_file(const std::string& file);

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
  int as_int() const;
  bool as_bool() const;
  std::string as_string() const;
  std::vector<double> as_doubles(std::size_t expected_size = 0) const;  ///< 0 = any length
  std::vector<std::string> as_strings() const;
  Eigen::Vector3d as_vec3() const;
  /// {xyz: [..], rpy: [..]} (both optional, default zero) -> transform (URDF rpy convention).
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
