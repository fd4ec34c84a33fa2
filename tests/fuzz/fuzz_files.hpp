#pragma once
// For fuzz targets of file loaders: a private scratch directory (removed at exit) where each
// input is written before the loader reads it. Include from one source.
//
// The directory is under $TMPDIR when set, else under /dev/shm (tmpfs) when it exists, else
// /tmp. On ext4, rewriting a file in place (open with O_TRUNC) makes the kernel write the new
// data out when the file is closed (the auto_da_alloc heuristic), and that flush took ~3.5 ms
// per input: more than the payload and robot loaders themselves (~240 and ~150 inputs a second
// under ASan, ~1700 and ~1200 with the files in memory). Each write also removes the old file
// first, so no file is ever truncated in place: with TMPDIR on ext4 an input then costs ~1.1 ms
// instead of ~5 ms (an empty STL through load_mesh).

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

namespace porter::fuzz {

class ScratchDir {
 public:
  ScratchDir() {
    dir_ = base() / ("porter_fuzz_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
  std::string write(const std::string& name, const std::uint8_t* data, std::size_t size) const {
    const std::string path = (dir_ / name).string();
    ::unlink(path.c_str());
    std::ofstream(path, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data),
                                                                 static_cast<std::streamsize>(size));
    return path;
  }
  std::string write(const std::string& name, const std::string& text) const {
    return write(name, reinterpret_cast<const std::uint8_t*>(text.data()), text.size());
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

 private:
  static std::filesystem::path base() {
    if (const char* tmp = std::getenv("TMPDIR"); tmp != nullptr && *tmp != '\0') return tmp;
    std::error_code ec;
    if (std::filesystem::is_directory("/dev/shm", ec)) return "/dev/shm";
    return "/tmp";
  }

  std::filesystem::path dir_;
};

inline ScratchDir& scratch() {
  static ScratchDir dir;
  return dir;
}

}  // namespace porter::fuzz
