#include "porter/planner/collision/map_kernel.hpp"

#include <algorithm>
#include <bitset>
#include <cmath>
#include <stdexcept>
#include <string>

#include "bit_rows.hpp"

namespace porter::planner {

MapKernel::MapKernel(const MapKernelSettings& settings, int padding_voxels, int base_layers, int base_reach2)
    : settings_(settings), pad_(padding_voxels), base_layers_(base_layers), base_reach2_(base_reach2) {
  if (padding_voxels < 1) throw std::invalid_argument("MapKernel: padding_voxels must be >= 1");
  if (base_layers < 1) throw std::invalid_argument("MapKernel: base_layers must be >= 1");
  if (base_reach2 < -1) throw std::invalid_argument("MapKernel: base_reach2 must be >= 0 (or -1 for none)");
  if (!(settings.safety_margin_m >= 0.0) || !std::isfinite(settings.safety_margin_m))
    throw std::invalid_argument("MapKernel: safety_margin_m must be finite and >= 0");
  if (!(settings.distance_cap_m > 0.0) || !std::isfinite(settings.distance_cap_m))
    throw std::invalid_argument("MapKernel: distance_cap_m must be finite and > 0");
}

void MapKernel::allocate(const OccupancyGrid& grid) {
  res_ = grid.resolution_m();
  grid_origin_W_ = grid.origin_W();
  grid_dims_ = grid.dims();
  const double t = -grid_origin_W_.z() / res_;
  const double ground_index = std::round(t);
  if (std::abs(t - ground_index) > 1e-6)
    throw std::invalid_argument("MapKernel: the ground z = 0 is not a voxel boundary of the grid (origin z = " +
                                std::to_string(grid_origin_W_.z()) + ")");
  dims_ = grid_dims_ + Eigen::Vector3i::Constant(2 * pad_);
  ground_ = pad_ + static_cast<int>(ground_index);
  padded_origin_W_ = grid_origin_W_ - Eigen::Vector3d::Constant(pad_ * res_);
  words_per_row_ = (dims_.x() + 63) / 64 + 1;
  row_bits_ = 64 * words_per_row_;
  const auto n_words = static_cast<std::size_t>(words_per_row_ * dims_.y() * static_cast<std::int64_t>(dims_.z()));
  bricks_ = (dims_ + Eigen::Vector3i::Constant(3)) / 4;
  const auto n_bricks = static_cast<std::size_t>(bricks_.x()) * static_cast<std::size_t>(bricks_.y()) *
                        static_cast<std::size_t>(bricks_.z());
  cells_ = (grid_dims_ + Eigen::Vector3i::Constant(kCellVoxels - 1)) / kCellVoxels;
  field_sy_ = static_cast<std::size_t>(cells_.x()) + 2;
  field_sz_ = field_sy_ * (static_cast<std::size_t>(cells_.y()) + 2);
  const std::size_t field_entries = field_sz_ * (static_cast<std::size_t>(cells_.z()) + 2);
  // arm_bits8() and clear8() index with 32-bit lanes (16 GiB of bits per set, 2 GiB of cells).
  if (n_words > static_cast<std::size_t>(INT32_MAX) || n_bricks > static_cast<std::size_t>(INT32_MAX) ||
      field_entries > static_cast<std::size_t>(INT32_MAX))
    throw std::invalid_argument("MapKernel: padded map too large (" + std::to_string(n_words) + " words per set, " +
                                std::to_string(field_entries) + " distance cells)");
  occ_.assign(n_words, 0);
  base_.assign(n_words, 0);
  arm_bricks_.assign(n_bricks, 0);
  core_.assign(n_words, 0);
  edge_mask_.assign(static_cast<std::size_t>(words_per_row_), 0);
  for (std::int64_t x = 0; x < row_bits_; ++x)
    if (x < pad_ || x >= pad_ + grid_dims_.x())
      edge_mask_[static_cast<std::size_t>(x >> 6)] |= std::uint64_t{1} << (x & 63);

  // Margin: voxel offsets whose boxes are closer than r_m (strictly); per (dy, dz) an x half-width.
  const double r = settings_.safety_margin_m;
  margin_voxels_ = r > 0.0 ? static_cast<int>(std::ceil(r / res_ - 1e-12)) : 0;
  if (margin_voxels_ > 60) throw std::invalid_argument("MapKernel: safety margin wider than 60 voxels");
  const int k = margin_voxels_, n = 2 * k + 1;
  margin_half_width_.assign(static_cast<std::size_t>(n * n), -1);
  auto gap = [](int d) { return std::max(std::abs(d) - 1, 0); };
  for (int dz = -k; dz <= k; ++dz)
    for (int dy = -k; dy <= k; ++dy) {
      int best = -1;
      for (int a = 0; a <= k; ++a) {
        const double g2 = res_ * res_ * (gap(a) * gap(a) + gap(dy) * gap(dy) + gap(dz) * gap(dz));
        if ((r == 0.0 && a == 0 && dy == 0 && dz == 0) || (r > 0.0 && g2 < r * r)) best = a;
      }
      margin_half_width_[static_cast<std::size_t>((dy + k) + n * (dz + k))] = best;
    }

  cell_offset_ = static_cast<float>(pad_);
  cap_units_ = std::min(255, static_cast<int>(std::floor(4.0 * settings_.distance_cap_m / res_)));
  clearance_.assign(field_entries, 0);
  float_slack2_ = 0.25f + 0.002f * static_cast<float>(dims_.maxCoeff());
  sat_.assign(static_cast<std::size_t>(dims_.x() + 1) * static_cast<std::size_t>(dims_.y() + 1), 0);
}

bool MapKernel::copy_grid_rows(const OccupancyGrid& grid, MapUpdateStats& stats, std::vector<ChangeBox>* tiles) {
  const std::vector<std::uint64_t>& src = grid.words();
  const std::int64_t nx = grid_dims_.x();
  std::vector<std::uint64_t> tmp(static_cast<std::size_t>(words_per_row_));
  constexpr int T = kChangeTileVoxels;
  const int ntx = (grid_dims_.x() + T - 1) / T, nty = (grid_dims_.y() + T - 1) / T;
  if (tiles) tiles->assign(static_cast<std::size_t>(ntx) * static_cast<std::size_t>(nty), ChangeBox{});
  bool changed = false;
  for (int iz = 0; iz < grid_dims_.z(); ++iz)
    for (int iy = 0; iy < grid_dims_.y(); ++iy) {
      std::fill(tmp.begin(), tmp.end(), 0);
      const std::int64_t a = grid.linear_index(0, iy, iz);
      const std::int64_t b = pad_;
      for (std::int64_t kw = b >> 6; kw * 64 < b + nx; ++kw) {
        const std::int64_t lo = std::max(b, kw * 64), hi = std::min(b + nx, kw * 64 + 64);
        const std::uint64_t v = bits::read64(src.data(), src.size(), a + (lo - b));
        const int sh = static_cast<int>(lo - kw * 64);
        tmp[static_cast<std::size_t>(kw)] |= (v & bits::low_mask(static_cast<int>(hi - lo))) << sh;
      }
      std::uint64_t* dst = &occ_[static_cast<std::size_t>(row(iy + pad_, iz + pad_) * words_per_row_)];
      for (std::int64_t kw = 0; kw < words_per_row_; ++kw) {
        const std::uint64_t diff = dst[kw] ^ tmp[static_cast<std::size_t>(kw)];
        if (!diff) continue;
        changed = true;
        const int x_first = static_cast<int>(kw * 64 + __builtin_ctzll(diff)) - pad_;
        const int x_last = static_cast<int>(kw * 64 + 63 - __builtin_clzll(diff)) - pad_;
        const Eigen::Vector3i lo(x_first, iy, iz), hi(x_last, iy, iz);
        const bool first = stats.changed_voxels == 0;
        stats.changed_lo = first ? lo : Eigen::Vector3i(stats.changed_lo.cwiseMin(lo));
        stats.changed_hi = first ? hi : Eigen::Vector3i(stats.changed_hi.cwiseMax(hi));
        stats.changed_voxels += static_cast<std::int64_t>(std::bitset<64>(diff).count());
        if (tiles) {
          for (int tx = std::max(x_first, 0) / T; tx <= std::min(x_last, grid_dims_.x() - 1) / T; ++tx) {
            ChangeBox& b = (*tiles)[static_cast<std::size_t>(tx + ntx * (iy / T))];
            const Eigen::Vector3i a(std::max(x_first, tx * T), iy, iz), c(std::min(x_last, tx * T + T - 1), iy, iz);
            const bool fresh = b.empty();
            b.lo = fresh ? a : Eigen::Vector3i(b.lo.cwiseMin(a));
            b.hi = fresh ? c : Eigen::Vector3i(b.hi.cwiseMax(c));
          }
        }
        dst[kw] = tmp[static_cast<std::size_t>(kw)];
      }
    }
  return changed;
}

bool MapKernel::outside_base_row(int y, int z) const {
  if (y < pad_ || y >= pad_ + grid_dims_.y()) return true;
  if (z >= pad_ + grid_dims_.z()) return true;
  return z >= ground_ && z < pad_;  // between the ground and a grid that starts above it
}

bool MapKernel::outside_arm_row(int y, int z) const {
  if (y < pad_ || y >= pad_ + grid_dims_.y()) return true;
  if (z < pad_ || z >= pad_ + grid_dims_.z()) return true;
  return z < ground_;
}

void MapKernel::rebuild_rows(int y0, int y1, int z0, int z1) {
  y0 = std::max(y0, 0);
  z0 = std::max(z0, 0);
  y1 = std::min(y1, dims_.y() - 1);
  z1 = std::min(z1, dims_.z() - 1);
  if (y0 > y1 || z0 > z1) return;
  const std::int64_t W = words_per_row_;
  // O_m for the rows one beyond the target rows (the 26-dilation of the arm set reads them).
  const int my0 = std::max(y0 - 1, 0), my1 = std::min(y1 + 1, dims_.y() - 1);
  const int mz0 = std::max(z0 - 1, 0), mz1 = std::min(z1 + 1, dims_.z() - 1);
  const int mny = my1 - my0 + 1;
  std::vector<std::uint64_t> om(static_cast<std::size_t>(W) * mny * (mz1 - mz0 + 1), 0);
  auto om_row = [&](int y, int z) { return &om[static_cast<std::size_t>(W * ((y - my0) + mny * (z - mz0)))]; };
  const int k = margin_voxels_, n = 2 * k + 1;
  // O dilated along x by a = 0..k for the source rows (each from the previous by one step),
  // then O_m(y, z) = OR over (dy, dz) of the x-dilation a(dy, dz) of row (y + dy, z + dz).
  const int sy0 = std::max(my0 - k, 0), sy1 = std::min(my1 + k, dims_.y() - 1);
  const int sz0 = std::max(mz0 - k, 0), sz1 = std::min(mz1 + k, dims_.z() - 1);
  const int sny = sy1 - sy0 + 1;
  const std::size_t src_rows = static_cast<std::size_t>(sny) * static_cast<std::size_t>(sz1 - sz0 + 1);
  std::vector<std::uint64_t> xd(static_cast<std::size_t>(k + 1) * src_rows * static_cast<std::size_t>(W), 0);
  auto xd_row = [&](int a, int y, int z) {
    return &xd[(static_cast<std::size_t>(a) * src_rows + static_cast<std::size_t>((y - sy0) + sny * (z - sz0))) *
               static_cast<std::size_t>(W)];
  };
  for (int z = sz0; z <= sz1; ++z)
    for (int y = sy0; y <= sy1; ++y) {
      std::copy_n(&occ_[static_cast<std::size_t>(row(y, z) * W)], W, xd_row(0, y, z));
      for (int a = 1; a <= k; ++a) bits::or_dilated(xd_row(a, y, z), xd_row(a - 1, y, z), W, 1);
    }
  for (int z = mz0; z <= mz1; ++z)
    for (int y = my0; y <= my1; ++y) {
      std::uint64_t* dst = om_row(y, z);
      for (int dz = -k; dz <= k; ++dz)
        for (int dy = -k; dy <= k; ++dy) {
          const int a = margin_half_width_[static_cast<std::size_t>((dy + k) + n * (dz + k))];
          const int ry = y + dy, rz = z + dz;
          if (a < 0 || ry < 0 || rz < 0 || ry >= dims_.y() || rz >= dims_.z()) continue;
          const std::uint64_t* src = xd_row(a, ry, rz);
          for (std::int64_t w = 0; w < W; ++w) dst[w] |= src[w];
        }
    }
  std::vector<std::uint64_t> src(static_cast<std::size_t>(W)), arm_row(static_cast<std::size_t>(W));
  for (int z = z0; z <= z1; ++z)
    for (int y = y0; y <= y1; ++y) {
      std::uint64_t* b = &base_[static_cast<std::size_t>(row(y, z) * W)];
      const std::uint64_t* m = om_row(y, z);
      if (z < ground_) {
        std::fill(b, b + W, 0);  // below the ground: nothing for the base (it never looks there)
      } else {
        const bool out_b = outside_base_row(y, z);
        for (std::int64_t w = 0; w < W; ++w)
          b[w] = out_b ? ~std::uint64_t{0} : (m[w] | edge_mask_[static_cast<std::size_t>(w)]);
      }
      std::uint64_t* c = &core_[static_cast<std::size_t>(row(y, z) * W)];
      const bool out_c = outside_arm_row(y, z);
      for (std::int64_t w = 0; w < W; ++w)
        c[w] = out_c ? ~std::uint64_t{0} : (m[w] | edge_mask_[static_cast<std::size_t>(w)]);
      std::uint64_t* a = arm_row.data();
      std::fill(a, a + W, 0);
      bool full = false;
      for (int dz = -1; dz <= 1 && !full; ++dz)
        for (int dy = -1; dy <= 1 && !full; ++dy) {
          const int sy = y + dy, sz = z + dz;
          if (sy < 0 || sz < 0 || sy >= dims_.y() || sz >= dims_.z() || outside_arm_row(sy, sz)) {
            full = true;
            break;
          }
          const std::uint64_t* ms = om_row(sy, sz);
          for (std::int64_t w = 0; w < W; ++w)
            src[static_cast<std::size_t>(w)] = ms[w] | edge_mask_[static_cast<std::size_t>(w)];
          bits::or_dilated(a, src.data(), W, 1);
        }
      if (full) std::fill(a, a + W, ~std::uint64_t{0});
      // Into the bricks: four bits of the row per brick, at the row's place in it.
      const int shift = brick_bit(0, y, z);
      const std::size_t first = static_cast<std::size_t>(brick(0, y, z));
      for (int bx = 0; bx < bricks_.x(); ++bx) {
        const std::uint64_t nibble = (a[bx >> 4] >> (4 * (bx & 15))) & 0xfu;
        std::uint64_t& word = arm_bricks_[first + static_cast<std::size_t>(bx)];
        word = (word & ~(std::uint64_t{0xf} << shift)) | (nibble << shift);
      }
    }
}

std::vector<MapKernel::ChangeBox> MapKernel::merge_change_boxes(const std::vector<ChangeBox>& tiles, int grow,
                                                                const Eigen::Vector3i& dims) {
  std::vector<ChangeBox> boxes;
  for (const ChangeBox& b : tiles)
    if (!b.empty()) boxes.push_back(b);
  // Voxels of a box grown by `grow` on every side (the region its update touches).
  auto grown_volume = [grow, &dims](const ChangeBox& b) {
    const Eigen::Vector3i lo = (b.lo - Eigen::Vector3i::Constant(grow)).cwiseMax(-2);
    const Eigen::Vector3i hi = (b.hi + Eigen::Vector3i::Constant(grow)).cwiseMin(dims + Eigen::Vector3i::Ones());
    const Eigen::Vector3i e = (hi - lo + Eigen::Vector3i::Ones()).cwiseMax(1);
    return static_cast<double>(e.x()) * e.y() * e.z();
  };
  auto unite = [](const ChangeBox& a, const ChangeBox& b) {
    ChangeBox u;
    u.lo = a.lo.cwiseMin(b.lo);
    u.hi = a.hi.cwiseMax(b.hi);
    return u;
  };
  // Beyond this many boxes the pairwise merging costs more than it saves: one box.
  constexpr std::size_t kMaxBoxes = 64;
  if (boxes.size() > kMaxBoxes) {
    ChangeBox all = boxes.front();
    for (const ChangeBox& b : boxes) all = unite(all, b);
    return {all};
  }
  // Greedy: merge a pair while one update over the union costs no more than the two apart.
  for (bool merged = true; merged;) {
    merged = false;
    for (std::size_t i = 0; i < boxes.size() && !merged; ++i)
      for (std::size_t j = i + 1; j < boxes.size() && !merged; ++j) {
        const ChangeBox u = unite(boxes[i], boxes[j]);
        if (grown_volume(u) <= grown_volume(boxes[i]) + grown_volume(boxes[j])) {
          boxes[i] = u;
          boxes.erase(boxes.begin() + static_cast<std::ptrdiff_t>(j));
          merged = true;
        }
      }
  }
  return boxes;
}

MapUpdateStats MapKernel::set_map(const OccupancyGrid& grid) {
  if (grid.num_voxels() == 0) throw std::invalid_argument("MapKernel: empty occupancy grid");
  MapUpdateStats stats;
  const bool same =
      has_map() && grid.resolution_m() == res_ && grid.origin_W() == grid_origin_W_ && grid.dims() == grid_dims_;
  if (!same) {
    allocate(grid);
    copy_grid_rows(grid, stats);
    rebuild_rows(0, dims_.y() - 1, 0, dims_.z() - 1);
    rebuild_projection();
    rebuild_clearance(Eigen::Vector3i::Zero(), cells_ - Eigen::Vector3i::Ones());
    return stats;
  }
  stats.incremental = true;
  std::vector<ChangeBox> tiles;
  if (!copy_grid_rows(grid, stats, &tiles)) return stats;
  // The changes of a mapper's update are scattered over the map (a few voxels here and there in
  // the sensor's range): one box around all of them made the distance field's update as costly
  // as a rebuild (120-240 ms on a 36 x 24 x 4 m grid with ~100 changed voxels). The tiles' boxes
  // are merged where one update over their union costs no more than two, and each is updated
  // on its own; the sets and the field are exact either way (each update recomputes its region
  // from O).
  const int reach = margin_voxels_ + 1;
  const int cap_cells = static_cast<int>(std::ceil(cap_units_ / (4.0 * kCellVoxels))) + 2;  // cap in cells
  // An update's region: the box grown by the rows' reach and the cap (the cells), then by the
  // distance transform's own reach (rebuild_clearance's domain).
  const int domain_reach = static_cast<int>(std::ceil(cap_units_ / 4.0)) + 2;
  const std::vector<ChangeBox> boxes =
      merge_change_boxes(tiles, kCellVoxels * cap_cells + reach + domain_reach, grid_dims_);
  for (const ChangeBox& b : boxes) {
    const Eigen::Vector3i lo = b.lo + Eigen::Vector3i::Constant(pad_ - reach);
    const Eigen::Vector3i hi = b.hi + Eigen::Vector3i::Constant(pad_ + reach);
    rebuild_rows(lo.y(), hi.y(), lo.z(), hi.z());
  }
  rebuild_projection();
  for (const ChangeBox& b : boxes) {
    // Cells whose voxels may have changed in the arm set, grown by the distance cap: every cell
    // whose (capped) distance can see a changed voxel.
    const Eigen::Vector3i lo = b.lo + Eigen::Vector3i::Constant(pad_ - reach);
    const Eigen::Vector3i hi = b.hi + Eigen::Vector3i::Constant(pad_ + reach);
    const Eigen::Vector3i cell_lo =
        ((lo - Eigen::Vector3i::Constant(pad_)).cwiseMax(0)) / kCellVoxels - Eigen::Vector3i::Constant(cap_cells);
    const Eigen::Vector3i cell_hi =
        ((hi - Eigen::Vector3i::Constant(pad_)).cwiseMax(0)) / kCellVoxels + Eigen::Vector3i::Constant(cap_cells);
    rebuild_clearance(cell_lo, cell_hi);
  }
  return stats;
}

bool MapKernel::in_occupied(int x, int y, int z) const {
  if (x < 0 || y < 0 || z < 0 || x >= dims_.x() || y >= dims_.y() || z >= dims_.z()) return false;
  const std::int64_t b = row(y, z) * row_bits_ + x;
  return (occ_[static_cast<std::size_t>(b >> 6)] >> (b & 63)) & 1u;
}

bool MapKernel::in_margin(int x, int y, int z) const {
  const int k = margin_voxels_, n = 2 * k + 1;
  for (int dz = -k; dz <= k; ++dz)
    for (int dy = -k; dy <= k; ++dy) {
      const int a = margin_half_width_[static_cast<std::size_t>((dy + k) + n * (dz + k))];
      for (int dx = -a; dx <= a; ++dx)
        if (in_occupied(x + dx, y + dy, z + dz)) return true;
    }
  return false;
}

bool MapKernel::in_base(int x, int y, int z) const {
  if (x < 0 || y < 0 || z < 0 || x >= dims_.x() || y >= dims_.y() || z >= dims_.z()) return false;
  return base_bit(x, y, z);
}

bool MapKernel::in_arm(int x, int y, int z) const {
  if (x < 0 || y < 0 || z < 0 || x >= dims_.x() || y >= dims_.y() || z >= dims_.z()) return false;
  return arm_bit(x, y, z);
}

bool MapKernel::in_core(int x, int y, int z) const {
  if (x < 0 || y < 0 || z < 0 || x >= dims_.x() || y >= dims_.y() || z >= dims_.z()) return false;
  const std::int64_t b = row(y, z) * row_bits_ + x;
  return (core_[static_cast<std::size_t>(b >> 6)] >> (b & 63)) & 1u;
}

std::size_t MapKernel::bytes() const {
  return (occ_.size() + base_.size() + arm_bricks_.size() + core_.size() + edge_mask_.size()) * sizeof(std::uint64_t) +
         sat_.size() * sizeof(std::uint16_t) + base_disc_.size() * sizeof(std::uint64_t) + clearance_.size();
}

}  // namespace porter::planner
