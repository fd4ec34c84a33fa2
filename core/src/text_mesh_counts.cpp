#include "text_mesh_counts.hpp"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <vector>

#include "porter/core/mesh_loader.hpp"

namespace porter::detail {
namespace {

constexpr std::size_t kHeaderBytes = 64 * 1024;
constexpr std::size_t kChunkBytes = 64 * 1024;

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

// Whitespace-separated tokens of `text`, '#' starting a comment to the end of the line (as
// assimp's OFF reader skips them), at most `max_tokens`.
std::vector<std::string> tokens(const std::string& text, std::size_t max_tokens) {
  std::vector<std::string> out;
  std::size_t i = 0;
  while (i < text.size() && out.size() < max_tokens) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c == '#') {
      while (i < text.size() && text[i] != '\n') ++i;
    } else if (std::isspace(c) != 0) {
      ++i;
    } else {
      const std::size_t start = i;
      while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i])) == 0 && text[i] != '#') ++i;
      out.push_back(text.substr(start, i - start));
    }
  }
  return out;
}

// The leading digits of a token as assimp's strtoul10 reads them, saturated instead of wrapped
// (a count that wraps to a small number is refused all the same).
std::uint64_t leading_count(const std::string& token) {
  std::uint64_t v = 0;
  for (const char c : token) {
    if (c < '0' || c > '9') break;
    v = std::min<std::uint64_t>(v * 10 + static_cast<std::uint64_t>(c - '0'), std::uint64_t{1} << 62);
  }
  return v;
}

// Calls `line(begin, end)` for every line of the file, reading it in chunks.
template <class F>
bool for_each_line(const std::string& path, F&& line) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  // Not a std::vector: zero-filling the chunk on every call was most of a small file's cost.
  const std::unique_ptr<char[]> chunk(new char[kChunkBytes]);
  char* const buffer = chunk.get();
  std::string carry;
  while (in) {
    in.read(buffer, static_cast<std::streamsize>(kChunkBytes));
    const std::size_t n = static_cast<std::size_t>(in.gcount());
    std::size_t start = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (buffer[i] != '\n') continue;
      if (carry.empty()) {
        line(buffer + start, buffer + i);
      } else {
        carry.append(buffer + start, i - start);
        line(carry.data(), carry.data() + carry.size());
        carry.clear();
      }
      start = i + 1;
    }
    carry.append(buffer + start, n - start);
  }
  if (!carry.empty()) line(carry.data(), carry.data() + carry.size());
  return true;
}

bool line_end(char c) { return c == '\n' || c == '\r' || c == '\f' || c == '\0'; }

