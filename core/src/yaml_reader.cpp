#include "porter/core/yaml_reader.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>

namespace porter::yaml {

namespace {
std::string describe(const YAML::Node& n) {
  if (!n.IsDefined() || n.IsNull()) return "nothing";
  if (n.IsScalar()) return "'" + n.Scalar() + "'";
  if (n.IsSequence()) return "a sequence";
  return "a map";
}

constexpr std::size_t kMaxFileBytes = Reader::kMaxFileBytes;
constexpr std::size_t kMaxNodes = Reader::kMaxNodes;
constexpr int kMaxDepth = Reader::kMaxDepth;

std::string line_of(const YAML::Node& n) {
  const YAML::Mark m = n.Mark();
  return m.is_null() ? std::string() : " (line " + std::to_string(m.line + 1) + ")";
}

// yaml-cpp keeps every pair of a map whose key repeats and operator[] returns the first, so a
// repeated key would silently lose its second value: refuse it, and keys that are not scalars
// (a sequence or map as key) which no Porter config uses. The walk also bounds the nesting
// depth and the number of nodes visited (aliases are visited again at each use, so a
// "billion laughs" file is refused here instead of in a loader's loop).
void check_tree(const YAML::Node& node, const std::string& file, const std::string& path, int depth,
                std::size_t& visited) {
  if (++visited > kMaxNodes)
    throw LoadError(file, "", "more than " + std::to_string(kMaxNodes) + " YAML nodes (aliases counted at each use)");
  if (depth > kMaxDepth)
    throw LoadError(file, path.empty() ? std::string() : "key '" + path + "'",
                    "nested deeper than " + std::to_string(kMaxDepth) + " levels");
  if (node.IsMap()) {
    std::set<std::string> seen;
    for (const auto& kv : node) {
      if (!kv.first.IsScalar())
        throw LoadError(file, path.empty() ? std::string() : "key '" + path + "'",
                        "a map key must be a plain name, got " + describe(kv.first) + line_of(kv.first));
      const std::string& key = kv.first.Scalar();
      const std::string child = path.empty() ? key : path + "." + key;
      if (!seen.insert(key).second)
        throw LoadError(file, "key '" + child + "'", "appears twice in the same map" + line_of(kv.first));
      check_tree(kv.second, file, child, depth + 1, visited);
    }
  } else if (node.IsSequence()) {
    for (std::size_t i = 0; i < node.size(); ++i)
      check_tree(node[i], file, path + "[" + std::to_string(i) + "]", depth + 1, visited);
  }
}

Reader checked(YAML::Node node, const std::string& file) {
  std::size_t visited = 0;
  check_tree(node, file, "", 0, visited);
  return Reader(std::move(node), file);
}

}  // namespace

Reader Reader::load_file(const std::string& file) {
  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) throw LoadError(file, "", "file not found");
  if (!std::filesystem::is_regular_file(file, ec)) throw LoadError(file, "", "not a regular file");
  const auto bytes = std::filesystem::file_size(file, ec);
  if (ec) throw LoadError(file, "", "cannot read its size: " + ec.message());
  if (bytes > kMaxFileBytes)
    throw LoadError(file, "", "file of " + std::to_string(bytes) + " bytes exceeds the " +
                                  std::to_string(kMaxFileBytes) + "-byte limit for a config file");
  YAML::Node node;
  try {
    node = YAML::LoadFile(file);
  } catch (const YAML::Exception& e) {
    throw LoadError(file, "line " + std::to_string(e.mark.line + 1), "not valid YAML: " + e.msg);
  }
  return checked(std::move(node), file);
}

Reader Reader::parse(const std::string& text, const std::string& file_label) {
  if (text.size() > kMaxFileBytes)
    throw LoadError(file_label, "", "text of " + std::to_string(text.size()) + " bytes exceeds the " +
                                        std::to_string(kMaxFileBytes) + "-byte limit for a config file");
  YAML::Node node;
  try {
    node = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw LoadError(file_label, "line " + std::to_string(e.mark.line + 1), "not valid YAML: " + e.msg);
  }
  return checked(std::move(node), file_label);
}

void Reader::fail(const std::string& reason) const {
  throw LoadError(file_, path_.empty() ? std::string() : "key '" + path_ + "'", reason);
}

bool Reader::has(const std::string& key) const {
  return node_.IsMap() && node_[key].IsDefined();
}

Reader Reader::get(const std::string& key) const {
  const std::string child_path = path_.empty() ? key : path_ + "." + key;
  if (!node_.IsMap()) fail("expected a map containing '" + key + "', got " + describe(node_));
  YAML::Node child = node_[key];
  if (!child.IsDefined()) throw LoadError(file_, "key '" + child_path + "'", "missing");
  return Reader(child, file_, child_path);
}

Reader Reader::at(std::size_t i) const {
  if (!node_.IsSequence()) fail("expected a sequence, got " + describe(node_));
  if (i >= node_.size()) fail("index " + std::to_string(i) + " out of range");
  return Reader(node_[i], file_, path_ + "[" + std::to_string(i) + "]");
}

