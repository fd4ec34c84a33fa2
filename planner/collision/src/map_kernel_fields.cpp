// Derived fields of the map kernel: the base projection's summed-area table and disc bits, and the cell
// distance field (exact squared Euclidean distance transform, Felzenszwalb & Huttenlocher).
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "edt.hpp"
#include "porter/planner/collision/map_kernel.hpp"

namespace porter::planner {

void MapKernel::rebuild_projection() {
  const std::int64_t W = words_per_row_;
  const int nx = dims_.x(), ny = dims_.y();
  const int z_end = std::min(ground_ + base_layers_, dims_.z());
  const std::int64_t sx = nx + 1;
  const std::int64_t columns = static_cast<std::int64_t>(nx) * ny;
  // The projected columns, as sites of the column bits' distance transform (when they are used).
  std::vector<std::uint8_t> site(base_reach2_ >= 0 ? static_cast<std::size_t>(columns) : 0);
  std::vector<std::uint64_t> proj(static_cast<std::size_t>(W));
  for (int y = 0; y < ny; ++y) {
    std::fill(proj.begin(), proj.end(), 0);
    for (int z = std::max(ground_, 0); z < z_end; ++z) {
      const std::uint64_t* b = &base_[static_cast<std::size_t>(row(y, z) * W)];
      for (std::int64_t w = 0; w < W; ++w) proj[static_cast<std::size_t>(w)] |= b[w];
    }
    std::uint16_t run = 0;  // modulo 2^16, like the table
    for (int x = 0; x < nx; ++x) {
      const auto set = static_cast<std::uint8_t>((proj[static_cast<std::size_t>(x >> 6)] >> (x & 63)) & 1u);
      run = static_cast<std::uint16_t>(run + set);
      sat_[static_cast<std::size_t>((x + 1) + sx * (y + 1))] =
          static_cast<std::uint16_t>(sat_[static_cast<std::size_t>((x + 1) + sx * y)] + run);
      if (!site.empty()) site[static_cast<std::size_t>(x + static_cast<std::int64_t>(nx) * y)] = set;
    }
  }
  // Column bits: squared centre distance of every column to the nearest projected column (a 2D
  // transform: one layer) beyond base_reach2. A column within reach of the array's edge might
  // have a projected column beyond it: never clear.
  base_disc_.assign(static_cast<std::size_t>((columns + 63) / 64), 0);
  if (site.empty()) return;
  std::vector<std::int32_t> d2;
  edt::squared_distance_3d(site, nx, ny, 1, d2);
  int reach = 0;
  while (static_cast<std::int64_t>(reach + 1) * (reach + 1) <= base_reach2_) ++reach;
  for (int y = reach; y < ny - reach; ++y)
    for (int x = reach; x < nx - reach; ++x) {
      const std::int64_t b = x + static_cast<std::int64_t>(nx) * y;
      if (d2[static_cast<std::size_t>(b)] > base_reach2_)
        base_disc_[static_cast<std::size_t>(b >> 6)] |= std::uint64_t{1} << (b & 63);
    }
}

namespace {

/// The squared voxel distance from which a clearance comes out capped: floor(4 sqrt(q)) >=
/// cap_units once q >= ceil(cap_units / 4)^2.
std::int32_t far2_for_cap(int cap_units) {
  const int c = (cap_units + 3) / 4;
  return c * c;
}

}  // namespace

void MapKernel::rebuild_clearance(const Eigen::Vector3i& cell_lo_in, const Eigen::Vector3i& cell_hi_in) {
  const Eigen::Vector3i cell_lo = cell_lo_in.cwiseMax(0);
  const Eigen::Vector3i cell_hi = cell_hi_in.cwiseMin(cells_ - Eigen::Vector3i::Ones());
  if ((cell_lo.array() > cell_hi.array()).any()) return;
  // Voxel domain (grid indices): the cells' voxels grown by the cap (+2 for the dilation and
  // rounding), but never more than 2 voxels beyond the grid: everything outside it is in the
  // core set, so a ring of it stands for all of it.
  const int reach = static_cast<int>(std::ceil(cap_units_ / 4.0)) + 2;
  const Eigen::Vector3i lo = (kCellVoxels * cell_lo - Eigen::Vector3i::Constant(reach)).cwiseMax(-2);
  const Eigen::Vector3i hi = (kCellVoxels * cell_hi + Eigen::Vector3i::Constant(kCellVoxels - 1 + reach))
                                 .cwiseMin(grid_dims_ + Eigen::Vector3i::Constant(1));
  const Eigen::Vector3i n = hi - lo + Eigen::Vector3i::Ones();
  auto local = [&](int x, int y, int z) {
    return static_cast<std::size_t>(x) +
           static_cast<std::size_t>(n.x()) * (static_cast<std::size_t>(y) + static_cast<std::size_t>(n.y()) * z);
  };
  std::vector<std::uint8_t> set(static_cast<std::size_t>(n.prod()), 0);
  for (int z = 0; z < n.z(); ++z)
    for (int y = 0; y < n.y(); ++y) {
      // Padded indices.
      const int vy = lo.y() + y + pad_, vz = lo.z() + z + pad_;
      std::uint8_t* out = &set[local(0, y, z)];
      if (vy < 0 || vz < 0 || vy >= dims_.y() || vz >= dims_.z()) {
        std::fill(out, out + n.x(), std::uint8_t{1});
        continue;
      }
      for (int x = 0; x < n.x(); ++x) {
        const int vx = lo.x() + x + pad_;
        out[x] = (vx < 0 || vx >= dims_.x() || core_bit(vx, vy, vz)) ? 1 : 0;
      }
    }
  // Vertex distances: after dilate_to_vertices(), the transform at voxel v is the squared
  // distance from v's minimum corner to the nearest core voxel's box (edt.hpp). A cell's centre
  // is the minimum corner of its voxel (kCellVoxels / 2) along each axis.
  edt::dilate_to_vertices(set, n.x(), n.y(), n.z());
  std::vector<std::int32_t> d2;
  constexpr int kHalf = kCellVoxels / 2;
  // Only the cell centres are read: the transform is exact on their lattice.
  edt::squared_distance_3d_sampled(set, n.x(), n.y(), n.z(), kCellVoxels * cell_lo.x() + kHalf - lo.x(),
                                   kCellVoxels * cell_lo.y() + kHalf - lo.y(), kCellVoxels, d2,
                                   far2_for_cap(cap_units_));
  for (int cz = cell_lo.z(); cz <= cell_hi.z(); ++cz)
    for (int cy = cell_lo.y(); cy <= cell_hi.y(); ++cy)
      for (int cx = cell_lo.x(); cx <= cell_hi.x(); ++cx) {
        const std::int32_t q = d2[local(kCellVoxels * cx + kHalf - lo.x(), kCellVoxels * cy + kHalf - lo.y(),
                                        kCellVoxels * cz + kHalf - lo.z())];
        // In units of h / 4, rounded down.
        const double units = 4.0 * std::sqrt(static_cast<double>(q));
        const int value = std::min(cap_units_, static_cast<int>(std::floor(units)));
        clearance_[field_index(cx, cy, cz)] = static_cast<std::uint8_t>(value);
      }
}

}  // namespace porter::planner
