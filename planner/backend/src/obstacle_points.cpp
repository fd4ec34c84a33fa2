#include "porter/backend/obstacle_points.hpp"

#include <algorithm>
#include <cmath>

namespace porter::backend {

CellMask::CellMask(const Eigen::AlignedBox3d& bounds_W, double cell_m) : bounds_(bounds_W), cell_m_(cell_m) {
  if (bounds_.isEmpty() || !(cell_m > 0.0)) return;
  for (int a = 0; a < 3; ++a) dims_[a] = std::max(1, static_cast<int>(std::ceil(bounds_.sizes()[a] / cell_m_)));
  bits_.assign(static_cast<std::size_t>(dims_.x()) * static_cast<std::size_t>(dims_.y()) * static_cast<std::size_t>(dims_.z()), 0);
}

bool CellMask::range(const Eigen::AlignedBox3d& box, Eigen::Vector3i& lo, Eigen::Vector3i& hi) const {
  if (bits_.empty() || box.isEmpty()) return false;
  for (int a = 0; a < 3; ++a) {
    if (box.max()[a] < bounds_.min()[a] || box.min()[a] > bounds_.max()[a]) return false;
    lo[a] = std::clamp(static_cast<int>(std::floor((box.min()[a] - bounds_.min()[a]) / cell_m_)), 0, dims_[a] - 1);
    hi[a] = std::clamp(static_cast<int>(std::floor((box.max()[a] - bounds_.min()[a]) / cell_m_)), 0, dims_[a] - 1);
  }
  return true;
}

void CellMask::add(const Eigen::AlignedBox3d& box) {
  Eigen::Vector3i lo, hi;
  if (!range(box, lo, hi)) return;
  for (int z = lo.z(); z <= hi.z(); ++z)
    for (int y = lo.y(); y <= hi.y(); ++y)
      for (int x = lo.x(); x <= hi.x(); ++x) bits_[index(x, y, z)] = 1;
}

bool CellMask::contains(const Eigen::Vector3d& p) const {
  if (bits_.empty() || !bounds_.contains(p)) return false;
  int c[3];
  for (int a = 0; a < 3; ++a) {
    c[a] = std::clamp(static_cast<int>(std::floor((p[a] - bounds_.min()[a]) / cell_m_)), 0, dims_[a] - 1);
  }
  return bits_[index(c[0], c[1], c[2])] != 0;
}

bool CellMask::covers(const Eigen::AlignedBox3d& box) const {
  if (box.isEmpty()) return true;
  Eigen::Vector3i lo, hi;
  if (!range(box, lo, hi)) return true;  // no point of the box is in the grid: none can be contained
  for (int z = lo.z(); z <= hi.z(); ++z)
    for (int y = lo.y(); y <= hi.y(); ++y)
      for (int x = lo.x(); x <= hi.x(); ++x)
        if (!bits_[index(x, y, z)]) return false;
  return true;
}

std::int64_t CellMask::count() const {
  std::int64_t n = 0;
  for (std::uint8_t b : bits_) n += b;
  return n;
}

std::vector<ObstaclePoint> collect_obstacle_points(const OccupancyGrid& map,
                                                   const Eigen::AlignedBox3d& region,
                                                   const ObstaclePointSettings& settings) {
  return collect_obstacle_points(map, region, settings, nullptr, nullptr);
}

std::vector<ObstaclePoint> collect_obstacle_points(const OccupancyGrid& map,
                                                   const Eigen::AlignedBox3d& region,
                                                   const ObstaclePointSettings& settings, const CellMask* keep,
                                                   std::vector<std::uint64_t>* keys) {
  std::vector<ObstaclePoint> out;
  if (keys) keys->clear();
  if (map.num_voxels() == 0 || region.isEmpty()) return out;
  const double res = map.resolution_m();
  const Eigen::Vector3i dims = map.dims();
  Eigen::Vector3i lo, hi;
  for (int a = 0; a < 3; ++a) {
    lo[a] = std::max(0, static_cast<int>(std::floor((region.min()[a] - map.origin_W()[a]) / res)));
    hi[a] = std::min(dims[a] - 1, static_cast<int>(std::floor((region.max()[a] - map.origin_W()[a]) / res)));
  }
  auto occupied_or_outside = [&](int i, int j, int k) {
    return !map.in_bounds(i, j, k) || map.occupied(i, j, k);
  };
  // Only the set bits of the storage are visited (a map is mostly free space: the forest scene's
  // 3.5 M voxels are 55 k words, most of them zero), in increasing linear index, i.e. z, then y,
  // then x ascending: the order of a plain triple loop over the voxels.
  const std::vector<std::uint64_t>& words = map.words();
  const std::int64_t nx = dims.x(), ny = dims.y();
  const std::int64_t n = map.num_voxels();
  const std::int64_t first_word = (lo.x() + nx * (lo.y() + ny * static_cast<std::int64_t>(lo.z()))) >> 6;
  const std::int64_t last_word = std::min<std::int64_t>(
      static_cast<std::int64_t>(words.size()) - 1, (hi.x() + nx * (hi.y() + ny * static_cast<std::int64_t>(hi.z()))) >> 6);
  for (std::int64_t w = std::max<std::int64_t>(0, first_word); w <= last_word; ++w) {
    std::uint64_t bits = words[static_cast<std::size_t>(w)];
    while (bits != 0) {
      // C++17 has no std::countr_zero; bits != 0 here.
      const std::int64_t idx = (w << 6) + __builtin_ctzll(bits);
      bits &= bits - 1;
      if (idx >= n) break;
      const int i = static_cast<int>(idx % nx);
      const std::int64_t row = idx / nx;
      const int j = static_cast<int>(row % ny);
      const int k = static_cast<int>(row / ny);
      if (i < lo.x() || i > hi.x() || j < lo.y() || j > hi.y() || k < lo.z() || k > hi.z()) continue;
      if (settings.surface_only && occupied_or_outside(i - 1, j, k) && occupied_or_outside(i + 1, j, k) &&
          occupied_or_outside(i, j - 1, k) && occupied_or_outside(i, j + 1, k) &&
          occupied_or_outside(i, j, k - 1) && occupied_or_outside(i, j, k + 1)) {
        continue;
      }
      const Eigen::Vector3d c = map.voxel_center_W(i, j, k);
      if (!region.contains(c)) continue;
      // After the surface test, which drops most occupied voxels (the interior of solid
      // obstacles) after a few look-ups: the mask is asked only about surface voxels.
      if (keep && !keep->contains(c)) continue;
      out.push_back({c, (1u << kNumLinks) - 1, false});
      if (keys) keys->push_back(static_cast<std::uint64_t>(idx));
    }
  }
  if (settings.ground && region.min().z() <= 0.0) {
    const std::uint32_t links = ((1u << kNumLinks) - 1) & ~1u;
    out.reserve(out.size() + static_cast<std::size_t>(hi.x() - lo.x() + 1) * static_cast<std::size_t>(hi.y() - lo.y() + 1));
    for (int j = lo.y(); j <= hi.y(); ++j) {
      for (int i = lo.x(); i <= hi.x(); ++i) {
        Eigen::Vector3d c = map.voxel_center_W(i, j, 0);
        c.z() = -0.5 * res;
        if (c.x() < region.min().x() || c.x() > region.max().x() || c.y() < region.min().y() ||
            c.y() > region.max().y()) {
          continue;
        }
        if (keep && !keep->contains(c)) continue;
        out.push_back({c, links, true});
        if (keys) keys->push_back(static_cast<std::uint64_t>(n + i + nx * j));
      }
    }
  }
  return out;
}

}  // namespace porter::backend
