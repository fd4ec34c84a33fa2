#include "porter/core/occupancy_grid.hpp"

#include <algorithm>
#include <bitset>
#include <cmath>

namespace porter {

OccupancyGrid::OccupancyGrid(const Eigen::Vector3d& origin_W, double resolution_m, const Eigen::Vector3i& dims)
    : origin_W_(origin_W), resolution_m_(resolution_m), dims_(dims.cwiseMax(0)) {
  words_.assign(static_cast<std::size_t>((num_voxels() + 63) / 64), 0);
}

OccupancyGrid OccupancyGrid::covering(const Eigen::AlignedBox3d& bounds_W, double resolution_m) {
  Eigen::Vector3i dims;
  for (int i = 0; i < 3; ++i) {
    const double n = (bounds_W.max()[i] - bounds_W.min()[i]) / resolution_m;
    dims[i] = std::max(1, static_cast<int>(std::ceil(n - 1e-9)));
  }
  return OccupancyGrid(bounds_W.min(), resolution_m, dims);
}

Eigen::AlignedBox3d OccupancyGrid::bounds_W() const {
  return Eigen::AlignedBox3d(origin_W_, origin_W_ + resolution_m_ * dims_.cast<double>());
}

Eigen::Vector3i OccupancyGrid::world_to_index(const Eigen::Vector3d& p_W) const {
  const Eigen::Vector3d f = ((p_W - origin_W_) / resolution_m_).array().floor();
  // Clamp before the cast so far-away points cannot overflow int; NaN maps to -1 (outside).
  Eigen::Vector3i out;
  for (int i = 0; i < 3; ++i) out[i] = f[i] >= -1.0 ? static_cast<int>(std::min(f[i], double(dims_[i]))) : -1;
  return out;
}

bool OccupancyGrid::world_to_index_checked(const Eigen::Vector3d& p_W, Eigen::Vector3i* idx) const {
  if (!(p_W.array() == p_W.array()).all()) return false;  // NaN
  const Eigen::Vector3i i = world_to_index(p_W);
  if (!in_bounds(i)) return false;
  *idx = i;
  return true;
}

Eigen::Vector3d OccupancyGrid::voxel_center_W(int ix, int iy, int iz) const {
  return origin_W_ + resolution_m_ * Eigen::Vector3d(ix + 0.5, iy + 0.5, iz + 0.5);
}

Eigen::AlignedBox3d OccupancyGrid::voxel_box_W(int ix, int iy, int iz) const {
  const Eigen::Vector3d lo = origin_W_ + resolution_m_ * Eigen::Vector3d(ix, iy, iz);
  const Eigen::Vector3d hi = origin_W_ + resolution_m_ * Eigen::Vector3d(ix + 1, iy + 1, iz + 1);
  return Eigen::AlignedBox3d(lo, hi);
}

bool OccupancyGrid::occupied_at(const Eigen::Vector3d& p_W) const {
  Eigen::Vector3i idx;
  return world_to_index_checked(p_W, &idx) && occupied(idx);
}

void OccupancyGrid::clear() { std::fill(words_.begin(), words_.end(), 0); }

std::int64_t OccupancyGrid::count() const {
  std::int64_t n = 0;
  for (const auto w : words_) n += static_cast<std::int64_t>(std::bitset<64>(w).count());
  return n;
}

}  // namespace porter
