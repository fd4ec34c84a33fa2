#include "porter/mapping/octomap_binary.hpp"

#include <algorithm>
#include <array>
#include <limits>

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

// The subtree of a block of size^3 voxels at (x, y, z) inside a brick's 8^3 states
// (x + 8 y + 64 z), pre-order, as Encoder::node writes it below the brick level.
int encode_local(const std::uint8_t* st, int size, int x, int y, int z, std::vector<std::uint8_t>& out) {
  const std::size_t pos = out.size();
  out.push_back(0);
  out.push_back(0);
  int codes[8];
  const int half = size / 2;
  for (int i = 0; i < 8; ++i) {
    const int cx = x + (i & 1) * half, cy = y + ((i >> 1) & 1) * half, cz = z + ((i >> 2) & 1) * half;
    codes[i] = half == 1 ? st[cx + 8 * cy + 64 * cz] : encode_local(st, half, cx, cy, cz, out);
  }
  bool uniform = codes[0] == kFree || codes[0] == kOccupied;
  bool any = false;
  for (int i = 0; i < 8; ++i) {
    uniform = uniform && codes[i] == codes[0];
    any = any || codes[i] != kUnknown;
  }
  if (uniform || !any) {
    out.resize(pos);
    return uniform ? codes[0] : kUnknown;
  }
  std::uint8_t b0 = 0, b1 = 0;
  for (int i = 0; i < 4; ++i) {
    b0 = static_cast<std::uint8_t>(b0 | (codes[i] << (2 * i)));
    b1 = static_cast<std::uint8_t>(b1 | (codes[i + 4] << (2 * i)));
  }
  out[pos] = b0;
  out[pos + 1] = b1;
  return kInner;
}

}  // namespace

void write_octomap_binary(const RollingMap& map, std::vector<std::uint8_t>& out) {
  out.clear();
  Encoder encoder(map, out);
  encoder.node(0, 0, 0, 0);
}

OctomapBinaryWriter::Brick& OctomapBinaryWriter::entry(int bx, int by, int bz) {
  const std::size_t i = static_cast<std::size_t>(bx % ring_.x()) +
                        static_cast<std::size_t>(ring_.x()) *
                            (static_cast<std::size_t>(by % ring_.y()) + static_cast<std::size_t>(ring_.y()) * static_cast<std::size_t>(bz % ring_.z()));
  return bricks_[i];
}

void OctomapBinaryWriter::encode_brick(const RollingMap& map, int bx, int by, int bz, Brick& e) {
  constexpr int kB = 1 << kBrickShift;
  const Eigen::Vector3i lo = map.window_min_key(), hi = lo + map.dims();
  const Eigen::Vector3i& n = map.dims();
  const float* v = map.raw_log_odds();
  std::uint8_t st[kB * kB * kB];
  std::uint8_t flags = 0;
  std::int64_t sx[kB];
  bool in_x[kB];
  for (int x = 0; x < kB; ++x) {
    const int kx = bx * kB + x;
    in_x[x] = kx >= lo.x() && kx < hi.x();
    sx[x] = kx % n.x();
  }
  for (int z = 0; z < kB; ++z) {
    const int kz = bz * kB + z;
    const bool in_z = kz >= lo.z() && kz < hi.z();
    for (int y = 0; y < kB; ++y) {
      const int ky = by * kB + y;
      std::uint8_t* row = st + kB * y + kB * kB * z;
      if (!in_z || ky < lo.y() || ky >= hi.y()) {
        std::fill(row, row + kB, static_cast<std::uint8_t>(kUnknown));
        flags |= kHasUnknown;
        continue;
      }
      const std::int64_t base = map.slot(Eigen::Vector3i(0, ky, kz));
      for (int x = 0; x < kB; ++x) {
        const float f = in_x[x] ? v[base + sx[x]] : std::numeric_limits<float>::quiet_NaN();
        const int code = f != f ? kUnknown : (map.occupied(f) ? kOccupied : kFree);
        row[x] = static_cast<std::uint8_t>(code);
        flags |= code == kUnknown ? kHasUnknown : (code == kFree ? kHasFree : kHasOccupied);
      }
    }
  }
  e.key = Eigen::Vector3i(bx, by, bz);
  e.bytes.clear();
  if (flags == kHasUnknown) {
    e.code = kUnknown;
  } else if (flags == kHasFree) {
    e.code = kFree;
  } else if (flags == kHasOccupied) {
    e.code = kOccupied;
  } else {
    e.code = static_cast<std::uint8_t>(encode_local(st, kB, 0, 0, 0, e.bytes));
  }
}

