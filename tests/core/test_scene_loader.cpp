// Scene files (scene_loader.hpp): format, parameters, seeds, strict errors.

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <memory>
#include <random>

#include <gtest/gtest.h>

#include "porter/core/load_error.hpp"
#include "porter/core/scene_loader.hpp"
#include "porter/core/scene_random.hpp"

namespace porter {
namespace {

namespace fs = std::filesystem;

class SceneFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("porter_scene_test_" + std::to_string(std::random_device{}()));
    fs::create_directories(dir_);
    std::ofstream(dir_ / "payload.yaml") << "name: dummy\n";
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string label() const { return (dir_ / "scene.yaml").string(); }

  /// A valid scene with `extra` appended (more top-level keys).
  static std::string base(const std::string& extra) {
    return "name: t\n"
           "bounds: {min: [-5, -5, 0], max: [5, 5, 3]}\n"
           "resolution: 0.1\n"
           "start: {base: [-4, 0, 0], arm: [0, 0.6, -0.9, 0, 0.5, 0]}\n"
           "goal: {base: [4, 0, 0], arm: [0, 0.6, -0.9, 0, 0.5, 0]}\n"
           "payload: payload.yaml\n" +
           extra;
  }

  /// Expects parse_scene to throw a LoadError naming this file and a key containing `key`.
  void expect_error(const std::string& text, const std::string& key, const SceneLoadOptions& opts = {}) {
    try {
      parse_scene(text, label(), opts);
      ADD_FAILURE() << "no error for key " << key;
    } catch (const LoadError& e) {
      EXPECT_EQ(e.file(), label());
      EXPECT_NE(e.element().find(key), std::string::npos) << "element '" << e.element() << "', message: " << e.what();
    }
  }

