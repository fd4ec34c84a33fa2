#include "ply_header.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <string>
#include <utility>
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

// One property of an element: a scalar, or a list (its count's type, then its items' type).
struct Property {
  bool list = false;
  std::string count_type;  // list only
  int bytes = 0;           // scalar: the value's; list: one item's
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::uint64_t min_bytes = 0;  // least bytes one element takes in the body
  std::vector<Property> properties;
};

bool is_signed_type(const std::string& t) {
  return t == "char" || t == "int8" || t == "short" || t == "int16" || t == "int" || t == "int32";
}
bool is_float_type(const std::string& t) {
  return t == "float" || t == "float32" || t == "double" || t == "float64";
}

// A list count as assimp turns it into an unsigned int (ConvertTo<unsigned int>): an unsigned
// type keeps its leading digits, a negative signed count wraps to ~4e9, a float is truncated.
// Returned as a double so that every one of those compares with what the file can hold.
// A claimed count for an error message: it may be any double (a 125-digit ASCII count, an infinite
// binary double), which no integer type holds.
std::string count_text(double n) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.15g", n);
  return buf;
}

double ascii_list_count(const std::string& token, const std::string& type) {
  if (is_float_type(type)) {
    const double v = std::strtod(token.c_str(), nullptr);
    return std::isnan(v) ? 4294967295.0 : v < 0.0 ? 4294967295.0 : v;
  }
  std::size_t i = 0;
  bool negative = false;
  if (is_signed_type(type) && i < token.size() && (token[i] == '-' || token[i] == '+')) negative = token[i++] == '-';
  double v = 0.0;
  for (; i < token.size() && token[i] >= '0' && token[i] <= '9'; ++i) v = 10.0 * v + (token[i] - '0');
  return negative && v > 0.0 ? 4294967295.0 : v;
}

// The body of an ASCII PLY as assimp's IOStreamBuffer::getNextLine cuts it: '\r', '\n', '\0'
// and '\f' end a line; a line that starts at a line end first skips through the next '\n'.
class AsciiLines {
 public:
  explicit AsciiLines(std::string body) : body_(std::move(body)) {}
  bool next(std::string& line) {
    if (pos_ >= body_.size()) return false;
    if (end_of_line(body_[pos_])) {
      while (pos_ < body_.size() && body_[pos_] != '\n') ++pos_;
      ++pos_;
      if (pos_ >= body_.size()) return false;
    }
    const std::size_t from = pos_;
    while (pos_ < body_.size() && !end_of_line(body_[pos_])) ++pos_;
    line.assign(body_, from, pos_ - from);
    ++pos_;
    return true;
  }

 private:
  static bool end_of_line(char c) { return c == '\r' || c == '\n' || c == '\0' || c == '\f'; }
  std::string body_;
  std::size_t pos_ = 0;
};

// Walks the element instances of an ASCII body, one a line as assimp reads them: a list may not
// claim more values than its line has characters (assimp sizes the list by the claim before
// reading a value: a count of 399125025 on a face line asked for 3.2 GB). A claim above the
// values the line has but within its length is left to assimp, which reads what is there (so
// allocating at most 8 bytes per character of the line).
// A body with fewer lines than the header's instances is refused: past the file's end assimp
// parses every missing instance from what its line buffer still holds (the last line, or stale
// bytes), so a cut file whose last line began with 49761958, read as the face list count 388
// times, took it past 24 GB (found by the suite's random-input test), and an element of 2e9
// instances without properties is sized (48 GB) before a line is read.
std::string check_ascii_lists(const std::vector<Element>& elements, std::string body) {
  AsciiLines lines(std::move(body));
  std::string line;
  std::uint64_t read = 0;
  for (const Element& e : elements) {
    bool has_list = false;
    for (const Property& p : e.properties) has_list = has_list || p.list;
    for (std::uint64_t k = 0; k < e.count; ++k) {
      if (!lines.next(line)) {
        std::uint64_t needed = 0;
        for (const Element& each : elements) needed += each.count;
        return "PLY body ends after " + std::to_string(read) + " lines; its header's elements need " +
               std::to_string(needed) + " (" + e.name + " " + std::to_string(k) + " is missing)";
      }
      ++read;
      if (!has_list) continue;
      std::vector<std::string> tokens;
      std::istringstream words(line);
      for (std::string w; words >> w;) tokens.push_back(w);
      std::size_t at = 0;
      for (const Property& p : e.properties) {
        if (at >= tokens.size()) break;
        if (!p.list) {
          ++at;
          continue;
        }
        const double n = ascii_list_count(tokens[at++], p.count_type);
        if (n > static_cast<double>(line.size()))
          return "PLY " + e.name + " " + std::to_string(k) + " has a list of " +
                 count_text(n) + " values on a line of " +
                 std::to_string(line.size()) + " characters";
        at += static_cast<std::size_t>(n);
      }
    }
  }
  return {};
}

