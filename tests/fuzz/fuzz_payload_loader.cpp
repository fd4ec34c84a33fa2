// Fuzz target: load_payload on any YAML text. It must return a payload within the reach limit or
// throw LoadError naming a file.
#include <cstdint>
#include <cstdlib>
#include <string>

#include "fuzz_files.hpp"
#include "porter/core/geometry.hpp"
#include "porter/core/load_error.hpp"
#include "porter/core/payload_loader.hpp"
#include "porter/core/robot_loader.hpp"

namespace {
// The shipped meshes, where the shipped payload seeds look for them (meshes/<file>).
bool copy_meshes() {
  const std::filesystem::path to = porter::fuzz::scratch().path("meshes");
  std::filesystem::create_directories(to);
  for (const char* f : {"arc.ply", "long_bar.obj", "t_bar.stl"})
    std::filesystem::copy_file(std::string(PORTER_SOURCE_DIR) + "/config/payloads/meshes/" + f, to / f,
                               std::filesystem::copy_options::overwrite_existing);
  return true;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const bool meshes = copy_meshes();
  (void)meshes;
  const std::string path = porter::fuzz::scratch().write("payload.yaml", data, size);
  try {
    const porter::Payload p = porter::load_payload(path);
    if (p.shapes.empty()) std::abort();
    for (const auto& shape : p.shapes)
      if (!(porter::shape_max_distance(shape, Eigen::Vector3d::Zero()) <= porter::kRobotMaxReach_m)) std::abort();
  } catch (const porter::LoadError& e) {
    if (e.file().empty()) std::abort();
  }
  return 0;
}
