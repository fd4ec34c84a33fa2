// Scene YAML -> Scene (scene_loader.hpp). The format is documented in config/scenes/README.md.

#include "porter/core/scene_loader.hpp"

#include <cmath>
#include <filesystem>
#include <cctype>
#include <set>
#include <sstream>
#include <vector>

#include "porter/core/load_error.hpp"
#include "porter/core/mesh_loader.hpp"
#include "porter/core/scene_random.hpp"
#include "porter/core/yaml_reader.hpp"

namespace porter {
namespace {

using yaml::Reader;

constexpr double kPi = 3.14159265358979323846;

/// (-pi, pi]; exact for any finite angle (std::remainder is exact).
double wrap_angle(double a) {
  const double w = std::remainder(a, 2.0 * kPi);
  return w <= -kPi ? w + 2.0 * kPi : w;
}

std::string join_keys(const std::map<std::string, double>& m) {
  std::string s;
  for (const auto& kv : m) s += (s.empty() ? "" : ", ") + kv.first;
  return s.empty() ? "none" : s;
}

std::string fmt(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

Eigen::Isometry3d planar_pose(double x, double y, double z, double yaw_rad) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(x, y, z);
  return T;
}

CollisionShape make_box(const Eigen::Vector3d& size_m, const Eigen::Isometry3d& T_W_box, std::string name) {
  CollisionShape s;
  s.geometry = Box{size_m};
  s.T_parent_shape = T_W_box;
  s.name = std::move(name);
  return s;
}

class SceneParser {
 public:
  SceneParser(Reader root, const SceneLoadOptions& options) : root_(std::move(root)), options_(options) {}

  Scene parse() {
    root_.expect_keys({"name", "description", "bounds", "resolution", "seed", "parameters", "start", "goal",
                       "payload", "obstacles", "random"});
    read_parameters();
    Scene s;
    s.source_file = root_.file();
    s.name = root_.get("name").as_string();
    if (root_.has("description")) s.description = root_.get("description").as_string();
    s.parameters = params_;
    read_bounds(s);
    s.start = read_configuration(root_.get("start"), s);
    s.goal = read_configuration(root_.get("goal"), s);
    const Reader payload = root_.get("payload");
    s.payload_file = yaml::resolve_path(root_.file(), payload.as_string());
    if (!std::filesystem::is_regular_file(s.payload_file)) payload.fail("file '" + s.payload_file + "' not found");
    s.seed = options_.seed ? *options_.seed : (root_.has("seed") ? read_seed(root_.get("seed")) : 0);
    if (root_.has("obstacles")) {
      const Reader obstacles = root_.get("obstacles");
      for (std::size_t i = 0; i < obstacles.size(); ++i) read_obstacle(obstacles.at(i), s);
    }
    if (root_.has("random")) {
      PortableRandom rng(s.seed);
      const Reader random = root_.get("random");
      for (std::size_t i = 0; i < random.size(); ++i) read_generator(random.at(i), s, rng);
    }
    return s;
  }

