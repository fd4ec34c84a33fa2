#pragma once
// The map kernel (paper §IV-B, K_map): the obstacle map as padded, bit-packed 3D occupancy that
// the robot kernels are tested against with single-bit lookups, plus the derived data that lets
// a query skip whole regions.
//
// Lattice: the voxels of the OccupancyGrid given to set_map() (origin o, resolution h), extended
// by `padding_voxels` P on every side, so that index (x, y, z) here is grid index + P. Rows along
// x are word-aligned: bit x of row (y, z) is bit x % 64 of word (y + Ny z) * W + x / 64, with one
// spare word per row so a 64-bit window starting at any x in the row can be read. The arm set
// alone is stored in bricks of 4 x 4 x 4 voxels, one 64-bit word each (brick (x/4, y/4, z/4) is
// word x/4 + Bx (y/4 + By z/4), bit (x % 4) + 4 (y % 4) + 16 (z % 4)): the eight points of a
// kernel block lie within a few voxels of each other, so they read one or two bricks where rows
// would take four to nine loads.
//
// Sets held (each voxel a closed box):
//   O     occupied voxels of the grid;
//   O_m   O dilated by the safety margin r_m: every voxel whose box is closer than r_m (strict)
//         to the box of an occupied voxel (r_m = 0: O_m = O);
//   base  O_m  ∪ voxels outside the grid horizontally or above its top (or between the ground
//         and the grid's bottom when the grid starts above z = 0). Voxels below the ground are
//         NOT set: the ground is not an obstacle for the base. Tested by the base kernel K^0.
//   core  O_m ∪ every voxel outside the grid ∪ every voxel below the ground z = 0: what the
//         arm and the payload must not touch.
//   arm   dilate26(core), the 26-neighbourhood dilation: a point of a kernel K^1..K^7 closer
//         than one voxel to a core voxel lies in it (see robot_kernels.hpp). A set bit is the
//         cheap first test; arm_near() then decides from the exact distance to the core voxels.
// The ground z = 0 must be a voxel boundary (o_z / h an integer); set_map() throws
// std::invalid_argument otherwise. Its padded layer index is ground_layer().
//
// Derived data, kept exact with respect to the sets above:
//   - a 2D summed-area table of the base set projected over the base kernel's layers
//     [ground, ground + base_layers): the number of set columns in any x-y rectangle in O(1);
//   - a bit per column (x, y) of the padded array: no column of that projection has its centre
//     within sqrt(base_reach2) columns of this column's centre (exact squared distance transform
//     of the projection). With base_reach2 the largest squared offset of a base kernel column
//     from the base's own column, a set bit under the base clears every yaw at once with one
//     lookup in a small table (17 kB for a 22 x 8 m map) before the summed-area table is read;
//     on 5 000 free-near forest configurations it decided 75 % of the base tests. Columns within
//     sqrt(base_reach2) of the array's edge have the bit clear.
//   - a distance field over cells of kCellVoxels^3 voxels of the grid's region: per cell, the
//     Euclidean distance from the cell's centre (a lattice vertex) to the nearest core voxel's
//     box, in units of h / 4, rounded down and capped at distance_cap_m, from an exact distance
//     transform at voxel level; stored with a ring of zero cells around it (0 is a lower bound
//     anywhere). A query point's bound (clearance_units(), clear8()) comes from the eight cell
//     centres around it, the corners c_k of a cube of edge A = 4 kCellVoxels units:
//         d(x)^2 >= sum_k w_k v_k^2 - A^2 (t_x (1 - t_x) + t_y (1 - t_y) + t_z (1 - t_z)),
//     w_k the trilinear weights of x's offsets t in the cube and v_k <= d(c_k) the stored values.
//     Why it holds: for any closed set S, |x|^2 - d(x)^2 = max over s in S of (2 x.s - |s|^2) is
//     convex in x (a maximum of affine functions), so at x = sum_k w_k c_k it is at most
//     sum_k w_k (|c_k|^2 - d(c_k)^2); rearranged, d(x)^2 >= sum_k w_k d(c_k)^2 - sum_k w_k
//     |c_k - x|^2, and the last sum is the variance term above.
//     Why not the nearest centre's value minus the offset (d is 1-Lipschitz): that loses up to
//     half a cell diagonal (1.7 voxels) at any distance, where the interpolated square loses
//     about A^2 (t(1 - t) + ...) / (2 d), a fraction of a voxel once the obstacle is a few voxels
//     away (test_map_kernel.cpp compares both with the exact distance). A tighter bound proves
//     more sphere-tree nodes clear, so a check opens fewer nodes and blocks near obstacles.
//     Float32: the offsets t carry an error of about 2^-23 D cells (D the largest padded
//     dimension), and along one axis the bound's square changes by less than
//     |v_1^2 - v_0^2| + A^2 < 4 700 units^2 per cell (|v_1 - v_0| <= A + 1, v <= 255), so the
//     rounding of t moves it by at most 3 * 4 700 * 2^-23 D < 0.0017 D units^2; the arithmetic
//     adds less than 0.1. clear8() subtracts 0.25 + 0.002 D units^2 from the square before
//     comparing (float_slack2()), and kFloatSlackUnits from the root as before.
//
// Incremental update: set_map() with a grid of the same origin, resolution and size compares it
// with the current one and recomputes only the rows and cells within reach of the changed voxels
// (margin + 1 voxel for the sets, + the distance cap for the distance field).
//
// Thread-safety: const members may be called concurrently; set_map() needs exclusive access.

