#include "porter/pipeline/config_dir.hpp"

#include <filesystem>
#include <system_error>

namespace porter::pipeline {

namespace {

namespace fs = std::filesystem;

bool is_config_dir(const fs::path& dir) {
  std::error_code ec;
  return fs::is_regular_file(dir / "planner" / "pipeline.yaml", ec);
}

}  // namespace

std::string find_config_dir() {
  std::error_code ec;
  const fs::path cwd = fs::current_path(ec);
  if (!ec && is_config_dir(cwd / "config")) return (cwd / "config").string();
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return "";
  for (fs::path dir = exe.parent_path(); !dir.empty(); dir = dir.parent_path()) {
    if (is_config_dir(dir / "config")) return (dir / "config").string();
    if (is_config_dir(dir / "share" / "porter" / "config")) return (dir / "share" / "porter" / "config").string();
    if (dir == dir.root_path()) break;
  }
  return "";
}

}  // namespace porter::pipeline
