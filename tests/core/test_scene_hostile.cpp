// Hostile and careless scene files: every one is refused with the file and the key, or (angles)
// wrapped, before anything is allocated over the scene's bounds.

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include <gtest/gtest.h>

#include "porter/core/load_error.hpp"
#include "porter/core/scene_loader.hpp"
#include "porter/core/scene_voxelizer.hpp"

namespace porter {
namespace {

namespace fs = std::filesystem;

class HostileScenes : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("porter_hostile_scene_" + std::to_string(std::random_device{}()));
    fs::create_directories(dir_);
    std::ofstream(dir_ / "payload.yaml") << "name: dummy\n";
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string label() const { return (dir_ / "scene.yaml").string(); }

  static std::string scene(const std::string& start_base = "[-4, 0, 0]", const std::string& resolution = "0.1",
                           const std::string& bounds = "{min: [-5, -5, 0], max: [5, 5, 3]}",
                           const std::string& extra = "") {
    return "name: t\nbounds: " + bounds + "\nresolution: " + resolution + "\nstart: {base: " + start_base +
           ", arm: [0, 0.6, -0.9, 0, 0.5, 0]}\ngoal: {base: [4, 0, 0], arm: [0, 0.6, -0.9, 0, 0.5, 0]}\n"
           "payload: payload.yaml\n" + extra;
  }

  /// The LoadError parse_scene throws; fails the test when there is none or it names another file.
  LoadError error_of(const std::string& text, const SceneLoadOptions& opts = {}) {
    try {
      parse_scene(text, label(), opts);
    } catch (const LoadError& e) {
      EXPECT_EQ(e.file(), label());
      return e;
    }
    ADD_FAILURE() << "accepted:\n" << text;
    return LoadError("", "", "");
  }

  void expect_error(const std::string& text, const std::string& key, const std::string& reason,
                    const SceneLoadOptions& opts = {}) {
    const LoadError e = error_of(text, opts);
    EXPECT_NE(e.element().find(key), std::string::npos) << e.what();
    EXPECT_NE(e.reason().find(reason), std::string::npos) << e.what();
  }

