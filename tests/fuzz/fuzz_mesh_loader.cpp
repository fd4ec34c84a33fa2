// Fuzz target: load_mesh on any bytes. The first byte picks the file extension (assimp chooses
// its importer by it): ply, stl, obj, off, dae. A mesh it returns must be finite with in-range
// triangle indices; anything it refuses must be a LoadError naming the file.
#include <cstdint>
#include <cstdlib>
#include <string>

#include "fuzz_files.hpp"
#include "porter/core/load_error.hpp"
#include "porter/core/mesh_loader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static const char* const kExtensions[] = {"ply", "stl", "obj", "off", "dae"};
  const std::string path = porter::fuzz::scratch().write(std::string("mesh.") + kExtensions[data[0] % 5], data + 1, size - 1);
  try {
    const porter::MeshPtr mesh = porter::load_mesh(path);
    if (!mesh || mesh->triangles.empty()) std::abort();
    const int n = static_cast<int>(mesh->vertices_m.size());
    for (const auto& v : mesh->vertices_m)
      if (!v.allFinite()) std::abort();
    for (const auto& t : mesh->triangles)
      if ((t.array() < 0).any() || (t.array() >= n).any()) std::abort();
  } catch (const porter::LoadError& e) {
    if (e.file() != path) std::abort();
  }
  return 0;
}