  fs::path dir_;
};

TEST_F(SceneFiles, ReadsEveryFieldAndObstacleType) {
  std::ofstream(dir_ / "cube.obj") << "v -0.5 -0.5 -0.5\nv 0.5 -0.5 -0.5\nv 0.5 0.5 -0.5\nv -0.5 0.5 -0.5\n"
                                      "v -0.5 -0.5 0.5\nv 0.5 -0.5 0.5\nv 0.5 0.5 0.5\nv -0.5 0.5 0.5\n"
                                      "f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\n"
                                      "f 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n";
  const Scene s = parse_scene(base("description: d\nseed: 7\n"
                                   "obstacles:\n"
                                   "  - box: {center: [1, 2, 0.5], size: [0.8, 0.1, 1.0], yaw: 0.5, name: b}\n"
                                   "  - cylinder: {center: [-1, -2], radius: 0.3, z: [0.5, 1.5]}\n"
                                   "  - sphere: {center: [0, 3, 1], radius: 0.25}\n"
                                   "  - mesh: {file: cube.obj, pose: {xyz: [2, -3, 1], rpy: [0, 0, 0.3]}, scale: [1, 2, 0.5]}\n"),
                              label());
  EXPECT_EQ(s.name, "t");
  EXPECT_EQ(s.description, "d");
  EXPECT_EQ(s.seed, 7u);
  EXPECT_EQ(s.source_file, label());
  EXPECT_EQ(s.resolution_m, 0.1);
  EXPECT_TRUE(s.bounds_W.min().isApprox(Eigen::Vector3d(-5, -5, 0)));
  EXPECT_EQ(s.start.base.x_m, -4.0);
  EXPECT_EQ(s.goal.q_rad[2], -0.9);
  EXPECT_EQ(fs::path(s.payload_file), dir_ / "payload.yaml");
  ASSERT_EQ(s.obstacles.size(), 4u);
  EXPECT_EQ(s.obstacles[0].name, "b");
  EXPECT_EQ(s.obstacles[1].name, "obstacles[1]");
  EXPECT_TRUE(shape_contains(s.obstacles[0], {1 + 0.35 * std::cos(0.5), 2 + 0.35 * std::sin(0.5), 0.9}));
  EXPECT_FALSE(shape_contains(s.obstacles[0], {1.35, 2, 0.9}));  // would be inside without the yaw
  EXPECT_TRUE(shape_contains(s.obstacles[1], {-1, -1.75, 1.45}));
  EXPECT_FALSE(shape_contains(s.obstacles[1], {-1, -2, 0.45}));
  EXPECT_TRUE(shape_contains(s.obstacles[2], {0, 3.2, 1}));
  // Mesh: unit cube scaled to 1 x 2 x 0.5, turned 0.3 rad about z, centred at (2, -3, 1).
  const Eigen::AlignedBox3d mb = shape_bounds(s.obstacles[3]);
  const double ex = 0.5 * std::cos(0.3) + 1.0 * std::sin(0.3), ez = 0.25;
  EXPECT_NEAR(mb.max().x(), 2 + ex, 1e-9);
  EXPECT_NEAR(mb.max().z(), 1 + ez, 1e-9);
  EXPECT_TRUE(shape_contains(s.obstacles[3], {2, -3 + 0.9 * std::cos(0.3), 1.2}));
}

TEST_F(SceneFiles, BridgeExpandsIntoTwoWallsAndADeck) {
  const Scene s = parse_scene(base("obstacles:\n"
                                   "  - bridge: {name: br, center: [1, 0.5], yaw: 1.5707963267948966, opening_width: 1.2,\n"
                                   "             clearance: 0.9, wall_width: 4, depth: 0.3, height: 2}\n"),
                              label());
  ASSERT_EQ(s.obstacles.size(), 3u);
  EXPECT_EQ(s.obstacles[0].name, "br.left_wall");
  EXPECT_EQ(s.obstacles[2].name, "br.deck");
  auto occupied = [&](double x, double y, double z) {
    for (const auto& o : s.obstacles)
      if (shape_contains(o, {x, y, z})) return true;
    return false;
  };
  // Driving direction +y, so the opening spans x in [0.4, 1.6] and the wall y in [0.35, 0.65].
  EXPECT_FALSE(occupied(1.0, 0.5, 0.45));
  EXPECT_FALSE(occupied(0.41, 0.5, 0.89));
  EXPECT_TRUE(occupied(1.0, 0.5, 0.91));   // under side of the deck
  EXPECT_TRUE(occupied(1.0, 0.5, 1.99));
  EXPECT_FALSE(occupied(1.0, 0.5, 2.01));  // above the wall
  EXPECT_TRUE(occupied(0.39, 0.5, 0.1));   // side walls
  EXPECT_TRUE(occupied(1.61, 0.5, 0.1));
  EXPECT_TRUE(occupied(-0.99, 0.64, 1.0));
  EXPECT_FALSE(occupied(-1.01, 0.5, 1.0));  // beyond wall_width
  EXPECT_FALSE(occupied(1.0, 0.66, 1.0));   // beyond the depth
}

TEST_F(SceneFiles, ParametersSubstituteAndOverride) {
  const std::string text = base("parameters: {h_b: 1.0, w: 1.1}\n"
                                "obstacles:\n"
                                "  - bridge: {center: [0, 0], opening_width: $w, clearance: $h_b, wall_width: 10,\n"
                                "             depth: 0.3, height: 2.5}\n");
  const Scene a = parse_scene(text, label());
  EXPECT_EQ(a.parameters.at("h_b"), 1.0);
  const Eigen::AlignedBox3d deck = shape_bounds(a.obstacles[2]);
  EXPECT_NEAR(deck.min().z(), 1.0, 1e-12);
  EXPECT_NEAR(deck.sizes().y(), 1.1, 1e-12);
  SceneLoadOptions opts;
  opts.parameter_overrides = {{"h_b", 0.8}};
  const Scene b = parse_scene(text, label(), opts);
  EXPECT_EQ(b.parameters.at("h_b"), 0.8);
  EXPECT_EQ(b.parameters.at("w"), 1.1);
  EXPECT_NEAR(shape_bounds(b.obstacles[2]).min().z(), 0.8, 1e-12);
  opts.parameter_overrides = {{"h_c", 0.8}};
  expect_error(text, "parameters", opts);
  expect_error(base("parameters: {h_b: 1.0}\nresolution2: 1\n"), "resolution2");
  expect_error(base("obstacles:\n  - sphere: {center: [0, 0, $nope], radius: 1}\n"), "obstacles[0].sphere.center[2]");
  expect_error(base("parameters: {h_b: $x}\n"), "parameters.h_b");
}

TEST_F(SceneFiles, StrictErrorsNameFileAndKey) {
  expect_error(base("colour: red\n"), "colour");
  expect_error(base("obstacles:\n  - box: {center: [0, 0, 1], size: [1, 1, 1], colour: red}\n"),
               "obstacles[0].box.colour");
  expect_error(base("obstacles:\n  - box: {center: [0, 0, 1]}\n"), "obstacles[0].box.size");
  expect_error(base("obstacles:\n  - box: {center: [0, 0, 1], size: [1, -1, 1]}\n"), "obstacles[0].box.size");
  expect_error(base("obstacles:\n  - box: {center: [0, 0, 1], size: [1, 1]}\n"), "obstacles[0].box.size");
  expect_error(base("obstacles:\n  - box: {center: [0, 0, 1], size: abc}\n"), "obstacles[0].box.size");
  expect_error(base("obstacles:\n  - box: {center: [0, 0, x], size: [1, 1, 1]}\n"), "obstacles[0].box.center[2]");
  expect_error(base("obstacles:\n  - cone: {center: [0, 0, 1]}\n"), "obstacles[0].cone");
  expect_error(base("obstacles:\n  - {box: {center: [0, 0, 1], size: [1, 1, 1]}, sphere: {}}\n"), "obstacles[0]");
  expect_error(base("obstacles:\n  - cylinder: {center: [0, 0], radius: 0.2, z: [2, 1]}\n"),
               "obstacles[0].cylinder.z");
  expect_error(base("obstacles:\n  - bridge: {center: [0, 0], opening_width: 5, clearance: 1, wall_width: 4,"
                    " depth: 0.3, height: 2}\n"),
               "obstacles[0].bridge.opening_width");
  expect_error(base("obstacles:\n  - mesh: {file: missing.obj}\n"), "obstacles[0].mesh.file");
  expect_error(base("obstacles:\n  - sphere: {center: [0, 0, 1], radius: 1, name: a}\n"
                    "  - sphere: {center: [0, 0, 3], radius: 1, name: a}\n"),
               "obstacles[1]");
  expect_error(base("random:\n  - trees: {count: 3}\n"), "random[0].trees");
  // Top-level fields.
  std::string no_start = base("");
  no_start.erase(no_start.find("start:"), no_start.find("goal:") - no_start.find("start:"));
  expect_error(no_start, "start");
  expect_error("name: t\nbounds: {min: [0, 0, 0], max: [-1, 1, 1]}\nresolution: 0.1\n", "bounds");
  std::string neg_res = base("");
  neg_res.replace(neg_res.find("resolution: 0.1"), 15, "resolution: -0.1");
  expect_error(neg_res, "resolution");
  std::string no_payload = base("");
  no_payload.replace(no_payload.find("payload.yaml"), 12, "nothing.yaml");
  expect_error(no_payload, "payload");
  std::string outside = base("");
  outside.replace(outside.find("[-4, 0, 0]"), 10, "[-6, 0, 0]");
  expect_error(outside, "start.base");
  expect_error(base("").replace(0, 7, ""), "name");
}

TEST_F(SceneFiles, MissingOrMalformedFile) {
  try {
    load_scene((dir_ / "nope.yaml").string());
    ADD_FAILURE();
  } catch (const LoadError& e) {
    EXPECT_EQ(e.file(), (dir_ / "nope.yaml").string());
  }
  EXPECT_THROW(parse_scene("name: [unclosed\n", label()), LoadError);
  EXPECT_THROW(parse_scene("", label()), LoadError);
}

const char* kColumns =
    "obstacles:\n"
    "  - box: {name: wall, center: [0, 0, 1], size: [0.2, 6, 2], yaw: 0.3}\n"
    "random:\n"
    "  - columns: {count: 12, region: {min: [-4.5, -4.5], max: [4.5, 4.5]}, radius: [0.1, 0.2],\n"
    "              height: 2.0, min_clearance: 0.5}\n";

TEST_F(SceneFiles, RandomColumnsAreSeededAndKeepClear) {
  SceneLoadOptions o1, o2;
  o1.seed = 11;
  o2.seed = 12;
  const Scene a = parse_scene(base(kColumns), label(), o1);
  const Scene a2 = parse_scene(base(kColumns), label(), o1);
  const Scene b = parse_scene(base(kColumns), label(), o2);
  ASSERT_EQ(a.obstacles.size(), 13u);
  ASSERT_EQ(b.obstacles.size(), 13u);
  EXPECT_EQ(a.seed, 11u);
  bool differs = false;
  for (std::size_t i = 1; i < a.obstacles.size(); ++i) {
    const auto& ca = a.obstacles[i];
    EXPECT_EQ(ca.name, "random[0].columns[" + std::to_string(i - 1) + "]");
    EXPECT_EQ(ca.T_parent_shape.matrix(), a2.obstacles[i].T_parent_shape.matrix());
    EXPECT_EQ(std::get<Cylinder>(ca.geometry).radius_m, std::get<Cylinder>(a2.obstacles[i].geometry).radius_m);
    differs = differs || !ca.T_parent_shape.isApprox(b.obstacles[i].T_parent_shape);
    const auto& cyl = std::get<Cylinder>(ca.geometry);
    const Eigen::Vector2d c = ca.T_parent_shape.translation().head<2>();
    EXPECT_GE(cyl.radius_m, 0.1);
    EXPECT_LE(cyl.radius_m, 0.2);
    EXPECT_NEAR(ca.T_parent_shape.translation().z(), 1.0, 1e-12);  // z in [0, 2]
    EXPECT_LE(c.cwiseAbs().maxCoeff() + cyl.radius_m, 4.5 + 1e-12);
    EXPECT_GE((c - Eigen::Vector2d(-4, 0)).norm(), cyl.radius_m + 0.5);
    EXPECT_GE((c - Eigen::Vector2d(4, 0)).norm(), cyl.radius_m + 0.5);
    for (std::size_t j = 0; j < i; ++j) EXPECT_GE(footprint_distance(a.obstacles[j], c), cyl.radius_m + 0.5);
  }
  EXPECT_TRUE(differs);
  // The file's seed is the default.
  const Scene f = parse_scene(base(std::string("seed: 11\n") + kColumns), label());
  EXPECT_TRUE(f.obstacles.back().T_parent_shape.isApprox(a.obstacles.back().T_parent_shape));
}

TEST_F(SceneFiles, UnplaceableColumnsAreAnError) {
  expect_error(base("random:\n  - columns: {count: 200, region: {min: [-4, -4], max: [4, 4]}, radius: [0.2, 0.3],\n"
                    "              height: 2.0, min_clearance: 1.0, max_attempts: 50}\n"),
               "random[0].columns");
}

// 1000 columns x 1000 tries passed the count x max_attempts limit but, each try testing every
// column placed before, made 5.4e6 distance tests (15 s under ASan, a fuzzer timeout): all of a
// scene's generators together now stop at SceneLoadOptions::max_footprint_tests.
TEST_F(SceneFiles, ColumnFieldsStopAtTheDistanceTestLimit) {
  const std::string field =
      "  - columns: {count: 150, region: {min: [-4.5, -4.5], max: [4.5, 4.5]}, radius: [0.1, 0.1],\n"
      "              height: 2.0, min_clearance: 0.2, max_attempts: 1000}\n";
  // Within the default limit the field loads.
  const Scene one = parse_scene(base("random:\n" + field), label());
  ASSERT_EQ(one.obstacles.size(), 150u);
  SceneLoadOptions tight;
  tight.max_footprint_tests = 2000;
  try {
    parse_scene(base("random:\n" + field), label(), tight);
    ADD_FAILURE() << "no error";
  } catch (const LoadError& e) {
    EXPECT_EQ(e.file(), label());
    EXPECT_NE(e.element().find("random[0].columns"), std::string::npos) << e.element();
    EXPECT_NE(std::string(e.what()).find("more than 2000 distance tests"), std::string::npos) << e.what();
  }
  // The limit is the scene's: a second generator gets what the first left. Find the tests of one
  // field (the smallest limit that loads it), then two such fields exceed it in the second.
  std::int64_t lo = 0, hi = kSceneMaxFootprintTests;  // fails at lo, loads at hi
  while (hi - lo > 1) {
    SceneLoadOptions o;
    o.max_footprint_tests = lo + (hi - lo) / 2;
    try {
      parse_scene(base("random:\n" + field), label(), o);
      hi = o.max_footprint_tests;
    } catch (const LoadError&) {
      lo = o.max_footprint_tests;
    }
  }
  EXPECT_GT(hi, 2000);
  SceneLoadOptions room_for_one;
  room_for_one.max_footprint_tests = hi + hi / 2;
  expect_error(base("random:\n" + field + field), "random[1].columns", room_for_one);
  // With the default both fields load.
  EXPECT_EQ(parse_scene(base("random:\n" + field + field), label()).obstacles.size(), 300u);
}

TEST(PlaceColumns, StopsBeforeItsTestsCouldPassTheLimit) {
  ColumnFieldSpec spec;
  spec.count = 120;
  spec.region_min_W = Eigen::Vector2d(-4.0, -4.0);
  spec.region_max_W = Eigen::Vector2d(4.0, 4.0);
  spec.radius_min_m = 0.05;
  spec.radius_max_m = 0.2;
  spec.min_clearance_m = 0.3;
  spec.max_attempts = 500;
  std::vector<CollisionShape> existing(1);
  existing[0].geometry = Box{Eigen::Vector3d(0.5, 2.0, 1.0)};
  const std::vector<Eigen::Vector2d> keep_clear = {{-3.5, 0.0}};
  PortableRandom free_rng(4);
  const ColumnFieldResult unlimited = place_columns(spec, existing, keep_clear, free_rng);
  ASSERT_FALSE(unlimited.out_of_tests);
  ASSERT_GT(unlimited.footprint_tests, 1000);
  for (const std::int64_t limit : {std::int64_t{0}, std::int64_t{1}, std::int64_t{500}, unlimited.footprint_tests / 2,
                                   unlimited.footprint_tests - 1, unlimited.footprint_tests}) {
    spec.max_footprint_tests = limit;
    PortableRandom rng(4);
    const ColumnFieldResult r = place_columns(spec, existing, keep_clear, rng);
    SCOPED_TRACE("limit " + std::to_string(limit));
    EXPECT_LE(r.footprint_tests, limit);
    EXPECT_EQ(r.out_of_tests, limit < unlimited.footprint_tests);
    EXPECT_EQ(r.complete, unlimited.complete && !r.out_of_tests);
    // What it placed before stopping is what the unlimited run placed first.
    ASSERT_LE(r.columns.size(), unlimited.columns.size());
    for (std::size_t i = 0; i < r.columns.size(); ++i)
      EXPECT_EQ(r.columns[i].T_parent_shape.matrix(), unlimited.columns[i].T_parent_shape.matrix());
  }
}

TEST(FootprintCost, CountsTheDistanceEvaluationsOfOneFootprintDistance) {
  CollisionShape box;
  box.geometry = Box{Eigen::Vector3d(1.0, 2.0, 3.0)};
  box.T_parent_shape = Eigen::Translation3d(1.0, 2.0, 0.5) * Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ());
  EXPECT_EQ(footprint_cost(box), 1u);  // upright, yawed: a rectangle
  box.T_parent_shape = Eigen::Isometry3d(Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitX()));
  EXPECT_EQ(footprint_cost(box), 12u);  // tilted: the triangles of a box
  CollisionShape cylinder;
  cylinder.geometry = Cylinder{0.3, 1.0};
  EXPECT_EQ(footprint_cost(cylinder), 1u);
  cylinder.T_parent_shape = Eigen::Isometry3d(Eigen::AngleAxisd(1.0, Eigen::Vector3d::UnitY()));
  EXPECT_GE(footprint_cost(cylinder), 128u);  // tilted: a 64-gon prism, two triangles a side at least
  CollisionShape sphere;
  sphere.geometry = Sphere{0.5};
  EXPECT_EQ(footprint_cost(sphere), 1u);
  auto mesh = std::make_shared<TriangleMesh>(shape_to_mesh(box));
  mesh->triangles.resize(7);
  CollisionShape mesh_shape;
  mesh_shape.geometry = MeshShape{mesh};
  EXPECT_EQ(footprint_cost(mesh_shape), 7u);
  // place_columns counts a tilted obstacle at its cost: one try, tested against it only.
  ColumnFieldSpec spec;
  spec.count = 1;
  spec.region_min_W = Eigen::Vector2d(10.0, 10.0);
  spec.region_max_W = Eigen::Vector2d(12.0, 12.0);
  spec.radius_min_m = spec.radius_max_m = 0.1;
  spec.min_clearance_m = 0.1;
  PortableRandom rng(1);
  const ColumnFieldResult r = place_columns(spec, {cylinder}, {}, rng);
  ASSERT_TRUE(r.complete);
  EXPECT_EQ(r.footprint_tests, static_cast<std::int64_t>(footprint_cost(cylinder)));
}

