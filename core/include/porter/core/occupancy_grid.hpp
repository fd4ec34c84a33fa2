#pragma once
// A dense, bit-packed 3D occupancy grid (one bit per voxel) over an axis-aligned box of the
// world. Produced by the scene voxelizer; meant to be read by the planner's collision map and
// written by the mapper.
//
// Layout: voxel (ix, iy, iz) covers the closed box [origin + i*res, origin + (i+1)*res] per axis
// and has linear index ix + nx * (iy + ny * iz) (x fastest). Bit k of the storage is bit (k % 64)
// of word k / 64, so an x row of 64 voxels starting at a multiple of 64 is one word.
// Memory: ceil(nx*ny*nz / 64) * 8 bytes (20 x 8 x 2.5 m at 5 cm: 3.2 M voxels, 400 kB).
//
// Frames and units: world frame W, metres.
// Thread-safety: concurrent const access is safe; writes need exclusive access.

#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace porter {

class OccupancyGrid {
 public:
  /// An empty grid of zero voxels.
  OccupancyGrid() = default;
  /// All voxels free. dims must be non-negative and resolution_m > 0 (checked by callers:
  /// the constructor clamps negative dims to 0).
  OccupancyGrid(const Eigen::Vector3d& origin_W, double resolution_m, const Eigen::Vector3i& dims);

  /// The smallest grid with origin at bounds_W.min() whose voxels cover bounds_W (at least one
  /// voxel per axis). The far faces may lie up to one voxel past bounds_W.max(); extents within
  /// 1e-9 voxels of a whole number of voxels are not rounded up.
  static OccupancyGrid covering(const Eigen::AlignedBox3d& bounds_W, double resolution_m);

  const Eigen::Vector3d& origin_W() const { return origin_W_; }
  double resolution_m() const { return resolution_m_; }
  const Eigen::Vector3i& dims() const { return dims_; }
  std::int64_t num_voxels() const {
    return static_cast<std::int64_t>(dims_.x()) * dims_.y() * dims_.z();
  }
  /// The box covered by all voxels.
  Eigen::AlignedBox3d bounds_W() const;

  bool in_bounds(int ix, int iy, int iz) const {
    return ix >= 0 && iy >= 0 && iz >= 0 && ix < dims_.x() && iy < dims_.y() && iz < dims_.z();
  }
  bool in_bounds(const Eigen::Vector3i& idx) const { return in_bounds(idx.x(), idx.y(), idx.z()); }
  /// Precondition: in_bounds.
  std::int64_t linear_index(int ix, int iy, int iz) const {
    return ix + static_cast<std::int64_t>(dims_.x()) * (iy + static_cast<std::int64_t>(dims_.y()) * iz);
  }

  /// Index of the voxel containing p_W (floor of (p - origin) / res; may be out of bounds).
  Eigen::Vector3i world_to_index(const Eigen::Vector3d& p_W) const;
  /// As world_to_index, false (and *idx untouched) when p_W is outside the grid.
  bool world_to_index_checked(const Eigen::Vector3d& p_W, Eigen::Vector3i* idx) const;
  Eigen::Vector3d voxel_center_W(int ix, int iy, int iz) const;
  Eigen::AlignedBox3d voxel_box_W(int ix, int iy, int iz) const;

  /// False outside the grid.
  bool occupied(int ix, int iy, int iz) const {
    if (!in_bounds(ix, iy, iz)) return false;
    const std::int64_t k = linear_index(ix, iy, iz);
    return (words_[static_cast<std::size_t>(k >> 6)] >> (k & 63)) & 1u;
  }
  bool occupied(const Eigen::Vector3i& idx) const { return occupied(idx.x(), idx.y(), idx.z()); }
  /// Occupancy of the voxel containing p_W; false outside the grid.
  bool occupied_at(const Eigen::Vector3d& p_W) const;

  /// Precondition: in_bounds.
  void set(int ix, int iy, int iz, bool value = true) {
    const std::int64_t k = linear_index(ix, iy, iz);
    const std::uint64_t bit = std::uint64_t{1} << (k & 63);
    auto& w = words_[static_cast<std::size_t>(k >> 6)];
    w = value ? (w | bit) : (w & ~bit);
  }
  void clear();
  /// Number of occupied voxels.
  std::int64_t count() const;

  /// Raw storage (see Layout above). Bits past num_voxels() are always 0.
  const std::vector<std::uint64_t>& words() const { return words_; }

 private:
  Eigen::Vector3d origin_W_ = Eigen::Vector3d::Zero();
  double resolution_m_ = 1.0;
  Eigen::Vector3i dims_ = Eigen::Vector3i::Zero();
  std::vector<std::uint64_t> words_;
};

}  // namespace porter