 private:
  // ---- numbers, with "$name" parameter references -------------------------------------------
  double number(const Reader& r) const {
    const double v = raw_number(r);
    return bounded(r, v);
  }
  double raw_number(const Reader& r) const {
    if (r.is_scalar() && !r.node().Scalar().empty() && r.node().Scalar()[0] == '$') {
      const std::string name = r.node().Scalar().substr(1);
      const auto it = params_.find(name);
      if (it == params_.end())
        r.fail("unknown parameter '$" + name + "' (declared in 'parameters': " + join_keys(params_) + ")");
      return it->second;
    }
    return r.as_double();
  }
  double bounded(const Reader& r, double v) const {
    if (!(std::abs(v) <= kSceneMaxMagnitude_m))
      r.fail("must be within +-" + fmt(kSceneMaxMagnitude_m) + ", got " + fmt(v));
    return v;
  }
  double yaw_of(const Reader& r) const { return wrap_angle(number(r)); }
  double positive(const Reader& r) const {
    const double v = number(r);
    if (!(v > 0.0)) r.fail("must be positive, got " + fmt(v));
    return v;
  }
  double nonnegative(const Reader& r) const {
    const double v = number(r);
    if (v < 0.0) r.fail("must not be negative, got " + fmt(v));
    return v;
  }
  int integer(const Reader& r, int min_value, int max_value) const {
    const double v = raw_number(r);
    if (v != std::floor(v)) r.fail("expected an integer, got " + fmt(v));
    if (v < min_value) r.fail("must be at least " + std::to_string(min_value) + ", got " + fmt(v));
    if (v > max_value) r.fail("must be at most " + std::to_string(max_value) + ", got " + fmt(v));
    return static_cast<int>(v);
  }
  std::vector<double> numbers(const Reader& r, std::size_t n) const {
    if (!r.is_sequence() || r.size() != n)
      r.fail("expected a sequence of " + std::to_string(n) + " numbers");
    std::vector<double> out;
    for (std::size_t i = 0; i < n; ++i) out.push_back(number(r.at(i)));
    return out;
  }
  Eigen::Vector2d vec2(const Reader& r) const {
    const auto v = numbers(r, 2);
    return {v[0], v[1]};
  }
  Eigen::Vector3d vec3(const Reader& r) const {
    const auto v = numbers(r, 3);
    return {v[0], v[1], v[2]};
  }
  Eigen::Vector3d positive_vec3(const Reader& r) const {
    const Eigen::Vector3d v = vec3(r);
    if (!(v.array() > 0.0).all()) r.fail("every component must be positive, got [" + fmt(v.x()) + ", " +
                                         fmt(v.y()) + ", " + fmt(v.z()) + "]");
    return v;
  }
  std::string optional_name(const Reader& body, const std::string& fallback) const {
    return body.has("name") ? body.get("name").as_string() : fallback;
  }

  // ---- top level ----------------------------------------------------------------------------
  void read_parameters() {
    if (root_.has("parameters")) {
      const Reader p = root_.get("parameters");
      for (const auto& key : p.keys()) {
        const Reader v = p.get(key);
        if (key.empty() || !(std::isalpha(static_cast<unsigned char>(key[0])) || key[0] == '_'))
          v.fail("a parameter name must start with a letter or '_'");
        params_[key] = bounded(v, v.as_double());
      }
    }
    for (const auto& [name, value] : options_.parameter_overrides) {
      const auto it = params_.find(name);
      if (it == params_.end())
        throw LoadError(root_.file(), "key 'parameters'",
                        "override '" + name + "' names no parameter of this scene (declared: " +
                            join_keys(params_) + ")");
      if (!(std::abs(value) <= kSceneMaxMagnitude_m))
        throw LoadError(root_.file(), "key 'parameters." + name + "'",
                        "override " + fmt(value) + " is not a number within +-" + fmt(kSceneMaxMagnitude_m));
      it->second = value;
    }
  }

  static std::uint64_t read_seed(const Reader& r) {
    const std::string s = r.is_scalar() ? r.node().Scalar() : std::string();
    if (s.empty() || s.find_first_not_of("0123456789") != std::string::npos)
      r.fail("expected a non-negative integer");
    try {
      return std::stoull(s);
    } catch (const std::exception&) {
      r.fail("does not fit in 64 bits");
    }
  }

