#pragma once
// Helpers shared by the robot-model tests: paths of the shipped configs, and scratch files.

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

namespace porter::test {

inline std::string source_dir() {
  const char* env = std::getenv("PORTER_SOURCE_DIR");
  return env ? env : PORTER_SOURCE_DIR;
}

inline std::string robot_yaml() { return source_dir() + "/config/robots/scout_mini_piper/robot.yaml"; }
inline std::string payload_yaml(const std::string& name) {
  return source_dir() + "/config/payloads/" + name + ".yaml";
}

/// A fresh directory under the system temp dir, removed when the object dies.
class ScratchDir {
 public:
  explicit ScratchDir(const std::string& tag) {
    path_ = std::filesystem::temp_directory_path() /
            ("porter_" + tag + "_" + std::to_string(std::rand()) + "_" + std::to_string(::getpid()));
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() { std::filesystem::remove_all(path_); }
  std::string file(const std::string& name, const std::string& content) const {
    const auto p = path_ / name;
    std::ofstream(p) << content;
    return p.string();
  }
  std::string path(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

}  // namespace porter::test
