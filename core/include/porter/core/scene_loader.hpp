#pragma once
// Scene files (config/scenes/*.yaml; format in config/scenes/README.md) -> Scene. Part of
// porter::core_io.
//
// Strict: an unknown key, a repeated key, a missing field, a wrong type, a negative or zero
// size or resolution, a number outside the limits below, bounds with min >= max, maps that would
// need more memory than the cap, an unknown parameter reference or override, or random columns
// that cannot all be placed throw LoadError naming the file and the key path
// (e.g. "key 'obstacles[3].box.size'").
//
// Thread-safety: reentrant.

#include <cstdint>
#include <map>
#include <optional>
#include <string>

#include "porter/core/scene.hpp"

namespace porter {

/// Limits of a scene file, each refused with the figure (docs/hardening.md says why):
/// - every number (coordinates, sizes, radii, parameters) within +-kSceneMaxMagnitude_m: 10 km
///   is beyond any site the robot drives, and keeps voxel indices and products far from
///   overflow;
/// - resolution in [kSceneMinResolution_m, kSceneMaxResolution_m] (the planner's kernels need
///   the same range), and the voxel count times kSceneBytesPerVoxel within
///   SceneLoadOptions::memory_cap_bytes;
/// - random columns: count <= kSceneMaxColumns, max_attempts <= kSceneMaxAttempts and
///   count * max_attempts <= kSceneMaxPlacementTries (each try tests every placed obstacle), and
///   at most SceneLoadOptions::max_footprint_tests distance tests by all of a scene's
///   generators together (a try's tests grow with the obstacles placed and a tilted or mesh
///   obstacle costs its triangles: 1000 columns x 1000 tries took 15 s under ASan);
/// - yaws (start, goal, boxes, bridges) are wrapped to (-pi, pi].
inline constexpr double kSceneMaxMagnitude_m = 1e4;
inline constexpr double kSceneMinResolution_m = 0.005;
inline constexpr double kSceneMaxResolution_m = 1.0;
/// Memory a voxel of the scene's bounds costs once the planner builds its maps over them:
/// occupancy and kernel sets (bits), summed-area table (2 B), clearance (1 B), distance field
/// (4 B), rounded up.
inline constexpr double kSceneBytesPerVoxel = 8.0;
inline constexpr int kSceneMaxColumns = 1000;
inline constexpr int kSceneMaxAttempts = 100000;
inline constexpr double kSceneMaxPlacementTries = 1e6;
/// Default of SceneLoadOptions::max_footprint_tests: 3x the 3e6 tests of 1000 columns with
/// 5 cm clearance in the forest's field (1e7 take about 40 ms in a Release build).
inline constexpr std::int64_t kSceneMaxFootprintTests = 10'000'000;

struct SceneLoadOptions {
  /// Largest memory the scene's maps may need (voxels x kSceneBytesPerVoxel), bytes.
  double memory_cap_bytes = 2.0 * (1u << 30);
  /// Largest number of distance tests the scene's random generators may make together (each
  /// try of a column tests it against every keep-clear point, obstacle and placed column).
  std::int64_t max_footprint_tests = kSceneMaxFootprintTests;
  /// Seed of the random generators; when absent the file's `seed` (default 0) is used.
  std::optional<std::uint64_t> seed;
  /// Values replacing the defaults of the file's `parameters`; naming a parameter the file does
  /// not declare is an error.
  std::map<std::string, double> parameter_overrides;
};

/// Loads a scene file; relative paths inside it (payload, meshes) are resolved against the
/// file's directory.
Scene load_scene(const std::string& path, const SceneLoadOptions& options = {});

/// Parses scene YAML held in memory. `file_label` names it in errors and is the base for
/// relative paths (as if the text had been read from that file).
Scene parse_scene(const std::string& yaml_text, const std::string& file_label,
                  const SceneLoadOptions& options = {});

}  // namespace porter