// The rejection sampling as place_columns' contract states it, every test through
// footprint_distance (the slow reference of place_columns' disc test against placed columns).
ColumnFieldResult place_columns_reference(const ColumnFieldSpec& spec, const std::vector<CollisionShape>& existing_W,
                                          const std::vector<Eigen::Vector2d>& keep_clear_xy_W, PortableRandom& rng) {
  ColumnFieldResult result;
  for (int k = 0; k < spec.count; ++k) {
    bool placed = false;
    for (int attempt = 0; attempt < spec.max_attempts && !placed; ++attempt) {
      const double r = rng.uniform(spec.radius_min_m, spec.radius_max_m);
      const double x = rng.uniform(spec.region_min_W.x() + r, spec.region_max_W.x() - r);
      const double y = rng.uniform(spec.region_min_W.y() + r, spec.region_max_W.y() - r);
      if (spec.region_max_W.x() - spec.region_min_W.x() < 2.0 * r ||
          spec.region_max_W.y() - spec.region_min_W.y() < 2.0 * r)
        continue;
      const Eigen::Vector2d c(x, y);
      const double need = r + spec.min_clearance_m;
      bool ok = true;
      for (const auto& p : keep_clear_xy_W) ok = ok && (p - c).norm() >= need;
      for (const auto& o : existing_W) ok = ok && footprint_distance(o, c) >= need;
      for (const auto& o : result.columns) ok = ok && footprint_distance(o, c) >= need;
      if (!ok) continue;
      CollisionShape col;
      col.geometry = Cylinder{r, spec.height_m};
      col.T_parent_shape.translation() = Eigen::Vector3d(x, y, 0.5 * spec.height_m);
      col.name = spec.name_prefix + "[" + std::to_string(k) + "]";
      result.columns.push_back(std::move(col));
      placed = true;
    }
    if (!placed) return result;
  }
  result.complete = true;
  return result;
}

