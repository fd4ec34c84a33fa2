// Fuzz target: parse_scene on any text (a scratch directory holds the payload file the seeds
// name). It must return a scene or throw LoadError naming the file; a scene it returns must
// have finite bounds, a resolution within the limits, wrapped yaws, and voxelize within the
// memory cap; its random columns stay within the distance-test limit.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "fuzz_files.hpp"
#include "porter/core/load_error.hpp"
#include "porter/core/scene_loader.hpp"
#include "porter/core/scene_voxelizer.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string payload = porter::fuzz::scratch().write("payload.yaml", "name: dummy\n");
  static const std::string label = porter::fuzz::scratch().path("scene.yaml");
  const std::string text(reinterpret_cast<const char*>(data), size);
  porter::SceneLoadOptions options;
  // 2 MiB (262 144 voxels): every accepted scene is voxelized, and a cap of 64 MiB let each run
  // fill up to 8e6 voxels, milliseconds per input. The check is the same at any cap; the coarse
  // seeds (coarse_*.yaml) fit under this one, the shipped ones exercise the refusal.
  options.memory_cap_bytes = 2.0 * (1 << 20);
  // 5e4 distance tests for the random columns (default 1e7, ~40 ms in Release): one costs
  // ~2-3 us under ASan + UBSan + coverage, so 1e7 took ~30 s, a timeout, and 5e4 stays under
  // ~0.15 s. The limit's check is the same at any value; the forest seeds need ~6e3.
  options.max_footprint_tests = 50'000;
  try {
    const porter::Scene s = porter::parse_scene(text, label, options);
    if (!s.bounds_W.min().allFinite() || !s.bounds_W.max().allFinite()) std::abort();
    if (!(s.resolution_m >= porter::kSceneMinResolution_m && s.resolution_m <= porter::kSceneMaxResolution_m))
      std::abort();
    for (const double yaw : {s.start.base.yaw_rad, s.goal.base.yaw_rad})
      if (!(std::abs(yaw) <= 3.14159265358979323846 + 1e-12)) std::abort();
    if (s.obstacles.size() < 50) porter::voxelize(s);  // bounded: the cap holds the grid small
  } catch (const porter::LoadError& e) {
    if (e.file() != label) std::abort();
  }
  return 0;
}