std::size_t Reader::size() const {
  if (!node_.IsSequence()) fail("expected a sequence, got " + describe(node_));
  return node_.size();
}

std::vector<std::string> Reader::keys() const {
  if (!node_.IsMap()) fail("expected a map, got " + describe(node_));
  std::vector<std::string> out;
  for (const auto& kv : node_) {
    if (!kv.first.IsScalar()) fail("a map key must be a plain name, got " + describe(kv.first));
    out.push_back(kv.first.Scalar());
  }
  return out;
}

void Reader::expect_keys(std::initializer_list<const char*> allowed) const {
  for (const auto& key : keys()) {
    bool ok = false;
    for (const char* a : allowed) ok = ok || key == a;
    if (!ok) {
      std::string list;
      for (const char* a : allowed) list += std::string(list.empty() ? "" : ", ") + a;
      const std::string where = path_.empty() ? key : path_ + "." + key;
      throw LoadError(file_, "key '" + where + "'", "unknown key (allowed here: " + list + ")");
    }
  }
}

double Reader::as_double() const {
  if (!node_.IsScalar()) fail("expected a number, got " + describe(node_));
  try {
    std::size_t used = 0;
    const std::string s = node_.Scalar();
    const double v = std::stod(s, &used);
    if (used != s.size() || !std::isfinite(v)) throw std::invalid_argument(s);
    return v;
  } catch (const std::exception&) {
    fail("expected a number, got " + describe(node_));
  }
}

double Reader::as_positive() const {
  const double v = as_double();
  if (!(v > 0.0)) fail("must be positive, got " + node_.Scalar());
  return v;
}

double Reader::as_nonnegative() const {
  const double v = as_double();
  if (v < 0.0) fail("must not be negative, got " + node_.Scalar());
  return v;
}

double Reader::as_in(double lo, double hi, const char* unit, bool open_low) const {
  const double v = as_double();
  if (!(open_low ? v > lo : v >= lo) || !(v <= hi)) {
    char buf[200];
    std::snprintf(buf, sizeof buf, "%g%s%s is out of range %c%g, %g]", v, *unit != '\0' ? " " : "", unit,
                  open_low ? '(' : '[', lo, hi);
    fail(buf);
  }
  return v;
}

int Reader::as_int() const {
  const double v = as_double();
  if (v != std::floor(v) || std::abs(v) > 2e9) fail("expected an integer, got " + node_.Scalar());
  return static_cast<int>(v);
}

bool Reader::as_bool() const {
  if (!node_.IsScalar()) fail("expected true or false, got " + describe(node_));
  const std::string& s = node_.Scalar();
  if (s == "true") return true;
  if (s == "false") return false;
  fail("expected true or false, got " + describe(node_));
}

std::string Reader::as_string() const {
  if (!node_.IsScalar()) fail("expected a string, got " + describe(node_));
  return node_.Scalar();
}

std::vector<double> Reader::as_doubles(std::size_t expected_size) const {
  if (!node_.IsSequence()) fail("expected a sequence of numbers, got " + describe(node_));
  if (expected_size != 0 && node_.size() != expected_size)
    fail("expected a sequence of " + std::to_string(expected_size) + " numbers, got " +
         std::to_string(node_.size()));
  std::vector<double> out;
  for (std::size_t i = 0; i < node_.size(); ++i) out.push_back(at(i).as_double());
  return out;
}

std::vector<std::string> Reader::as_strings() const {
  if (!node_.IsSequence()) fail("expected a sequence of strings, got " + describe(node_));
  std::vector<std::string> out;
  for (std::size_t i = 0; i < node_.size(); ++i) out.push_back(at(i).as_string());
  return out;
}

Eigen::Vector3d Reader::as_vec3() const {
  const auto v = as_doubles(3);
  return {v[0], v[1], v[2]};
}

Eigen::Isometry3d Reader::as_pose() const {
  expect_keys({"xyz", "rpy"});
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  // A pose in a config places a part of the robot or the world: within 10 km (the scenes'
  // bounds), its angles within one turn either way.
  if (has("xyz")) {
    T.translation() = get("xyz").as_vec3();
    if (!(T.translation().cwiseAbs().maxCoeff() <= 1e4)) get("xyz").fail("must be within 1e4 m on each axis");
  }
  if (has("rpy")) {
    const Eigen::Vector3d rpy = get("rpy").as_vec3();
    if (!(rpy.cwiseAbs().maxCoeff() <= 6.283185307179586)) get("rpy").fail("angles must be within [-2 pi, 2 pi] rad");
    T.linear() = rpy_to_matrix(rpy[0], rpy[1], rpy[2]);
  }
  return T;
}

Eigen::Matrix3d rpy_to_matrix(double roll, double pitch, double yaw) {
  return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

std::string resolve_path(const std::string& file, const std::string& relative) {
  std::filesystem::path rel(relative);
  if (rel.is_absolute()) return rel.string();
  return (std::filesystem::path(file).parent_path() / rel).lexically_normal().string();
}

}  // namespace porter::yaml
