#pragma once
// For config-loader tests: every number a shipped config file holds, replaced in turn by hostile
// values, in a private copy of config/ (so the paths the file names, relative to it, resolve as
// in the tree). The number is replaced in the text where it stands (comments and layout kept).
//
//   porter::test::check_hostile_numbers("tracker/porter_tracker.yaml",
//       [](const std::string& file) { porter::tracker_app::load_tracker_config(file); });
//
// Every number set to NaN, +-infinity or +-1e300 must be refused with a LoadError naming the
// file; set to 0, -1, 1e-300, +-1e9 or 0.5 it may be loaded or refused, again only by a
// LoadError naming the file (anything else fails the test; a crash or a sanitizer report ends
// it). Returns the number of values replaced, so a test can check it found them. A loader that
// checks several files together may name `also_named` instead (e.g. "DIR/*.yaml").

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "porter/core/load_error.hpp"

namespace porter::test {

/// A private copy of the source tree's config/ under the temporary directory, removed at the end.
class ConfigCopy {
 public:
  ConfigCopy() {
    static int serial = 0;
    dir_ = std::filesystem::temp_directory_path() /
           ("porter_config_" + std::to_string(::getpid()) + "_" + std::to_string(serial++));
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
    std::filesystem::copy(std::string(PORTER_SOURCE_DIR) + "/config", dir_ / "config",
                          std::filesystem::copy_options::recursive);
  }
  ~ConfigCopy() {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
  ConfigCopy(const ConfigCopy&) = delete;
  ConfigCopy& operator=(const ConfigCopy&) = delete;
  /// A path inside the copy, relative to config/.
  std::string path(const std::string& relative) const { return (dir_ / "config" / relative).string(); }

 private:
  std::filesystem::path dir_;
};

/// A plain scalar of a YAML document that reads whole as a number: its key path and where its
/// text stands.
struct NumberSite {
  std::string key;
  std::string text;
  std::size_t offset = 0;
  std::size_t length = 0;
};

inline void find_numbers(const YAML::Node& node, const std::string& key, std::vector<NumberSite>& out) {
  if (node.IsMap()) {
    for (const auto& kv : node) find_numbers(kv.second, key.empty() ? kv.first.Scalar() : key + "." + kv.first.Scalar(), out);
  } else if (node.IsSequence()) {
    for (std::size_t i = 0; i < node.size(); ++i) find_numbers(node[i], key + "[" + std::to_string(i) + "]", out);
  } else if (node.IsScalar() && node.Tag() == "?") {
    const std::string& s = node.Scalar();
    char* end = nullptr;
    std::strtod(s.c_str(), &end);
    if (!s.empty() && end == s.c_str() + s.size()) {
      out.push_back({key, s, static_cast<std::size_t>(node.Mark().pos), s.size()});
    }
  }
}

inline int check_hostile_numbers(const std::string& relative, const std::function<void(const std::string&)>& load,
                                 const std::string& also_named = "") {
  const ConfigCopy copy;
  const std::string file = copy.path(relative);
  std::ifstream in(file, std::ios::binary);
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  std::vector<NumberSite> sites;
  find_numbers(YAML::Load(text), "", sites);

  const auto run = [&](const NumberSite& site, const std::string& value, bool must_refuse) {
    std::string mutated = text;
    mutated.replace(site.offset, site.length, value);
    std::ofstream(file, std::ios::binary | std::ios::trunc) << mutated;
    const std::string what = relative + ": " + site.key + " = " + value;
    try {
      load(file);
      if (must_refuse) ADD_FAILURE() << what << " was accepted";
    } catch (const LoadError& e) {
      if (e.file() != file && (also_named.empty() || e.file() != (std::filesystem::path(file).parent_path() / also_named).string())) {
        ADD_FAILURE() << what << ": the error names another file: " << e.what();
      }
    } catch (const std::exception& e) {
      ADD_FAILURE() << what << ": not a LoadError: " << e.what();
    }
  };
  int replaced = 0;
  for (const NumberSite& site : sites) {
    if (text.compare(site.offset, site.length, site.text) != 0) {
      ADD_FAILURE() << relative << ": " << site.key << ": the number is not at byte " << site.offset;
      continue;
    }
    for (const char* v : {".nan", ".inf", "-.inf", "1e300", "-1e300"}) {
      run(site, v, true);
      ++replaced;
    }
    for (const char* v : {"0", "-1", "1e-300", "1e9", "-1e9", "0.5"}) {
      run(site, v, false);
      ++replaced;
    }
  }
  std::ofstream(file, std::ios::binary | std::ios::trunc) << text;
  return replaced;
}

}  // namespace porter::test