  void read_bounds(Scene& s) const {
    const Reader b = root_.get("bounds");
    b.expect_keys({"min", "max"});
    const Eigen::Vector3d lo = vec3(b.get("min")), hi = vec3(b.get("max"));
    for (int i = 0; i < 3; ++i)
      if (!(lo[i] < hi[i]))
        b.fail(std::string("min must be below max on every axis (") + "xyz"[i] + ": " + fmt(lo[i]) +
               " >= " + fmt(hi[i]) + ")");
    s.bounds_W = Eigen::AlignedBox3d(lo, hi);
    const Reader res = root_.get("resolution");
    s.resolution_m = positive(res);
    if (s.resolution_m < kSceneMinResolution_m || s.resolution_m > kSceneMaxResolution_m)
      res.fail("must be within [" + fmt(kSceneMinResolution_m) + ", " + fmt(kSceneMaxResolution_m) + "] m, got " +
               fmt(s.resolution_m));
    // Checked before anything is allocated over the bounds.
    const Eigen::Vector3d n = ((hi - lo) / s.resolution_m).array().ceil();
    const double bytes = n.prod() * kSceneBytesPerVoxel;
    if (!(bytes <= options_.memory_cap_bytes))
      res.fail("gives " + fmt(n.prod()) + " voxels over the bounds, about " + fmt(bytes / (1 << 20)) +
               " MiB of maps at " + fmt(kSceneBytesPerVoxel) + " B per voxel, above the memory cap of " +
               fmt(options_.memory_cap_bytes / (1 << 20)) + " MiB (coarser resolution or smaller bounds)");
  }

  RobotConfiguration read_configuration(const Reader& r, const Scene& s) const {
    r.expect_keys({"base", "arm"});
    const Reader base = r.get("base");
    const Eigen::Vector3d b = vec3(base);
    if (b.x() < s.bounds_W.min().x() || b.x() > s.bounds_W.max().x() || b.y() < s.bounds_W.min().y() ||
        b.y() > s.bounds_W.max().y())
      base.fail("base position (" + fmt(b.x()) + ", " + fmt(b.y()) + ") is outside the scene bounds");
    RobotConfiguration c;
    c.base = {b.x(), b.y(), wrap_angle(b.z())};
    const auto q = numbers(r.get("arm"), kNumArmJoints);
    for (int j = 0; j < kNumArmJoints; ++j) c.q_rad[j] = q[static_cast<std::size_t>(j)];
    return c;
  }

  // ---- obstacles ----------------------------------------------------------------------------
  /// The single key of a one-key map item, e.g. "box" in `- box: {...}`.
  static std::string item_type(const Reader& item, const char* what, const char* allowed) {
    const auto keys = item.keys();
    if (keys.size() != 1)
      item.fail(std::string("expected a map with exactly one key naming the ") + what + " type (" + allowed +
                "), got " + std::to_string(keys.size()) + " keys");
    return keys[0];
  }

  void add(Scene& s, CollisionShape shape, const Reader& where) {
    if (!names_.insert(shape.name).second)
      where.fail("obstacle name '" + shape.name + "' is used twice");
    s.obstacles.push_back(std::move(shape));
  }

  void read_obstacle(const Reader& item, Scene& s) {
    const std::string type = item_type(item, "obstacle", "box, cylinder, sphere, mesh, bridge");
    const Reader body = item.get(type);
    const std::string fallback = item.path();
    if (type == "box") {
      body.expect_keys({"center", "size", "yaw", "name"});
      const Eigen::Vector3d c = vec3(body.get("center"));
      const Eigen::Vector3d size = positive_vec3(body.get("size"));
      const double yaw = body.has("yaw") ? yaw_of(body.get("yaw")) : 0.0;
      add(s, make_box(size, planar_pose(c.x(), c.y(), c.z(), yaw), optional_name(body, fallback)), body);
    } else if (type == "cylinder") {
      body.expect_keys({"center", "radius", "z", "name"});
      const Eigen::Vector2d c = vec2(body.get("center"));
      const double r = positive(body.get("radius"));
      const Reader zr = body.get("z");
      const Eigen::Vector2d z = vec2(zr);
      if (!(z[0] < z[1])) zr.fail("expected [zmin, zmax] with zmin < zmax");
      CollisionShape shape;
      shape.geometry = Cylinder{r, z[1] - z[0]};
      shape.T_parent_shape = planar_pose(c.x(), c.y(), 0.5 * (z[0] + z[1]), 0.0);
      shape.name = optional_name(body, fallback);
      add(s, std::move(shape), body);
    } else if (type == "sphere") {
      body.expect_keys({"center", "radius", "name"});
      CollisionShape shape;
      const Eigen::Vector3d c = vec3(body.get("center"));
      shape.geometry = Sphere{positive(body.get("radius"))};
      shape.T_parent_shape.translation() = c;
      shape.name = optional_name(body, fallback);
      add(s, std::move(shape), body);
    } else if (type == "mesh") {
      read_mesh(body, fallback, s);
    } else if (type == "bridge") {
      read_bridge(body, fallback, s);
    } else {
      throw LoadError(root_.file(), "key '" + item.path() + "." + type + "'",
                      "unknown obstacle type (expected box, cylinder, sphere, mesh or bridge)");
    }
  }

