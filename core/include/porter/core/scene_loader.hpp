#pragma once
// Scene files (config/scenes/*.yaml; format in config/scenes/README.md) -> Scene. Part of
// porter::core_io.
//
// Strict: an unknown key, a missing field, a wrong type, a negative or zero size or
// resolution, bounds with min >= max, an unknown parameter reference or override, or random
// columns that cannot all be placed throw LoadError naming the file and the key path
// (e.g. "key 'obstacles[3].box.size'").
//
// Thread-safety: reentrant.

#include <cstdint>
#include <map>
#include <optional>
#include <string>

#include "porter/core/scene.hpp"

namespace porter {

struct SceneLoadOptions {
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