#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "porter/core/occupancy_grid.hpp"
#include "porter/planner/collision/simd8.hpp"

namespace porter::planner {

struct MapKernelSettings {
  /// Safety margin r_m >= 0 (m): voxels closer than this to an occupied voxel count as occupied.
  double safety_margin_m = 0.0;
  /// Distances above this are stored as this (m); bounds the reach of an incremental update.
  double distance_cap_m = 1.0;
};

struct MapUpdateStats {
  bool incremental = false;  ///< false: everything was rebuilt
  std::int64_t changed_voxels = 0;
  Eigen::Vector3i changed_lo = Eigen::Vector3i::Zero();  ///< grid index box of the changes (inclusive)
  Eigen::Vector3i changed_hi = Eigen::Vector3i::Constant(-1);
};

class MapKernel {
 public:
  /// Edge of a distance-field cell, in voxels; even, so a cell's centre is a lattice vertex.
  /// Two: the field costs a byte per 8 grid voxels (0.44 MB for a 22 x 8 x 2.5 m map at 5 cm).
  /// One-voxel cells (then with the smallest distance over the cell as the bound) execute fewer
  /// instructions per check but take 8x the memory, and the larger field misses the caches more:
  /// no faster on the shipped scenes.
  static constexpr int kCellVoxels = 2;
  static_assert(kCellVoxels % 2 == 0, "cell centres must be lattice vertices");
  static constexpr float kInvCell = 1.f / kCellVoxels;
  /// Subtracted from every clearance bound (units of h / 4): covers float32 rounding of the query
  /// point itself (about 1e-4 units at 500 voxels from the origin); the bound's own evaluation
  /// is covered by float_slack2().
  static constexpr float kFloatSlackUnits = 1.f / 64.f;

  MapKernel() = default;
  /// padding_voxels >= 1 on every side; base_layers >= 1 voxel layers above the ground covered by
  /// the base kernel (for the projection); base_reach2 >= 0 the squared column distance of
  /// base_disc_clear() (-1: no column is ever clear). Throws std::invalid_argument on bad values.
  MapKernel(const MapKernelSettings& settings, int padding_voxels, int base_layers, int base_reach2 = -1);

  /// Replaces the map; incremental when the grid has the current geometry. Throws
  /// std::invalid_argument for an empty grid or a ground that is not a voxel boundary.
  MapUpdateStats set_map(const OccupancyGrid& grid);

  bool has_map() const { return !arm_bricks_.empty(); }
  const MapKernelSettings& settings() const { return settings_; }
  int padding() const { return pad_; }
  double resolution_m() const { return res_; }
  /// World position of padded voxel (0, 0, 0)'s minimum corner.
  const Eigen::Vector3d& padded_origin_W() const { return padded_origin_W_; }
  const Eigen::Vector3i& padded_dims() const { return dims_; }
  const Eigen::Vector3i& grid_dims() const { return grid_dims_; }
  int ground_layer() const { return ground_; }
  int base_layers() const { return base_layers_; }