  void read_mesh(const Reader& body, const std::string& fallback, Scene& s) {
    body.expect_keys({"file", "pose", "scale", "name"});
    const Reader file = body.get("file");
    const std::string path = yaml::resolve_path(root_.file(), file.as_string());
    Eigen::Vector3d scale = Eigen::Vector3d::Ones();
    if (body.has("scale")) {
      const Reader sc = body.get("scale");
      scale = sc.is_sequence() ? positive_vec3(sc) : Eigen::Vector3d::Constant(positive(sc));
    }
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    if (body.has("pose")) {
      const Reader pose = body.get("pose");
      pose.expect_keys({"xyz", "rpy"});
      if (pose.has("xyz")) T.translation() = vec3(pose.get("xyz"));
      if (pose.has("rpy")) {
        const Eigen::Vector3d rpy = vec3(pose.get("rpy")).unaryExpr([](double a) { return wrap_angle(a); });
        T.linear() = yaml::rpy_to_matrix(rpy[0], rpy[1], rpy[2]);
      }
    }
    CollisionShape shape;
    try {
      shape.geometry = MeshShape{load_mesh(path, scale)};
    } catch (const LoadError& e) {
      file.fail("cannot load mesh '" + path + "': " + e.reason());
    }
    shape.T_parent_shape = T;
    shape.name = optional_name(body, fallback);
    add(s, std::move(shape), body);
  }

  void read_bridge(const Reader& body, const std::string& fallback, Scene& s) {
    body.expect_keys({"center", "yaw", "opening_width", "clearance", "wall_width", "depth", "height", "name"});
    const Eigen::Vector2d c = vec2(body.get("center"));
    const double yaw = body.has("yaw") ? yaw_of(body.get("yaw")) : 0.0;
    const Reader opening_r = body.get("opening_width");
    const double opening = positive(opening_r);
    const Reader clearance_r = body.get("clearance");
    const double clearance = positive(clearance_r);
    const double wall_width = positive(body.get("wall_width"));
    const double depth = positive(body.get("depth"));
    const double height = positive(body.get("height"));
    if (!(opening < wall_width))
      opening_r.fail("must be less than wall_width (" + fmt(opening) + " >= " + fmt(wall_width) + ")");
    if (!(clearance < height))
      clearance_r.fail("must be less than height (" + fmt(clearance) + " >= " + fmt(height) + ")");
    const std::string name = optional_name(body, fallback);
    // Bridge frame: x along the driving direction (yaw), y across the opening, z up.
    const Eigen::Isometry3d T_W_bridge = planar_pose(c.x(), c.y(), 0.0, yaw);
    const double side = 0.5 * (wall_width - opening);
    const double side_y = 0.5 * (opening + side);
    auto place = [&](double y, double z) { return T_W_bridge * planar_pose(0.0, y, z, 0.0); };
    add(s, make_box({depth, side, height}, place(side_y, 0.5 * height), name + ".left_wall"), body);
    add(s, make_box({depth, side, height}, place(-side_y, 0.5 * height), name + ".right_wall"), body);
    add(s, make_box({depth, opening, height - clearance}, place(0.0, 0.5 * (clearance + height)), name + ".deck"),
        body);
  }