  fs::path dir_;
};

constexpr double kPi = 3.14159265358979323846;

// A start yaw of 1e11 rad aborted in OMPL and 1e18 overflowed an int in the planner: yaws are
// wrapped when loaded.
TEST_F(HostileScenes, HugeStartAndGoalYawsAreWrapped) {
  for (const double yaw : {1e11, -1e11, 1e4, 3 * kPi}) {
    std::ostringstream base;
    base.precision(17);
    base << "[-4, 0, " << yaw << "]";
    const double expected = std::remainder(yaw, 2 * kPi);
    if (std::abs(yaw) > kSceneMaxMagnitude_m) {
      expect_error(scene(base.str()), "start.base[2]", "must be within");
      continue;
    }
    const Scene s = parse_scene(scene(base.str()), label());
    EXPECT_GT(s.start.base.yaw_rad, -kPi);
    EXPECT_LE(s.start.base.yaw_rad, kPi);
    EXPECT_NEAR(std::remainder(s.start.base.yaw_rad - expected, 2 * kPi), 0.0, 1e-9) << yaw;
  }
  expect_error(scene("[-4, 0, 1e18]"), "start.base[2]", "must be within +-10000");
}

// `z: [0, .inf]` overflowed in voxel_range, and an -O2 build dropped the obstacle silently.
TEST_F(HostileScenes, InfiniteAndHugeNumbersAreRefused) {
  expect_error(scene("[-4, 0, 0]", "0.1", "{min: [-5, -5, 0], max: [5, 5, 3]}",
                     "obstacles:\n  - cylinder: {center: [0, 0], radius: 0.2, z: [0, .inf]}\n"),
               "obstacles[0].cylinder.z[1]", "expected a number");
  expect_error(scene("[-4, 0, 0]", "0.1", "{min: [-5, -5, 0], max: [5, 5, 3]}",
                     "obstacles:\n  - cylinder: {center: [0, 0], radius: 0.2, z: [0, 1e308]}\n"),
               "obstacles[0].cylinder.z[1]", "must be within");
  expect_error(scene("[-4, 0, 0]", "0.1", "{min: [-5, -5, 0], max: [5, 5, 3]}",
                     "obstacles:\n  - box: {center: [0, 0, 1], size: [1e9, 1, 1]}\n"),
               "obstacles[0].box.size[0]", "must be within");
  expect_error(scene("[-4, 0, 0]", "0.1", "{min: [-5, -5, 0], max: [5, 5, nan]}"), "bounds.max[2]",
               "expected a number");
  expect_error(scene("[-4, 0, 0]", "0.1", "{min: [-5, -5, 0], max: [5, 5, 3]}", "parameters: {h: 1e300}\n"),
               "parameters.h", "must be within");
  SceneLoadOptions o;
  o.parameter_overrides["h"] = 1e300;
  expect_error(scene("[-4, 0, 0]", "0.1", "{min: [-5, -5, 0], max: [5, 5, 3]}", "parameters: {h: 1}\n"),
               "parameters.h", "override", o);
  // Within the limits the tall cylinder loads and is in the map (it used to vanish).
  const Scene s = parse_scene(scene("[-4, 0, 0]", "0.1", "{min: [-5, -5, 0], max: [5, 5, 3]}",
                                    "obstacles:\n  - cylinder: {center: [0, 0], radius: 0.2, z: [0, 10000]}\n"),
                              label());
  const OccupancyGrid grid = voxelize(s);
  Eigen::Vector3i idx;
  ASSERT_TRUE(grid.world_to_index_checked(Eigen::Vector3d(0.01, 0.01, 1.5), &idx));
  EXPECT_TRUE(grid.occupied(idx.x(), idx.y(), idx.z()));
}

// resolution 1e18 overflowed in the planner; 1 cm over large bounds took minutes; maps of
// 1.5e9 voxels (4.6 GB) were accepted.
TEST_F(HostileScenes, ResolutionAndMapSizeAreBoundedBeforeAllocating) {
  expect_error(scene("[-4, 0, 0]", "1e18"), "resolution", "must be within");
  expect_error(scene("[-4, 0, 0]", "2"), "resolution", "must be within [0.005, 1] m");
  expect_error(scene("[-4, 0, 0]", "0.001"), "resolution", "must be within");
  const std::string big = "{min: [-500, -500, 0], max: [500, 500, 3]}";
  const LoadError e = error_of(scene("[-4, 0, 0]", "0.01", big));
  EXPECT_EQ(e.element(), "key 'resolution'");
  EXPECT_NE(e.reason().find("3e+12 voxels"), std::string::npos) << e.what();
  EXPECT_NE(e.reason().find("memory cap of 2048 MiB"), std::string::npos) << e.what();
  // The cap is the caller's: 10 x 10 x 3 m at 10 cm is 300 000 voxels, 2.3 MiB of maps.
  SceneLoadOptions small;
  small.memory_cap_bytes = 2e6;
  expect_error(scene(), "resolution", "about 2.28882 MiB of maps at 8 B per voxel, above the memory cap of 1.90735 MiB",
               small);
  small.memory_cap_bytes = 3e6;
  EXPECT_NO_THROW(parse_scene(scene(), label(), small));
}

// count / max_attempts up to 1e9 spun for ever.
TEST_F(HostileScenes, RandomColumnCountsAreBounded) {
  const std::string region = "region: {min: [-4, -4], max: [4, 4]}, radius: [0.1, 0.2], height: 2, min_clearance: 0.1";
  expect_error(scene("[-4, 0, 0]", "0.1", "{min: [-5, -5, 0], max: [5, 5, 3]}",
                     "random:\n  - columns: {count: 1000000000, " + region + "}\n"),
               "random[0].columns.count", "must be at most 1000");
  expect_error(scene("[-4, 0, 0]", "0.1", "{min: [-5, -5, 0], max: [5, 5, 3]}",
                     "random:\n  - columns: {count: 3, max_attempts: 1000000000, " + region + "}\n"),
               "random[0].columns.max_attempts", "must be at most 100000");
  expect_error(scene("[-4, 0, 0]", "0.1", "{min: [-5, -5, 0], max: [5, 5, 3]}",
                     "random:\n  - columns: {count: 1000, max_attempts: 100000, " + region + "}\n"),
               "random[0].columns", "placement tries");
}

// yaml-cpp keeps the first of two equal keys: a repeated key would silently lose its value.
TEST_F(HostileScenes, RepeatedAndNonScalarKeysAreRefused) {
  expect_error(scene() + "resolution: 0.5\n", "resolution", "appears twice");
  expect_error(scene("[-4, 0, 0]", "0.1", "{min: [-5, -5, 0], max: [5, 5, 3], min: [0, 0, 0]}"), "bounds.min",
               "appears twice");
  const LoadError e = error_of(scene() + "? [a, b]\n: 1\n");
  EXPECT_NE(e.reason().find("a map key must be a plain name"), std::string::npos) << e.what();
}

TEST_F(HostileScenes, ADirectoryOrAnAliasBombNamesTheFile) {
  try {
    load_scene(dir_.string());
    ADD_FAILURE();
  } catch (const LoadError& e) {
    EXPECT_EQ(e.file(), dir_.string());
    EXPECT_NE(e.reason().find("not a regular file"), std::string::npos) << e.what();
  }
  std::string bomb = "a: &a [x, x, x, x, x, x, x, x, x, x]\n";
  for (char c = 'b'; c <= 'i'; ++c)
    bomb += std::string(1, c) + ": &" + c + " [*" + char(c - 1) + ", *" + char(c - 1) + ", *" + char(c - 1) +
            ", *" + char(c - 1) + ", *" + char(c - 1) + ", *" + char(c - 1) + ", *" + char(c - 1) + ", *" +
            char(c - 1) + ", *" + char(c - 1) + ", *" + char(c - 1) + "]\n";
  const LoadError e = error_of(bomb);
  EXPECT_NE(e.reason().find("YAML nodes"), std::string::npos) << e.what();
}

}  // namespace
}  // namespace porter