std::uint64_t read_unsigned(const unsigned char* p, int bytes, bool big_endian) {
  std::uint64_t v = 0;
  for (int i = 0; i < bytes; ++i) v |= std::uint64_t{p[big_endian ? bytes - 1 - i : i]} << (8 * i);
  return v;
}

// A binary list count as assimp turns it into an unsigned int (see ascii_list_count).
double binary_list_count(const unsigned char* p, const std::string& type, int bytes, bool big_endian) {
  const std::uint64_t raw = read_unsigned(p, bytes, big_endian);
  if (type == "float" || type == "float32") {
    float f;
    const auto u = static_cast<std::uint32_t>(raw);
    std::memcpy(&f, &u, sizeof f);
    return std::isnan(f) || f < 0.0f ? 4294967295.0 : static_cast<double>(f);
  }
  if (type == "double" || type == "float64") {
    double d;
    std::memcpy(&d, &raw, sizeof d);
    return std::isnan(d) || d < 0.0 ? 4294967295.0 : d;
  }
  if (is_signed_type(type) && (raw >> (8 * bytes - 1)) != 0) return 4294967295.0;  // negative
  return static_cast<double>(raw);
}

// Walks the element instances of a binary body: a list's items must fit in the bytes left.
std::string check_binary_lists(const std::vector<Element>& elements, const std::string& body, bool big_endian) {
  const auto* data = reinterpret_cast<const unsigned char*>(body.data());
  std::size_t at = 0;
  for (const Element& e : elements) {
    // Instances without properties take no bytes, so nothing bounds their count but the claim,
    // and assimp sizes an array by it (24 bytes an instance).
    if (e.properties.empty() && e.count > 0)
      return "PLY element '" + e.name + "' has " + std::to_string(e.count) + " instances and no properties";
    for (std::uint64_t k = 0; k < e.count; ++k) {
      for (const Property& p : e.properties) {
        const std::size_t value_bytes = static_cast<std::size_t>(p.list ? type_size(p.count_type) : p.bytes);
        if (at + value_bytes > body.size())
          return "PLY body ends after " + std::to_string(body.size()) + " bytes, inside " + e.name + " " +
                 std::to_string(k) + " (a file cut short?)";
        if (!p.list) {
          at += value_bytes;
          continue;
        }
        const int count_bytes = static_cast<int>(value_bytes);
        const double n = binary_list_count(data + at, p.count_type, count_bytes, big_endian);
        at += static_cast<std::size_t>(count_bytes);
        const std::size_t left = body.size() - at;
        if (n * p.bytes > static_cast<double>(left))
          return "PLY " + e.name + " " + std::to_string(k) + " has a list of " +
                 count_text(n) + " values of " + std::to_string(p.bytes) +
                 " bytes with " + std::to_string(left) + " bytes left";
        at += static_cast<std::size_t>(n) * static_cast<std::size_t>(p.bytes);
      }
    }
  }
  return {};
}

}  // namespace