  // ---- random generators --------------------------------------------------------------------
  void read_generator(const Reader& item, Scene& s, PortableRandom& rng) {
    const std::string type = item_type(item, "generator", "columns");
    if (type != "columns")
      throw LoadError(root_.file(), "key '" + item.path() + "." + type + "'",
                      "unknown random generator (expected columns)");
    const Reader body = item.get(type);
    body.expect_keys({"count", "region", "radius", "height", "min_clearance", "max_attempts", "name"});
    ColumnFieldSpec spec;
    spec.count = integer(body.get("count"), 0, kSceneMaxColumns);
    const Reader region = body.get("region");
    region.expect_keys({"min", "max"});
    spec.region_min_W = vec2(region.get("min"));
    spec.region_max_W = vec2(region.get("max"));
    if (!(spec.region_min_W.array() < spec.region_max_W.array()).all())
      region.fail("min must be below max on both axes");
    const Reader radius = body.get("radius");
    const Eigen::Vector2d r = vec2(radius);
    if (!(r[0] > 0.0 && r[0] <= r[1])) radius.fail("expected [rmin, rmax] with 0 < rmin <= rmax");
    if ((spec.region_max_W - spec.region_min_W).minCoeff() < 2.0 * r[0])
      radius.fail("rmin is too large for the region");
    spec.radius_min_m = r[0];
    spec.radius_max_m = std::min(r[1], 0.5 * (spec.region_max_W - spec.region_min_W).minCoeff());
    spec.height_m = positive(body.get("height"));
    spec.min_clearance_m = nonnegative(body.get("min_clearance"));
    spec.max_attempts = body.has("max_attempts") ? integer(body.get("max_attempts"), 1, kSceneMaxAttempts) : 1000;
    if (static_cast<double>(spec.count) * spec.max_attempts > kSceneMaxPlacementTries)
      body.fail("count x max_attempts = " + fmt(static_cast<double>(spec.count) * spec.max_attempts) +
                " placement tries exceeds " + fmt(kSceneMaxPlacementTries));
    spec.name_prefix = optional_name(body, body.path());
    spec.max_footprint_tests = options_.max_footprint_tests - footprint_tests_;
    const std::vector<Eigen::Vector2d> keep_clear = {{s.start.base.x_m, s.start.base.y_m},
                                                     {s.goal.base.x_m, s.goal.base.y_m}};
    ColumnFieldResult placed = place_columns(spec, s.obstacles, keep_clear, rng);
    footprint_tests_ += placed.footprint_tests;
    if (placed.out_of_tests)
      body.fail("placing the columns takes more than " + fmt(static_cast<double>(options_.max_footprint_tests)) +
                " distance tests (all generators of the scene together; placed " +
                std::to_string(placed.columns.size()) + " of " + std::to_string(spec.count) +
                "); lower count, max_attempts or min_clearance, or enlarge region");
    for (auto& column : placed.columns) add(s, std::move(column), body);
    if (!placed.complete)
      body.fail("placed only " + std::to_string(placed.columns.size()) + " of " + std::to_string(spec.count) +
                " columns with seed " + std::to_string(s.seed) + " (max_attempts " +
                std::to_string(spec.max_attempts) + " per column); lower count or min_clearance, or enlarge region");
  }

  Reader root_;
  const SceneLoadOptions& options_;
  std::map<std::string, double> params_;
  std::set<std::string> names_;
  std::int64_t footprint_tests_ = 0;  ///< by all random generators so far
};

}  // namespace

Scene load_scene(const std::string& path, const SceneLoadOptions& options) {
  return SceneParser(Reader::load_file(path), options).parse();
}

Scene parse_scene(const std::string& yaml_text, const std::string& file_label, const SceneLoadOptions& options) {
  return SceneParser(Reader::parse(yaml_text, file_label), options).parse();
}

}  // namespace porter
