#include "channel_literal_scan.hpp"

#include <algorithm>
#include <fstream>

namespace porter::test {
namespace fs = std::filesystem;

namespace {

bool is_source(const fs::path& p) {
  static const std::vector<std::string> kExtensions = {".c",   ".cc",  ".cpp", ".cxx",
                                                       ".h",   ".hh",  ".hpp", ".hxx"};
  return std::find(kExtensions.begin(), kExtensions.end(), p.extension().string()) !=
         kExtensions.end();
}

bool is_skipped_directory(const fs::path& dir) {
  const std::string name = dir.filename().string();
  if (!name.empty() && name[0] == '.') return true;
  if (name.rfind("build", 0) == 0) return true;
  std::error_code ec;
  return fs::exists(dir / "CMakeCache.txt", ec);
}

}  // namespace

std::vector<LiteralFinding> find_channel_literals(const fs::path& root,
                                                  const std::vector<std::string_view>& channel_names,
                                                  const std::vector<fs::path>& excluded) {
  std::vector<fs::path> excluded_abs;
  for (const fs::path& e : excluded) excluded_abs.push_back((root / e).lexically_normal());

  std::vector<std::string> quoted;
  for (std::string_view name : channel_names) quoted.push_back("\"" + std::string(name) + "\"");

  std::vector<LiteralFinding> findings;
  auto it = fs::recursive_directory_iterator(root, fs::directory_options::skip_permission_denied);
  for (; it != fs::recursive_directory_iterator(); ++it) {
    const fs::path path = it->path().lexically_normal();
    if (std::find(excluded_abs.begin(), excluded_abs.end(), path) != excluded_abs.end()) {
      if (it->is_directory()) it.disable_recursion_pending();
      continue;
    }
    if (it->is_directory()) {
      if (is_skipped_directory(path)) it.disable_recursion_pending();
      continue;
    }
    if (!it->is_regular_file() || !is_source(path)) continue;
    std::ifstream in(path);
    std::string line;
    int line_number = 0;
    while (std::getline(in, line)) {
      ++line_number;
      for (std::size_t i = 0; i < quoted.size(); ++i) {
        if (line.find(quoted[i]) != std::string::npos) {
          findings.push_back({path, line_number, std::string(channel_names[i])});
        }
      }
    }
  }
  return findings;
}

}  // namespace porter::test