  /// Bit of the arm set at padded index (precondition: inside the padded array).
  bool arm_bit(int x, int y, int z) const {
    return (arm_bricks_[static_cast<std::size_t>(brick(x, y, z))] >> brick_bit(x, y, z)) & 1u;
  }
  /// Bit of the core set at padded index (precondition: inside the padded array).
  bool core_bit(int x, int y, int z) const {
    const std::int64_t b = static_cast<std::int64_t>(row(y, z)) * row_bits_ + x;
    return (core_[static_cast<std::size_t>(b >> 6)] >> (b & 63)) & 1u;
  }
  /// Whether the point at padded voxel coordinates u lies within sqrt(r2) voxels (Euclidean,
  /// closed) of the box of a core voxel, for r2 < 1: only the 27 voxels around u's voxel can be
  /// that close. Precondition: u's voxel and its neighbours are inside the padded array.
  bool arm_near(float ux, float uy, float uz, float r2) const {
    const int cx = static_cast<int>(ux), cy = static_cast<int>(uy), cz = static_cast<int>(uz);
    const float fx = ux - static_cast<float>(cx), fy = uy - static_cast<float>(cy), fz = uz - static_cast<float>(cz);
    // Squared gap to the neighbour at offset -1, 0, +1 along each axis.
    const float gx[3] = {fx * fx, 0.f, (1.f - fx) * (1.f - fx)};
    const float gy[3] = {fy * fy, 0.f, (1.f - fy) * (1.f - fy)};
    const float gz[3] = {fz * fz, 0.f, (1.f - fz) * (1.f - fz)};
    for (int dz = 0; dz < 3; ++dz)
      for (int dy = 0; dy < 3; ++dy) {
        const float gyz = gy[dy] + gz[dz];
        if (gyz > r2) continue;
        const std::int64_t b = static_cast<std::int64_t>(row(cy + dy - 1, cz + dz - 1)) * row_bits_ + (cx - 1);
        const std::size_t w = static_cast<std::size_t>(b >> 6);
        const int s = static_cast<int>(b & 63);
        const std::uint64_t bits3 = ((core_[w] >> s) | ((core_[w + 1] << 1) << (63 - s))) & 7u;
        if (!bits3) continue;
        for (int dx = 0; dx < 3; ++dx)
          if (((bits3 >> dx) & 1u) && gx[dx] + gyz <= r2) return true;
      }
    return false;
  }
  /// 64 bits of the base set starting at padded x in row (y, z): bit i is voxel x + i.
  std::uint64_t base_window(int x, int y, int z) const {
    const std::int64_t b = static_cast<std::int64_t>(row(y, z)) * row_bits_ + x;
    const std::size_t w = static_cast<std::size_t>(b >> 6);
    const int s = static_cast<int>(b & 63);
    return (base_[w] >> s) | ((base_[w + 1] << 1) << (63 - s));
  }
  bool base_bit(int x, int y, int z) const { return base_window(x, y, z) & 1u; }
  /// Number of (x, y) columns in [x0, x1] x [y0, y1] (padded, inclusive, inside the array) with
  /// a base-set voxel in the base layers. Precondition: the rectangle has fewer than 65 536
  /// columns (the base kernel's tiles and footprint have a few hundred).
  std::int64_t base_columns_set(int x0, int y0, int x1, int y1) const {
    const std::int64_t sx = dims_.x() + 1;
    auto at = [&](int x, int y) { return sat_[static_cast<std::size_t>(x + sx * y)]; };
    // Sums modulo 2^16 (see sat_): exact for rectangles of fewer than 65 536 columns.
    return static_cast<std::uint16_t>(at(x1 + 1, y1 + 1) - at(x0, y1 + 1) - at(x1 + 1, y0) + at(x0, y0));
  }
  /// Whether no column of the base set's projection has its centre within sqrt(base_reach2)
  /// columns of column (x, y)'s centre (padded indices; precondition: inside the padded array).
  bool base_disc_clear(int x, int y) const {
    const std::int64_t b = static_cast<std::int64_t>(y) * dims_.x() + x;
    return (base_disc_[static_cast<std::size_t>(b >> 6)] >> (b & 63)) & 1u;
  }
  int base_reach2() const { return base_reach2_; }
  /// Lower bound (>= 0), in units of h / 4, of the distance from the point at padded voxel
  /// coordinates u (u = (p_W - padded_origin_W) / h) to the core set: the interpolated bound
  /// above, less float_slack2() in the square and kFloatSlackUnits after the root; 0 where the
  /// eight cells around u are not all in the field's array (more than a cell outside the grid's
  /// region). The reference for clear8().
  float clearance_units(float ux, float uy, float uz) const {
    const float u[3] = {ux, uy, uz};
    int c[3];
    float t[3];
    for (int a = 0; a < 3; ++a) {
      const float f = (u[a] - cell_offset_) * kInvCell - 0.5f;
      // The cube's low corner floor(f) in [-1, cells - 1]; NaN fails too.
      if (!(f >= -1.f && f < static_cast<float>(cells_[a]))) return 0.f;
      c[a] = static_cast<int>(f + 1.f) - 1;
      t[a] = f - static_cast<float>(c[a]);
    }
    const std::uint8_t* q = &clearance_[field_index(c[0], c[1], c[2])];
    auto v2 = [&](int dx, int dy, int dz) {
      const float v = q[static_cast<std::size_t>(dx) + field_sy_ * dy + field_sz_ * dz];
      return v * v;
    };
    const float e00 = v2(0, 0, 0) + t[0] * (v2(1, 0, 0) - v2(0, 0, 0)), e10 = v2(0, 1, 0) + t[0] * (v2(1, 1, 0) - v2(0, 1, 0));
    const float e01 = v2(0, 0, 1) + t[0] * (v2(1, 0, 1) - v2(0, 0, 1)), e11 = v2(0, 1, 1) + t[0] * (v2(1, 1, 1) - v2(0, 1, 1));
    const float e0 = e00 + t[1] * (e10 - e00), e1 = e01 + t[1] * (e11 - e01);
    const float var = t[0] * (1.f - t[0]) + t[1] * (1.f - t[1]) + t[2] * (1.f - t[2]);
    const float b2 = e0 + t[2] * (e1 - e0) - kCellUnits2 * var - float_slack2_;
    return b2 > 0.f ? std::max(std::sqrt(b2) - kFloatSlackUnits, 0.f) : 0.f;
  }

