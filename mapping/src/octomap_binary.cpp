#include "porter/mapping/octomap_binary.hpp"

namespace porter::mapping {

namespace {

// Two bits per child in OctoMap's binary node format.
constexpr int kUnknown = 0;
constexpr int kFree = 1;
constexpr int kOccupied = 2;
constexpr int kInner = 3;
constexpr int kTreeDepth = 16;

class Encoder {
 public:
  Encoder(const RollingMap& map, std::vector<std::uint8_t>& out)
      : map_(map), out_(out), lo_(map.window_min_key()), hi_(map.window_min_key() + map.dims()) {}

  // Pre-order: a node's two bytes, then the subtrees of its inner children in child order. A
  // child that turns out to be a leaf or unknown takes its reserved bytes back.
  int node(int depth, int kx, int ky, int kz) {
    const int size = 1 << (kTreeDepth - depth);
    if (kx + size <= lo_.x() || kx >= hi_.x() || ky + size <= lo_.y() || ky >= hi_.y() ||
        kz + size <= lo_.z() || kz >= hi_.z()) {
      return kUnknown;
    }
    const std::size_t pos = out_.size();
    out_.push_back(0);
    out_.push_back(0);
    int codes[8];
    const int half = size / 2;
    for (int i = 0; i < 8; ++i) {
      const int cx = kx + (i & 1) * half, cy = ky + ((i >> 1) & 1) * half, cz = kz + ((i >> 2) & 1) * half;
      codes[i] = depth + 1 == kTreeDepth ? voxel(cx, cy, cz) : node(depth + 1, cx, cy, cz);
    }
    bool uniform = codes[0] == kFree || codes[0] == kOccupied;
    bool any = false;
    for (int i = 0; i < 8; ++i) {
      uniform = uniform && codes[i] == codes[0];
      any = any || codes[i] != kUnknown;
    }
    if (uniform || !any) {
      out_.resize(pos);
      return uniform ? codes[0] : kUnknown;
    }
    std::uint8_t b0 = 0, b1 = 0;
    for (int i = 0; i < 4; ++i) {
      b0 = static_cast<std::uint8_t>(b0 | (codes[i] << (2 * i)));
      b1 = static_cast<std::uint8_t>(b1 | (codes[i + 4] << (2 * i)));
    }
    out_[pos] = b0;
    out_[pos + 1] = b1;
    return kInner;
  }

 private:
  int voxel(int kx, int ky, int kz) const {
    const Eigen::Vector3i key(kx, ky, kz);
    if (!map_.in_window(key)) return kUnknown;
    const float v = map_.raw_log_odds()[map_.slot(key)];
    if (v != v) return kUnknown;
    return map_.occupied(v) ? kOccupied : kFree;
  }

  const RollingMap& map_;
  std::vector<std::uint8_t>& out_;
  Eigen::Vector3i lo_, hi_;
};

}  // namespace

void write_octomap_binary(const RollingMap& map, std::vector<std::uint8_t>& out) {
  out.clear();
  Encoder encoder(map, out);
  encoder.node(0, 0, 0, 0);
}

}  // namespace porter::mapping
