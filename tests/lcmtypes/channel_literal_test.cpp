// No channel name may be spelled as a string literal outside the registry (DESIGN §2, STYLE 6).

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string_view>
#include <vector>

#include "channel_literal_scan.hpp"
#include "porter/channels.hpp"

namespace porter::test {
namespace {
namespace fs = std::filesystem;

std::vector<std::string_view> registry_names() {
  std::vector<std::string_view> names;
  for (const channels::ChannelInfo& info : channels::kAll) names.push_back(info.name);
  return names;
}

// Paths allowed to spell channel names: the registry itself and these tests (which restate the
// DESIGN table as their specification).
const std::vector<fs::path>& allowed_paths() {
  static const std::vector<fs::path> allowed = {"lcmtypes/include/porter/channels.hpp",
                                                "tests/lcmtypes"};
  return allowed;
}

void write_file(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path) << text;
}

TEST(ChannelLiterals, ScannerFindsPlantedLiteralsAndHonoursExclusions) {
  const fs::path root = fs::temp_directory_path() /
                        ("porter_literal_scan_" +
                         std::to_string(std::chrono::steady_clock::now().time_since_epoch().count()));
  const std::string quoted = std::string("\"") + std::string(channels::kRobotState.name()) + "\"";
  write_file(root / "app/src/main.cpp",
             "int x;\nauto c = " + quoted + ";  // planted\n");
  write_file(root / "app/include/ok.hpp", "auto c = porter::channels::kRobotState;\n");
  write_file(root / "notes.md", "the " + quoted + " channel\n");             // not a source file
  write_file(root / "build-x/gen.hpp", "auto c = " + quoted + ";\n");        // build dir
  write_file(root / "out/CMakeCache.txt", "");
  write_file(root / "out/gen.cpp", "auto c = " + quoted + ";\n");           // build tree
  write_file(root / ".git/x.cpp", "auto c = " + quoted + ";\n");            // hidden
  write_file(root / "lcmtypes/include/porter/channels.hpp", "auto c = " + quoted + ";\n");
  write_file(root / "tests/lcmtypes/t.cpp", "auto c = " + quoted + ";\n");

  const auto findings = find_channel_literals(root, registry_names(), allowed_paths());
  ASSERT_EQ(findings.size(), 1u);
  EXPECT_EQ(findings[0].file, (root / "app/src/main.cpp").lexically_normal());
  EXPECT_EQ(findings[0].line, 2);
  EXPECT_EQ(findings[0].channel, channels::kRobotState.name());
  fs::remove_all(root);
}

TEST(ChannelLiterals, NoneOutsideTheRegistry) {
  const fs::path root = PORTER_SOURCE_DIR;
  ASSERT_TRUE(fs::exists(root / "lcmtypes/include/porter/channels.hpp")) << root;
  const auto findings = find_channel_literals(root, registry_names(), allowed_paths());
  for (const LiteralFinding& f : findings) {
    ADD_FAILURE() << f.file.string() << ":" << f.line << ": channel \"" << f.channel
                  << "\" spelled as a literal; use porter::channels (porter/channels.hpp)";
  }
}

}  // namespace
}  // namespace porter::test