  /// Lane mask of the eight points whose clearance_units() exceeds need (>= 0; bit i: point i is
  /// farther than need_i units from the core set), compared in squares: (need + kFloatSlackUnits)^2
  /// against the bound's square less float_slack2(). NaN anywhere leaves the lane clear of nothing.
  PORTER_SIMD_INLINE std::uint32_t clear8(const v8f& ux, const v8f& uy, const v8f& uz, const v8f& need) const {
    const v8f off = v8f_splat(cell_offset_), inv_cell = v8f_splat(kInvCell), half = v8f_splat(0.5f);
    const v8f fx = (ux - off) * inv_cell - half, fy = (uy - off) * inv_cell - half, fz = (uz - off) * inv_cell - half;
    // s = floor(f) + 1, the cube's low corner in the field's array (ring included), exact for
    // f >= -2; unsigned, so lanes far outside (or NaN) wrap around instead of overflowing.
    const v8f two = v8f_splat(2.f), one = v8f_splat(1.f);
    const v8u sx = v8u(v8_trunc(fx + two)) - 1u, sy = v8u(v8_trunc(fy + two)) - 1u, sz = v8u(v8_trunc(fz + two)) - 1u;
    const v8f tx = fx + one - v8_float(v8i(sx)), ty = fy + one - v8_float(v8i(sy)), tz = fz + one - v8_float(v8i(sz));
    // Inside: the low corner in [-1, cells - 1] on every axis, i.e. s < cells + 1.
    const v8i inside = (sx < v8u(v8i_splat(cells_.x() + 1))) & (sy < v8u(v8i_splat(cells_.y() + 1))) &
                       (sz < v8u(v8i_splat(cells_.z() + 1)));
    const v8u index = (sx + v8u(v8i_splat(static_cast<std::int32_t>(field_sy_))) * sy +
                       v8u(v8i_splat(static_cast<std::int32_t>(field_sz_))) * sz) &
                      v8u(inside);  // outside lanes read entry 0
    // Per lane two 32-bit words of bytes: (x, y), (x+1, y), (x, y+1), (x+1, y+1) of the cube's
    // low face (lo) and high face (hi), two bytes per load.
    const std::uint8_t* values = clearance_.data();
    const std::size_t row = field_sy_, slice = field_sz_;
    v8i lo, hi;
    for (int i = 0; i < 8; ++i) {
      const std::uint8_t* q = values + index[i];
      std::uint16_t a, b, c, d;
      std::memcpy(&a, q, 2);
      std::memcpy(&b, q + row, 2);
      std::memcpy(&c, q + slice, 2);
      std::memcpy(&d, q + slice + row, 2);
      lo[i] = static_cast<std::int32_t>(a | (static_cast<std::uint32_t>(b) << 16));
      hi[i] = static_cast<std::int32_t>(c | (static_cast<std::uint32_t>(d) << 16));
    }
    const v8i byte = v8i_splat(255);
    auto square = [&byte](const v8i& word, int shift) PORTER_SIMD_LAMBDA {
      const v8f v = v8_float((word >> shift) & byte);
      return v * v;
    };
    const v8f v000 = square(lo, 0), v100 = square(lo, 8), v010 = square(lo, 16), v110 = square(lo, 24);
    const v8f v001 = square(hi, 0), v101 = square(hi, 8), v011 = square(hi, 16), v111 = square(hi, 24);
    const v8f e00 = v000 + tx * (v100 - v000), e10 = v010 + tx * (v110 - v010);
    const v8f e01 = v001 + tx * (v101 - v001), e11 = v011 + tx * (v111 - v011);
    const v8f e0 = e00 + ty * (e10 - e00), e1 = e01 + ty * (e11 - e01);
    const v8f var = tx * (one - tx) + ty * (one - ty) + tz * (one - tz);
    const v8f b2 = e0 + tz * (e1 - e0) - v8f_splat(kCellUnits2) * var - v8f_splat(float_slack2_);
    const v8f n = need + v8f_splat(kFloatSlackUnits);
    // Outside lanes: offsets t may lie outside [0, 1) there, so the variance term is no bound.
    return lane_mask(inside & (n > v8f_splat(0.f)) & (b2 > n * n));
  }
  /// The squared slack clear8() subtracts from the bound (units^2 of h / 4; see the header).
  float float_slack2() const { return float_slack2_; }
  /// arm_bit() of eight points at padded voxel coordinates u (truncated to their voxels), as a
  /// lane mask. Precondition: every voxel inside the padded array.
  PORTER_SIMD_INLINE std::uint32_t arm_bits8(const v8f& ux, const v8f& uy, const v8f& uz) const {
    const v8i ix = v8_trunc(ux), iy = v8_trunc(uy), iz = v8_trunc(uz);
    const v8i word = (ix >> 2) + v8i_splat(bricks_.x()) * ((iy >> 2) + v8i_splat(bricks_.y()) * (iz >> 2));
    const v8i bit = (ix & 3) | ((iy & 3) << 2) | ((iz & 3) << 4);
    std::uint32_t mask = 0;
    for (int i = 0; i < 8; ++i)
      mask |= static_cast<std::uint32_t>((arm_bricks_[static_cast<std::uint32_t>(word[i])] >> bit[i]) & 1u) << i;
    return mask;
  }

