#pragma once
// Reads a payload YAML (config/payloads/*.yaml). Part of porter::core_io.
//
//   name: t_bar
//   mesh: {file: meshes/t_bar.stl, scale: 1.0}      # or scale: [sx, sy, sz]
//   # ... or, instead of mesh, primitives in the payload frame:
//   # shapes:
//   #   - box: {size: [sx, sy, sz], pose: {xyz: [..], rpy: [..]}}
//   #   - cylinder: {radius: r, length: l, pose: {...}}
//   #   - sphere: {radius: r, pose: {...}}
//   grasp: {xyz: [x, y, z], rpy: [r, p, y]}          # pose of the payload frame in EE
//
// Exactly one of `mesh` and `shapes`. Paths are relative to the YAML file. Throws LoadError
// naming the file and key on any missing, unknown or invalid entry.

#include <string>

#include "porter/core/payload.hpp"

namespace porter {

Payload load_payload(const std::string& payload_yaml_path);

}  // namespace porter
