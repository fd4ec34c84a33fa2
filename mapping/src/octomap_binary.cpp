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

// The subtree of one brick from its packed states (voxel x + 8 y + 64 z at bits 2 i of
// words[i / 32]), bottom up: a node's eight child codes packed as the format writes them (child
// i at bits 2 i, x in bit 0 of i, y bit 1, z bit 2) decide it: 0 = unknown, 0x5555 = free leaf,
// 0xAAAA = occupied leaf, anything else an inner node with those two bytes. Then the inner
// nodes are written pre-order. Returns the brick's code.
int encode_brick_states(const std::uint64_t* words, std::vector<std::uint8_t>& out) {
  const auto code_of = [](unsigned packed) {
    return packed == 0 ? kUnknown : (packed == 0x5555u ? kFree : (packed == 0xAAAAu ? kOccupied : kInner));
  };
  // Four bits: voxels x = 2a, 2a + 1 of row (y, z).
  const auto pair = [words](int a, int y, int z) {
    const int i = 2 * a + 8 * y + 64 * z;
    return static_cast<unsigned>((words[i >> 5] >> (2 * (i & 31))) & 0xFu);
  };
  unsigned p1[64], p2[8], p3 = 0;  // packed child codes of the 2^3, 4^3 and 8^3 nodes
  int c1[64], c2[8];
  for (int c = 0; c < 4; ++c)
    for (int b = 0; b < 4; ++b)
      for (int a = 0; a < 4; ++a) {
        const int n = a + 4 * b + 16 * c;
        p1[n] = pair(a, 2 * b, 2 * c) | pair(a, 2 * b + 1, 2 * c) << 4 | pair(a, 2 * b, 2 * c + 1) << 8 |
                pair(a, 2 * b + 1, 2 * c + 1) << 12;
        c1[n] = code_of(p1[n]);
      }
  for (int r = 0; r < 2; ++r)
    for (int q = 0; q < 2; ++q)
      for (int p = 0; p < 2; ++p) {
        unsigned v = 0;
        for (int i = 0; i < 8; ++i) {
          const int n = (2 * p + (i & 1)) + 4 * (2 * q + ((i >> 1) & 1)) + 16 * (2 * r + ((i >> 2) & 1));
          v |= static_cast<unsigned>(c1[n]) << (2 * i);
        }
        const int m = p + 2 * q + 4 * r;
        p2[m] = v;
        c2[m] = code_of(v);
      }
  for (int i = 0; i < 8; ++i) p3 |= static_cast<unsigned>(c2[i]) << (2 * i);
  const int root = code_of(p3);
  if (root != kInner) return root;
  const auto bytes = [&out](unsigned v) {
    out.push_back(static_cast<std::uint8_t>(v & 0xFFu));
    out.push_back(static_cast<std::uint8_t>(v >> 8));
  };
  bytes(p3);
  for (int m = 0; m < 8; ++m) {
    if (c2[m] != kInner) continue;
    bytes(p2[m]);
    const int p = m & 1, q = (m >> 1) & 1, r = m >> 2;
    for (int i = 0; i < 8; ++i) {
      const int n = (2 * p + (i & 1)) + 4 * (2 * q + ((i >> 1) & 1)) + 16 * (2 * r + ((i >> 2) & 1));
      if (c1[n] == kInner) bytes(p1[n]);
    }
  }
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
  constexpr int kW = RollingMap::kBlockWords;
  const Eigen::Vector3i lo = map.window_min_key(), hi = lo + map.dims();
  const Eigen::Vector3i& n = map.dims();
  // Per axis: the slot of each of the brick's 8 keys (-1 outside the window), and whether they
  // are one whole slot block (inside the window, contiguous, starting at a multiple of 8).
  int slot[3][kB];
  bool whole = true;
  const int b[3] = {bx, by, bz};
  for (int a = 0; a < 3; ++a) {
    for (int i = 0; i < kB; ++i) {
      const int k = b[a] * kB + i;
      slot[a][i] = k >= lo[a] && k < hi[a] ? k % n[a] : -1;
    }
    whole = whole && slot[a][0] >= 0 && slot[a][0] % kB == 0 && slot[a][kB - 1] == slot[a][0] + kB - 1;
  }
  e.key = Eigen::Vector3i(bx, by, bz);
  e.bytes.clear();
  std::uint64_t packed[kW];
  const std::uint64_t* words = packed;
  if (whole) {
    words = map.block_states(slot[0][0] >> kBrickShift, slot[1][0] >> kBrickShift, slot[2][0] >> kBrickShift);
  } else {
    std::fill(packed, packed + kW, std::uint64_t{0});
    for (int z = 0; z < kB; ++z)
      for (int y = 0; y < kB; ++y)
        for (int x = 0; x < kB; ++x) {
          const int sx = slot[0][x], sy = slot[1][y], sz = slot[2][z];
          if (sx < 0 || sy < 0 || sz < 0) continue;
          const std::uint64_t* w = map.block_states(sx >> kBrickShift, sy >> kBrickShift, sz >> kBrickShift);
          const int i = (sx & 7) + 8 * (sy & 7) + 64 * (sz & 7);
          const int o = x + kB * y + kB * kB * z;
          packed[o >> 5] |= ((w[i >> 5] >> (2 * (i & 31))) & 3u) << (2 * (o & 31));
        }
  }
  bool unknown = true, free = true, occupied = true;
  for (int j = 0; j < kW; ++j) {
    unknown = unknown && words[j] == 0;
    free = free && words[j] == 0x5555555555555555ull;
    occupied = occupied && words[j] == 0xAAAAAAAAAAAAAAAAull;
  }
  if (unknown || free || occupied) {
    e.code = static_cast<std::uint8_t>(unknown ? kUnknown : (free ? kFree : kOccupied));
    return;
  }
  e.code = static_cast<std::uint8_t>(encode_brick_states(words, e.bytes));
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