  /// Reference accessors (slow, for tests): membership of the sets at padded indices; false
  /// outside the padded array.
  bool in_occupied(int x, int y, int z) const;
  bool in_margin(int x, int y, int z) const;  ///< O_m
  bool in_base(int x, int y, int z) const;
  bool in_arm(int x, int y, int z) const;
  bool in_core(int x, int y, int z) const;

  std::size_t bytes() const;

 private:
  std::int64_t row(int y, int z) const { return y + static_cast<std::int64_t>(dims_.y()) * z; }
  std::int64_t brick(int x, int y, int z) const {
    return (x >> 2) + static_cast<std::int64_t>(bricks_.x()) * ((y >> 2) + static_cast<std::int64_t>(bricks_.y()) * (z >> 2));
  }
  static int brick_bit(int x, int y, int z) { return (x & 3) | ((y & 3) << 2) | ((z & 3) << 4); }
  /// Entry of distance-field cell (x, y, z), -1 <= x <= cells_.x() (the zero ring included).
  std::size_t field_index(int x, int y, int z) const {
    return static_cast<std::size_t>(x + 1) + field_sy_ * static_cast<std::size_t>(y + 1) +
           field_sz_ * static_cast<std::size_t>(z + 1);
  }
  /// A cell's edge in clearance units, squared (the variance term's A^2).
  static constexpr float kCellUnits2 = 16.f * kCellVoxels * kCellVoxels;
  void allocate(const OccupancyGrid& grid);
  /// A grid index box of changed voxels (inclusive).
  struct ChangeBox {
    Eigen::Vector3i lo = Eigen::Vector3i::Zero(), hi = Eigen::Vector3i::Constant(-1);
    bool empty() const { return (hi.array() < lo.array()).any(); }
  };
  /// Edge of the xy tiles that changes are gathered in, grid voxels.
  static constexpr int kChangeTileVoxels = 32;
  /// Copies the grid into O, reports the changes in stats and, when `tiles` is given, one box per
  /// kChangeTileVoxels^2 column tile (tile tx + ntx * ty) around that tile's changes.
  bool copy_grid_rows(const OccupancyGrid& grid, MapUpdateStats& stats, std::vector<ChangeBox>* tiles = nullptr);
  /// The non-empty tile boxes, merged where one region grown by `grow` voxels (and clipped to
  /// two voxels beyond a grid of `dims`) is no larger than the two apart (at most 64 boxes; more
  /// are merged into one).
  static std::vector<ChangeBox> merge_change_boxes(const std::vector<ChangeBox>& tiles, int grow,
                                                   const Eigen::Vector3i& dims);
  void rebuild_rows(int y0, int y1, int z0, int z1);
  void rebuild_projection();  ///< summed-area table and column bits
  void rebuild_clearance(const Eigen::Vector3i& cell_lo, const Eigen::Vector3i& cell_hi);
  bool outside_base_row(int y, int z) const;
  bool outside_arm_row(int y, int z) const;