int OctomapBinaryWriter::node(int depth, int kx, int ky, int kz, std::vector<std::uint8_t>& out) {
  const int size = 1 << (kTreeDepth - depth);
  if (kx + size <= lo_.x() || kx >= hi_.x() || ky + size <= lo_.y() || ky >= hi_.y() || kz + size <= lo_.z() ||
      kz >= hi_.z()) {
    return kUnknown;
  }
  if (depth == kBrickDepth) {
    const Brick& e = entry(kx >> kBrickShift, ky >> kBrickShift, kz >> kBrickShift);
    if (e.code == kInner) out.insert(out.end(), e.bytes.begin(), e.bytes.end());
    return e.code;
  }
  const std::size_t pos = out.size();
  out.push_back(0);
  out.push_back(0);
  int codes[8];
  const int half = size / 2;
  for (int i = 0; i < 8; ++i) {
    codes[i] = node(depth + 1, kx + (i & 1) * half, ky + ((i >> 1) & 1) * half, kz + ((i >> 2) & 1) * half, out);
  }
  bool uniform = codes[0] == kFree || codes[0] == kOccupied;
  bool any = false;
  for (int i = 0; i < 8; ++i) {
    uniform = uniform && codes[i] == codes[0];
    any = any || codes[i] != kUnknown;
  }
  if (uniform || !any) {
    out.resize(pos);
    return uniform ? codes[0] : kUnknown;
  }
  std::uint8_t b0 = 0, b1 = 0;
  for (int i = 0; i < 4; ++i) {
    b0 = static_cast<std::uint8_t>(b0 | (codes[i] << (2 * i)));
    b1 = static_cast<std::uint8_t>(b1 | (codes[i + 4] << (2 * i)));
  }
  out[pos] = b0;
  out[pos + 1] = b1;
  return kInner;
}

void OctomapBinaryWriter::write(const RollingMap& map, std::vector<std::uint8_t>& out) {
  constexpr int kB = 1 << kBrickShift;
  const Eigen::Vector3i& n = map.dims();
  const bool fresh = map_ != &map || n != dims_ || map.resolution_m() != resolution_m_ || map.revision() < revision_;
  if (fresh) {
    map_ = &map;
    dims_ = n;
    resolution_m_ = map.resolution_m();
    // Bricks that meet a window of n keys: at most (n - 1) / 8 + 2 per axis, so indexing them
    // modulo n / 8 + 2 never puts two of them in one entry.
    ring_ = Eigen::Vector3i(n.x() / kB + 2, n.y() / kB + 2, n.z() / kB + 2);
    bricks_.assign(static_cast<std::size_t>(ring_.prod()), Brick{});
  }
  const Eigen::Vector3i lo = map.window_min_key(), hi = lo + n;
  // Per axis and brick: whether its keys inside the window are those of the last write, and
  // the slot blocks (slot >> 3) those keys live in (at most 3: 8 keys, wrapped modulo n).
  struct Axis {
    int first = 0;
    std::vector<std::uint8_t> same;
    std::vector<std::array<int, 3>> blocks;
    std::vector<int> num_blocks;
  };
  Axis ax[3];
  for (int i = 0; i < 3; ++i) {
    ax[i].first = lo[i] >> kBrickShift;
    const int count = ((hi[i] - 1) >> kBrickShift) - ax[i].first + 1;
    ax[i].same.assign(static_cast<std::size_t>(count), 0);
    ax[i].blocks.assign(static_cast<std::size_t>(count), {0, 0, 0});
    ax[i].num_blocks.assign(static_cast<std::size_t>(count), 0);
    for (int c = 0; c < count; ++c) {
      const int b = ax[i].first + c;
      const int k0 = std::max(b * kB, lo[i]), k1 = std::min(b * kB + kB, hi[i]);
      ax[i].same[static_cast<std::size_t>(c)] =
          !fresh && k0 == std::max(b * kB, lo_[i]) && k1 == std::min(b * kB + kB, hi_[i]);
      int& m = ax[i].num_blocks[static_cast<std::size_t>(c)];
      for (int k = k0; k < k1; ++k) {
        const int blk = (k % n[i]) >> RollingMap::kBlockShift;
        bool seen = false;
        for (int j = 0; j < m; ++j) seen = seen || ax[i].blocks[static_cast<std::size_t>(c)][static_cast<std::size_t>(j)] == blk;
        if (!seen) ax[i].blocks[static_cast<std::size_t>(c)][static_cast<std::size_t>(m++)] = blk;
      }
    }
  }
  stats_ = Stats{};
  const std::size_t nx = ax[0].same.size(), ny = ax[1].same.size(), nz = ax[2].same.size();
  for (std::size_t cz = 0; cz < nz; ++cz)
    for (std::size_t cy = 0; cy < ny; ++cy)
      for (std::size_t cx = 0; cx < nx; ++cx) {
        const int bx = ax[0].first + static_cast<int>(cx), by = ax[1].first + static_cast<int>(cy),
                  bz = ax[2].first + static_cast<int>(cz);
        Brick& e = entry(bx, by, bz);
        ++stats_.bricks;
        bool stale = e.key != Eigen::Vector3i(bx, by, bz) || !ax[0].same[cx] || !ax[1].same[cy] || !ax[2].same[cz];
        for (int jz = 0; jz < ax[2].num_blocks[cz] && !stale; ++jz)
          for (int jy = 0; jy < ax[1].num_blocks[cy] && !stale; ++jy)
            for (int jx = 0; jx < ax[0].num_blocks[cx] && !stale; ++jx) {
              stale = map.block_revision(ax[0].blocks[cx][static_cast<std::size_t>(jx)], ax[1].blocks[cy][static_cast<std::size_t>(jy)],
                                         ax[2].blocks[cz][static_cast<std::size_t>(jz)]) > revision_;
            }
        if (!stale) continue;
        encode_brick(map, bx, by, bz, e);
        ++stats_.bricks_encoded;
      }
  revision_ = map.revision();
  lo_ = lo;
  hi_ = hi;
  out.clear();
  node(0, 0, 0, 0, out);
}

}  // namespace porter::mapping