std::string check_ply_header(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return {};
  // The header as assimp 5.2's PLY reader sees it: a line ends at '\n', '\r', '\0' or '\f'; the
  // first line is the magic when its first three characters are "ply" in any case (the rest of
  // it is ignored). A check that cut lines at '\n' only and wanted the first line to be "ply"
  // let files starting "ply\fformat ascii 1.0" or "ply\x80..." with no end_header pass, and
  // assimp then searched for the end of their header for ever (found by the fuzzer).
  std::string head(kMaxHeaderBytes + 1, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  const auto line_end = [](char c) { return c == '\n' || c == '\r' || c == '\0' || c == '\f'; };
  const auto is = [&](std::size_t i, char lower) { return i < head.size() && (head[i] | 0x20) == lower; };
  if (!is(0, 'p') || !is(1, 'l') || !is(2, 'y')) return {};
  std::size_t first_end = 3;
  while (first_end < head.size() && !line_end(head[first_end])) ++first_end;

  bool binary = false, big_endian = false, have_format = false;
  std::vector<Element> elements;
  std::size_t header_bytes = 0;
  bool ended = false;
  const std::size_t start = first_end + 1;
  for (std::size_t pos = start; pos < head.size() && !ended;) {
    // As assimp's getNextLine: a line that starts at a line end first skips through the next
    // '\n' ("\r\n" ends one line). Reading every '\0' as an empty line let a header whose
    // end_header followed a run of NULs on the same '\n'-line pass, and assimp, skipping that
    // run together with end_header, looked for its end for ever (found by the fuzzer).
    if (line_end(head[pos])) {
      while (pos < head.size() && head[pos] != '\n') ++pos;
      if (pos >= head.size() && head.size() > kMaxHeaderBytes) return "PLY header longer than 64 kB";
      if (++pos >= head.size()) break;
    }
    std::size_t end = pos;
    while (end < head.size() && !line_end(head[end])) ++end;
    if (end >= head.size() && head.size() > kMaxHeaderBytes) return "PLY header longer than 64 kB";
    const std::string line = head.substr(pos, end - pos);
    pos = end + 1;
    // "\r\n" ends one line (the body of a binary file starts after both).
    if (end < head.size() && head[end] == '\r' && pos < head.size() && head[pos] == '\n') ++pos;
    std::istringstream words(line);
    std::string word;
    words >> word;
    // assimp's TokenMatch: the line starts with the word, and a space, a tab or the line's end
    // follows it. To istream ">>" a vertical tab ends the word too, so "end_header\v..." ended
    // this header while assimp searched on for its end for ever (found by the fuzzer).
    if (word == "end_header" && (line.compare(0, 10, "end_header") != 0 ||
                                 (line.size() > 10 && line[10] != ' ' && line[10] != '\t'))) {
      return "PLY end_header line is not one assimp reads (a space, a tab or the line's end must follow the word, "
             "at the start of the line)";
    }
    if (word == "end_header") {
      ended = true;
      header_bytes = std::min(pos, head.size());
      break;
    }
    if (word == "format") {
      std::string format;
      words >> format;
      if (format == "ascii") {
        binary = false;
      } else if (format == "binary_little_endian" || format == "binary_big_endian") {
        binary = true;
        big_endian = format == "binary_big_endian";
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
      // assimp 5.2 sizes a mesh's vertex (face) array by the first such element and then writes
      // every vertex (face) element into it: "element vertex 1 ... element vertex 3" overran the
      // heap, a second face element corrupted it (found by the fuzzer). Later assimp refuses
      // any element declared twice; so does this check.
      for (const Element& seen : elements)
        if (seen.name == e.name) return "PLY element '" + e.name + "' is declared twice";
      elements.push_back(e);
    } else if (word == "property") {
      if (elements.empty()) return "PLY property before any element";
      std::string type;
      words >> type;
      int bytes = 0;
      Property property;
      if (type == "list") {
        std::string count_type, item_type;
        words >> count_type >> item_type;
        if (type_size(count_type) == 0 || type_size(item_type) == 0)
          return "PLY list property of unknown type '" + count_type + " " + item_type + "'";
        bytes = type_size(count_type);  // a list may be empty: its count alone
        property = {true, count_type, type_size(item_type)};
      } else {
        bytes = type_size(type);
        if (bytes == 0) return "PLY property of unknown type '" + type + "'";
        property = {false, "", bytes};
      }
      elements.back().properties.push_back(property);
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
  // The body, read from where the header ended (the file is at most kMeshMaxFileBytes).
  in.clear();
  in.seekg(static_cast<std::streamoff>(header_bytes));
  std::string rest((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return binary ? check_binary_lists(elements, rest, big_endian) : check_ascii_lists(elements, std::move(rest));
}

}  // namespace porter::detail