  MapKernelSettings settings_;
  int pad_ = 1;
  int base_layers_ = 1;
  int margin_voxels_ = 0;
  std::vector<int> margin_half_width_;  ///< x half-width per (dy, dz), -1 when none; (2k+1)^2
  double res_ = 0.0;
  Eigen::Vector3d grid_origin_W_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d padded_origin_W_ = Eigen::Vector3d::Zero();
  Eigen::Vector3i grid_dims_ = Eigen::Vector3i::Zero();
  Eigen::Vector3i dims_ = Eigen::Vector3i::Zero();
  int ground_ = 0;
  std::int64_t words_per_row_ = 0, row_bits_ = 0;
  std::vector<std::uint64_t> occ_, base_, core_;  ///< O, base and core sets (padded rows)
  Eigen::Vector3i bricks_ = Eigen::Vector3i::Zero();  ///< arm bricks per axis: ceil(padded dims / 4)
  std::vector<std::uint64_t> arm_bricks_;             ///< the arm set, one word per brick
  std::vector<std::uint64_t> edge_mask_;         ///< one row: bits outside the grid's x range
  /// (Nx + 1) x (Ny + 1) summed-area table, modulo 2^16: a rectangle's count (below 2^16) comes
  /// out exact from four entries in modular arithmetic, at half the memory of 32-bit sums (a
  /// base check reads eight scattered entries; fewer cache misses).
  std::vector<std::uint16_t> sat_;
  int base_reach2_ = -1;
  std::vector<std::uint64_t> base_disc_;  ///< base_disc_clear() bits, column y * Nx + x
  Eigen::Vector3i cells_ = Eigen::Vector3i::Zero();
  float cell_offset_ = 0.f;  ///< = padding (cells start at the grid)
  int cap_units_ = 0;
  float float_slack2_ = 0.f;                 ///< see float_slack2()
  std::size_t field_sy_ = 0, field_sz_ = 0;  ///< strides of clearance_ (cells + 2 per axis)
  std::vector<std::uint8_t> clearance_;      ///< the field, with a ring of zero cells
};

}  // namespace porter::planner