// Walks the file as assimp's OFF importer does (the keyword, the counts, then one line per
// vertex and per face, empty lines skipped) and refuses a face line whose corner count is not
// in [1, 9]. assimp skips such a face by shrinking the face count while its face array stays
// as it was, and with more lines after the faces its import then crashes (a segfault inside
// Importer::ReadFile, found by the fuzzer).
std::string check_off_faces(const std::string& path, bool keyword, bool dimension, std::uint64_t vertices,
                            std::uint64_t faces) {
  std::ifstream in(path, std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::size_t i = 0;
  auto next_token = [&] {  // assimp's NextToken: spaces, line ends and '#' comment lines
    for (;;) {
      while (i < text.size() && (text[i] == ' ' || text[i] == '\t' || line_end(text[i])) && text[i] != '\0') ++i;
      if (i < text.size() && text[i] == '#') {
        while (i < text.size() && !line_end(text[i])) ++i;
        continue;
      }
      return;
    }
  };
  auto skip_digits = [&] {
    while (i < text.size() && text[i] >= '0' && text[i] <= '9') ++i;
  };
  next_token();
  if (keyword) {
    i = text.find("OFF", i) + 3;
    next_token();
  }
  if (dimension) {
    skip_digits();
    next_token();
  }
  for (int count = 0; count < 3; ++count) {  // vertices, faces, edges
    skip_digits();
    next_token();
  }
  std::uint64_t line = 0;
  while (i < text.size() && text[i] != '\0' && line < vertices + faces) {
    const std::size_t start = i;
    while (i < text.size() && !line_end(text[i]) && i - start < 4095) ++i;
    if (line >= vertices) {
      std::size_t c = start;
      while (c < i && (text[c] == ' ' || text[c] == '\t')) ++c;
      std::uint64_t corners = 0;
      for (; c < i && text[c] >= '0' && text[c] <= '9' && corners < 100; ++c) corners = corners * 10 + (text[c] - '0');
      if (corners < 1 || corners > 9)
        return "OFF face " + std::to_string(line - vertices) + " does not start with a corner count in [1, 9]";
    }
    while (i < text.size() && line_end(text[i]) && text[i] != '\0') ++i;
    ++line;
  }
  return {};
}

std::string check_off(const std::string& path, bool by_extension) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return {};
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  std::string head(ec ? 0 : static_cast<std::size_t>(std::min<std::uintmax_t>(size, kHeaderBytes)), '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  std::vector<std::string> t = tokens(head, 4);
  if (t.empty()) return {};
  // The header's keyword: [ST][C][N][4][n]OFF, as assimp reads it; without one (allowed for a
  // .off file) the counts come first.
  std::size_t p = 0;
  const std::string& k = t[0];
  if (k.compare(0, 2, "ST") == 0) p += 2;
  if (p < k.size() && k[p] == 'C') ++p;
  if (p < k.size() && k[p] == 'N') ++p;
  if (p < k.size() && k[p] == '4') ++p;
  const bool dimension = p < k.size() && k[p] == 'n';
  if (dimension) ++p;
  const bool keyword = k.compare(p, 3, "OFF") == 0;
  if (!keyword && !by_extension) return {};
  // assimp reads on right after "OFF": in "OFF436398308 8757" the first count is 436398308
  // (found by the fuzzer: that 18-byte file took assimp past 3.5 GB).
  if (keyword && k.size() > p + 3) t.insert(t.begin() + 1, k.substr(p + 3));
  std::size_t at = keyword ? 1 : 0;
  if (keyword && dimension) ++at;
  if (t.size() < at + 2) return {};  // assimp refuses it itself
  const std::uint64_t vertices = leading_count(t[at]);
  const std::uint64_t faces = leading_count(t[at + 1]);
  if (vertices > kMeshMaxVertices)
    return "OFF header claims " + std::to_string(vertices) + " vertices (limit " + std::to_string(kMeshMaxVertices) + ")";
  if (faces > kMeshMaxFaces)
    return "OFF header claims " + std::to_string(faces) + " faces (limit " + std::to_string(kMeshMaxFaces) + ")";
  std::uint64_t lines = 0;
  for_each_line(path, [&](const char*, const char*) { ++lines; });
  if (vertices + faces > lines)
    return "OFF header claims " + std::to_string(vertices) + " vertices and " + std::to_string(faces) +
           " faces, one line each; the file has " + std::to_string(lines) + " lines";
  return check_off_faces(path, keyword, keyword && dimension, vertices, faces);
}

std::string check_obj(const std::string& path) {
  std::uint64_t vertices = 0, faces = 0, corners = 0;
  for_each_line(path, [&](const char* b, const char* e) {
    while (b < e && (*b == ' ' || *b == '\t')) ++b;
    if (e - b < 2 || (b[1] != ' ' && b[1] != '\t')) return;
    if (b[0] == 'v') {
      ++vertices;
    } else if (b[0] == 'f') {
      ++faces;
      bool in_word = false;
      for (const char* c = b + 1; c < e; ++c) {
        const bool space = *c == ' ' || *c == '\t' || *c == '\r';
        if (!space && !in_word) ++corners;
        in_word = !space;
      }
    }
  });
  if (vertices > kMeshMaxVertices)
    return "OBJ file has " + std::to_string(vertices) + " vertices (limit " + std::to_string(kMeshMaxVertices) + ")";
  if (faces > kMeshMaxFaces)
    return "OBJ file has " + std::to_string(faces) + " faces (limit " + std::to_string(kMeshMaxFaces) + ")";
  if (corners > 3 * kMeshMaxFaces)
    return "OBJ faces have " + std::to_string(corners) + " corners in all (limit " +
           std::to_string(3 * kMeshMaxFaces) + ")";
  return {};
}

}  // namespace

std::string check_text_mesh_counts(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (std::string bad = check_off(path, ext == ".off"); !bad.empty()) return bad;
  // assimp picks the OBJ importer by extension, or by content for an extension it does not know.
  if (ext == ".ply" || ext == ".stl" || ext == ".off" || ext == ".dae") return {};
  return check_obj(path);
}

}  // namespace porter::detail
