#include "ply_header.hpp"

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <vector>

#include "porter/core/mesh_loader.hpp"

namespace porter::detail {
namespace {

constexpr std::size_t kMaxHeaderBytes = 64 * 1024;

// Bytes of one value of a PLY scalar type; 0 for an unknown type name.
int type_size(const std::string& t) {
  static const std::map<std::string, int> sizes = {
      {"char", 1}, {"uchar", 1}, {"int8", 1}, {"uint8", 1}, {"short", 2}, {"ushort", 2}, {"int16", 2},
      {"uint16", 2}, {"int", 4}, {"uint", 4}, {"int32", 4}, {"uint32", 4}, {"float", 4}, {"float32", 4},
      {"double", 8}, {"float64", 8}};
  const auto it = sizes.find(t);
  return it == sizes.end() ? 0 : it->second;
}

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::uint64_t min_bytes = 0;  // least bytes one element takes in the body
};

}  // namespace

std::string check_ply_header(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return {};
  std::string magic;
  if (!std::getline(in, magic) || (magic != "ply" && magic != "ply\r")) return {};

  bool binary = false, have_format = false;
  std::vector<Element> elements;
  std::string line;
  std::size_t header_bytes = magic.size() + 1;
  bool ended = false;
  while (std::getline(in, line)) {
    header_bytes += line.size() + 1;
    if (header_bytes > kMaxHeaderBytes) return "PLY header longer than 64 kB";
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream words(line);
    std::string word;
    words >> word;
    if (word == "end_header") {
      ended = true;
      break;
    }
    if (word == "format") {
      std::string format;
      words >> format;
      if (format == "ascii") {
        binary = false;
      } else if (format == "binary_little_endian" || format == "binary_big_endian") {
        binary = true;
      } else {
        return "PLY format '" + format + "' unknown";
      }
      have_format = true;
    } else if (word == "element") {
      Element e;
      std::string count;
      words >> e.name >> count;
      if (count.empty() || count.find_first_not_of("0123456789") != std::string::npos || count.size() > 18)
        return "PLY element '" + e.name + "' has count '" + count + "', not a non-negative integer";
      e.count = std::stoull(count);
      elements.push_back(e);
    } else if (word == "property") {
      if (elements.empty()) return "PLY property before any element";
      std::string type;
      words >> type;
      int bytes = 0;
      if (type == "list") {
        std::string count_type, item_type;
        words >> count_type >> item_type;
        if (type_size(count_type) == 0 || type_size(item_type) == 0)
          return "PLY list property of unknown type '" + count_type + " " + item_type + "'";
        bytes = type_size(count_type);  // a list may be empty: its count alone
      } else {
        bytes = type_size(type);
        if (bytes == 0) return "PLY property of unknown type '" + type + "'";
      }
      // ASCII: a value takes at least one character and one separator.
      elements.back().min_bytes += binary ? static_cast<std::uint64_t>(bytes) : 2u;
    }
  }
  if (!ended) return "PLY header has no end_header";
  if (!have_format) return "PLY header has no format line";

  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec || size < header_bytes) return {};
  const std::uint64_t body = size - header_bytes;
  std::uint64_t needed = 0;
  for (const Element& e : elements) {
    if (e.name == "vertex" && e.count > kMeshMaxVertices)
      return "PLY header claims " + std::to_string(e.count) + " vertices (limit " +
             std::to_string(kMeshMaxVertices) + ")";
    if (e.name == "face" && e.count > kMeshMaxFaces)
      return "PLY header claims " + std::to_string(e.count) + " faces (limit " + std::to_string(kMeshMaxFaces) + ")";
    if (e.count > (std::uint64_t{1} << 40)) return "PLY element '" + e.name + "' count is absurd";
    needed += e.count * e.min_bytes;
    if (needed > body)
      return "PLY header claims " + std::to_string(e.count) + " '" + e.name + "' elements, which need at least " +
             std::to_string(needed) + " bytes; the file has " + std::to_string(body) + " after its header";
  }
  return {};
}

}  // namespace porter::detail
