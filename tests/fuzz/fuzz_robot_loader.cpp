// Fuzz target: load_robot_model. Input: a URDF, or "<robot.yaml>\n#URDF\n<URDF>" to fuzz both
// files; without the marker the robot.yaml is the shipped one (it names scout_mini_piper.urdf).
// It must return a model or throw LoadError naming a file.
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "fuzz_files.hpp"
#include "porter/core/load_error.hpp"
#include "porter/core/robot_loader.hpp"

namespace {
std::string shipped_robot_yaml() {
  std::ifstream in(std::string(PORTER_SOURCE_DIR) + "/config/robots/scout_mini_piper/robot.yaml");
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string shipped = shipped_robot_yaml();
  const std::string text(reinterpret_cast<const char*>(data), size);
  const std::string marker = "\n#URDF\n";
  const std::size_t at = text.find(marker);
  const std::string yaml = at == std::string::npos ? shipped : text.substr(0, at);
  const std::string urdf = at == std::string::npos ? text : text.substr(at + marker.size());
  porter::fuzz::scratch().write("scout_mini_piper.urdf", urdf);
  const std::string path = porter::fuzz::scratch().write("robot.yaml", yaml);
  try {
    const porter::RobotModel m = porter::load_robot_model(path);
    for (const auto& link : m.links)
      if (!(link.bounding_radius_m >= 0.0 && link.bounding_radius_m < 1e3)) std::abort();
  } catch (const porter::LoadError& e) {
    if (e.file().empty()) std::abort();
  }
  return 0;
}
