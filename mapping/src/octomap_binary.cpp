#include "porter/mapping/octomap_binary.hpp"

namespace porter::mapping {

namespace {

// Two bits per child in OctoMap's binary node format.
constexpr int kUnknown = 0;
constexpr int kFree = 1;
constexpr int kOccupied = 2;
constexpr int kInner = 3;
constexpr int kTreeDepth = 16;
// Bricks of 8^3 voxels (tree depth 13) are summarised in one linear pass over the window, so
// the recursion descends to voxels only in bricks that mix states.
constexpr int kBrickDepth = 13;
constexpr int kBrickShift = kTreeDepth - kBrickDepth;
constexpr std::uint8_t kHasUnknown = 1, kHasFree = 2, kHasOccupied = 4;

class Encoder {
 public:
  Encoder(const RollingMap& map, std::vector<std::uint8_t>& out)
      : map_(map), out_(out), lo_(map.window_min_key()), hi_(map.window_min_key() + map.dims()) {
    for (int i = 0; i < 3; ++i) {
      blo_[i] = lo_[i] >> kBrickShift;
      nb_[i] = ((hi_[i] - 1) >> kBrickShift) - blo_[i] + 1;
    }
    flags_.assign(static_cast<std::size_t>(nb_[0]) * nb_[1] * nb_[2], 0);
    // Bricks reaching past the window hold unknown voxels.
    for (int bz = 0; bz < nb_[2]; ++bz)
      for (int by = 0; by < nb_[1]; ++by)
        for (int bx = 0; bx < nb_[0]; ++bx) {
          const int b[3] = {bx, by, bz};
          bool inside = true;
          for (int i = 0; i < 3; ++i) {
            const int k0 = (blo_[i] + b[i]) << kBrickShift;
            inside = inside && k0 >= lo_[i] && k0 + (1 << kBrickShift) <= hi_[i];
          }
          if (!inside) flags_[brick(bx, by, bz)] = kHasUnknown;
        }
    const Eigen::Vector3i& n = map.dims();
    const float* v = map.raw_log_odds();
    for (int kz = lo_.z(); kz < hi_.z(); ++kz)
      for (int ky = lo_.y(); ky < hi_.y(); ++ky) {
        const std::int64_t row = map.slot(Eigen::Vector3i(0, ky, kz));
        const std::size_t brow = brick(0, (ky >> kBrickShift) - blo_[1], (kz >> kBrickShift) - blo_[2]);
        int sx = lo_.x() % n.x();
        for (int kx = lo_.x(); kx < hi_.x(); ++kx) {
          const float f = v[row + sx];
          const std::uint8_t bit = f != f ? kHasUnknown : (map.occupied(f) ? kHasOccupied : kHasFree);
          flags_[brow + static_cast<std::size_t>((kx >> kBrickShift) - blo_[0])] |= bit;
          if (++sx == n.x()) sx = 0;
        }
      }
  }

  // Pre-order: a node's two bytes, then the subtrees of its inner children in child order. A
  // child that turns out to be a leaf or unknown takes its reserved bytes back.
  int node(int depth, int kx, int ky, int kz) {
    const int size = 1 << (kTreeDepth - depth);
    if (kx + size <= lo_.x() || kx >= hi_.x() || ky + size <= lo_.y() || ky >= hi_.y() ||
        kz + size <= lo_.z() || kz >= hi_.z()) {
      return kUnknown;
    }
    if (depth == kBrickDepth) {
      const std::uint8_t f = flags_[brick((kx >> kBrickShift) - blo_[0], (ky >> kBrickShift) - blo_[1],
                                          (kz >> kBrickShift) - blo_[2])];
      if (f == kHasUnknown) return kUnknown;
      if (f == kHasFree) return kFree;
      if (f == kHasOccupied) return kOccupied;
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

  std::size_t brick(int bx, int by, int bz) const {
    return static_cast<std::size_t>(bx) + static_cast<std::size_t>(nb_[0]) * (static_cast<std::size_t>(by) + static_cast<std::size_t>(nb_[1]) * bz);
  }

  const RollingMap& map_;
  std::vector<std::uint8_t>& out_;
  Eigen::Vector3i lo_, hi_;
  int blo_[3], nb_[3];
  std::vector<std::uint8_t> flags_;
};

}  // namespace

void write_octomap_binary(const RollingMap& map, std::vector<std::uint8_t>& out) {
  out.clear();
  Encoder encoder(map, out);
  encoder.node(0, 0, 0, 0);
}

}  // namespace porter::mapping
