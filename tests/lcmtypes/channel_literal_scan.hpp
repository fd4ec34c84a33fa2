#pragma once
// Finds channel names spelled as string literals ("ROBOT_STATE") in C++ sources, to enforce that
// channels are named only in the registry (lcmtypes/include/porter/channels.hpp).

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace porter::test {

struct LiteralFinding {
  std::filesystem::path file;
  int line = 0;
  std::string channel;
};

/// Scans C/C++ sources (.c .cc .cpp .cxx .h .hh .hpp .hxx) under `root` for `"<name>"`, for each
/// name in `channel_names`. Skips: hidden directories (.git, ...), directories whose name starts
/// with "build", directories holding a CMakeCache.txt (any build tree), and the paths in
/// `excluded` (files or directories, relative to `root`).
std::vector<LiteralFinding> find_channel_literals(const std::filesystem::path& root,
                                                  const std::vector<std::string_view>& channel_names,
                                                  const std::vector<std::filesystem::path>& excluded);

}  // namespace porter::test