TEST(PlaceColumns, SameFieldsAsEveryTestThroughFootprintDistance) {
  // Existing obstacles of every footprint kind: an upright box, a yawed box, a tilted cylinder,
  // a sphere; fields from sparse to too crowded to complete.
  std::vector<CollisionShape> existing(4);
  existing[0].geometry = Box{Eigen::Vector3d(1.0, 0.3, 2.0)};
  existing[0].T_parent_shape.translation() = Eigen::Vector3d(0.0, 1.0, 1.0);
  existing[1].geometry = Box{Eigen::Vector3d(2.0, 0.2, 1.0)};
  existing[1].T_parent_shape = Eigen::Translation3d(2.0, -2.0, 0.5) * Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ());
  existing[2].geometry = Cylinder{0.2, 1.5};
  existing[2].T_parent_shape = Eigen::Translation3d(-2.0, -1.0, 0.5) * Eigen::AngleAxisd(1.2, Eigen::Vector3d::UnitX());
  existing[3].geometry = Sphere{0.4};
  existing[3].T_parent_shape.translation() = Eigen::Vector3d(-3.0, 3.0, 0.4);
  const std::vector<Eigen::Vector2d> keep_clear = {{-4.0, 0.0}, {4.0, 0.0}};
  int complete = 0, incomplete = 0;
  for (const int count : {5, 40, 150}) {
    for (const double clearance : {0.1, 0.5, 1.2}) {
      for (const std::uint64_t seed : {1u, 2u, 3u}) {
        ColumnFieldSpec spec;
        spec.count = count;
        spec.region_min_W = Eigen::Vector2d(-5.0, -4.0);
        spec.region_max_W = Eigen::Vector2d(5.0, 4.0);
        spec.radius_min_m = 0.05;
        spec.radius_max_m = 0.3;
        spec.height_m = 2.0;
        spec.min_clearance_m = clearance;
        spec.max_attempts = 300;
        PortableRandom fast_rng(seed), slow_rng(seed);
        const ColumnFieldResult fast = place_columns(spec, existing, keep_clear, fast_rng);
        const ColumnFieldResult slow = place_columns_reference(spec, existing, keep_clear, slow_rng);
        SCOPED_TRACE("count " + std::to_string(count) + " clearance " + std::to_string(clearance) + " seed " +
                     std::to_string(seed));
        ASSERT_EQ(fast.complete, slow.complete);
        ASSERT_EQ(fast.columns.size(), slow.columns.size());
        for (std::size_t i = 0; i < fast.columns.size(); ++i) {
          EXPECT_EQ(fast.columns[i].name, slow.columns[i].name);
          EXPECT_EQ(fast.columns[i].T_parent_shape.matrix(), slow.columns[i].T_parent_shape.matrix());
          EXPECT_EQ(std::get<Cylinder>(fast.columns[i].geometry).radius_m,
                    std::get<Cylinder>(slow.columns[i].geometry).radius_m);
        }
        // The draws that follow are the same too: both consumed the same number.
        EXPECT_EQ(fast_rng.next_u64(), slow_rng.next_u64());
        ++(fast.complete ? complete : incomplete);
      }
    }
  }
  // Both outcomes were compared.
  EXPECT_GT(complete, 0);
  EXPECT_GT(incomplete, 0);
}

TEST(PortableRandom, UniformFromRawDraws) {
  PortableRandom r(5);
  std::mt19937_64 e(5);
  for (int k = 0; k < 1000; ++k) {
    const double u = r.uniform(2.0, 3.0);
    EXPECT_EQ(u, 2.0 + static_cast<double>(e() >> 11) * 0x1.0p-53);
    EXPECT_GE(u, 2.0);
    EXPECT_LT(u, 3.0);
  }
  // The standard fixes mt19937_64's 10000th output for the default seed.
  std::mt19937_64 d;
  d.discard(9999);
  EXPECT_EQ(d(), 9981545732273789042ull);
}

}  // namespace
}  // namespace porter
