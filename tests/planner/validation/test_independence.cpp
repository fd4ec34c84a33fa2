// The validator shares no code with the planner: none of its sources includes a planner header
// or the core's kinematics and trajectory code (it may use the core's geometry, model and
// loaders). The link side is checked at configure time (planner/validation/CMakeLists.txt).
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace {

TEST(ValidationIndependence, SourcesIncludeNoPlannerOrCoreKinematicsOrTrajectoryCode) {
  namespace fs = std::filesystem;
  const fs::path root = fs::path(PORTER_SOURCE_DIR) / "planner" / "validation";
  ASSERT_TRUE(fs::is_directory(root));
  const std::vector<std::string> allowed_core = {
      "porter/core/geometry.hpp",       "porter/core/robot_model.hpp",  "porter/core/payload.hpp",
      "porter/core/scene.hpp",          "porter/core/types.hpp",        "porter/core/load_error.hpp",
      "porter/core/robot_loader.hpp",   "porter/core/payload_loader.hpp", "porter/core/scene_loader.hpp"};
  const std::regex include_re(R"(^\s*#\s*include\s*[<"]([^>"]+)[>"])");
  int files = 0, includes = 0;
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    const std::string ext = entry.path().extension().string();
    if (ext != ".cpp" && ext != ".hpp") continue;
    ++files;
    std::ifstream in(entry.path());
    std::string line;
    while (std::getline(in, line)) {
      std::smatch m;
      if (!std::regex_search(line, m, include_re)) continue;
      const std::string inc = m[1];
      ++includes;
      if (inc.rfind("porter/", 0) != 0) continue;
      const bool own = inc.rfind("porter/validation/", 0) == 0;
      const bool core_ok = std::find(allowed_core.begin(), allowed_core.end(), inc) != allowed_core.end();
      EXPECT_TRUE(own || core_ok) << entry.path() << " includes " << inc;
    }
  }
  EXPECT_GE(files, 10);
  EXPECT_GE(includes, 30);
}

}  // namespace
