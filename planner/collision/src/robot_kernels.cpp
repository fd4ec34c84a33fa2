#include "porter/planner/collision/robot_kernels.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "porter/planner/collision/link_distance.hpp"

namespace porter::planner {

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kSqrt3 = 1.7320508075688772;
}  // namespace

std::vector<Eigen::Vector3f> lattice_points_within(const LinkDistance& link, const Eigen::Isometry3d& T_L_F,
                                                   double spacing_m, double radius_m,
                                                   const Eigen::AlignedBox3d& bounds_F) {
  std::vector<Eigen::Vector3f> out;
  if (link.empty() || bounds_F.isEmpty()) return out;
  const double s = spacing_m;
  Eigen::Vector3i lo, hi;
  for (int a = 0; a < 3; ++a) {
    lo[a] = static_cast<int>(std::ceil(bounds_F.min()[a] / s));
    hi[a] = static_cast<int>(std::floor(bounds_F.max()[a] / s));
  }
  if ((lo.array() > hi.array()).any()) return out;
  constexpr int kB = 4;
  const double block_radius = 0.5 * (kB - 1) * s * kSqrt3;
  auto sd_at = [&](const Eigen::Vector3d& p_F) { return link.signed_distance(T_L_F * p_F); };
  for (int bz = lo.z(); bz <= hi.z(); bz += kB)
    for (int by = lo.y(); by <= hi.y(); by += kB)
      for (int bx = lo.x(); bx <= hi.x(); bx += kB) {
        const Eigen::Vector3d c = s * (Eigen::Vector3d(bx, by, bz) + Eigen::Vector3d::Constant(0.5 * (kB - 1)));
        const double dc = sd_at(c);
        if (dc > block_radius + radius_m) continue;
        const bool all_in = dc < -block_radius;
        for (int iz = bz; iz < bz + kB && iz <= hi.z(); ++iz)
          for (int iy = by; iy < by + kB && iy <= hi.y(); ++iy)
            for (int ix = bx; ix < bx + kB && ix <= hi.x(); ++ix) {
              const Eigen::Vector3d p = s * Eigen::Vector3d(ix, iy, iz);
              if (all_in || sd_at(p) <= radius_m) out.push_back(p.cast<float>());
            }
      }
  return out;
}

RobotKernels::RobotKernels(const RobotModel& model, const RobotKernelSettings& settings)
    : res_(settings.resolution_m) {
  if (!(res_ > 0.0) || !std::isfinite(res_)) throw std::invalid_argument("RobotKernels: resolution_m must be > 0");
  if (model.links[0].shapes.empty()) throw std::invalid_argument("RobotKernels: the base link has no geometry");
  if (settings.lattice_subdivision < 1) throw std::invalid_argument("RobotKernels: lattice_subdivision must be >= 1");
  spacing_ = res_ / settings.lattice_subdivision;
  radii_ = compute_chain_radii(model);
  // Yaw moves base points horizontally only: the radius about the vertical axis is what counts.
  // Distance to the axis <= distance to any point of it; take the shape's mid-height.
  for (const auto& s : model.links[0].shapes) {
    const Eigen::AlignedBox3d b = shape_bounds(s);
    base_horizontal_radius_ =
        std::max(base_horizontal_radius_, shape_max_distance(s, Eigen::Vector3d(0, 0, b.center().z())));
  }
  const double target = settings.max_sample_error_m > 0.0 ? settings.max_sample_error_m : 0.1 * res_;
  int n_yaw = settings.base_yaw_samples;
  if (n_yaw <= 0) n_yaw = std::max(8, static_cast<int>(std::ceil(base_horizontal_radius_ * kPi / target)));
  build_base(model, n_yaw);
  for (int j = 1; j < kNumLinks; ++j) build_link(model, j, target);
  for (int j = 1; j < kNumLinks; ++j)
    if (kernel_radius_[static_cast<std::size_t>(j)] >= res_)
      throw std::invalid_argument("RobotKernels: kernel radius of link " + std::to_string(j) +
                                  " reaches a voxel; lower max_sample_error_m or raise lattice_subdivision");
  // Every kernel point lies within reach + d_j of the base origin, every base offset within
  // reach + e_0 + 2 voxels (one for the origin's position in its voxel, one for the box).
  double slack = sample_error_[0] + 2.0 * res_;
  for (int j = 1; j < kNumLinks; ++j) slack = std::max(slack, kernel_radius_[static_cast<std::size_t>(j)]);
  max_extent_voxels_ = static_cast<int>(std::ceil((radii_.reach_m + slack) / res_)) + 2;
}

double RobotKernels::inflation_bound_m(int link) const {
  if (link == 0) return std::sqrt(2.0) * (res_ + sample_error_[0]) + sample_error_[0];
  return kSqrt3 * spacing_ + 3.0 * sample_error_[static_cast<std::size_t>(link)];
}

int RobotKernels::base_sample_wrapped(double yaw_rad) const {
  const int n = num_samples_[0];
  const double t = (yaw_rad + kPi) * inv_step_[0];
  if (!std::isfinite(t)) return 0;
  const double k = std::floor(t + 0.5);
  const double m = k - n * std::floor(k / n);
  return std::min(n - 1, std::max(0, static_cast<int>(m)));
}

double RobotKernels::base_sample_yaw(int k) const { return -kPi + k * step_[0]; }

double RobotKernels::joint_sample_value(int joint, int k) const {
  return lower_[static_cast<std::size_t>(joint)] + k * step_[static_cast<std::size_t>(joint)];
}

void RobotKernels::build_base(const RobotModel& model, int n_yaw) {
  num_samples_[0] = n_yaw;
  step_[0] = 2.0 * kPi / n_yaw;
  inv_step_[0] = 1.0 / step_[0];
  const double e0 = base_horizontal_radius_ * kPi / n_yaw;
  sample_error_[0] = e0;
  const double h = res_;
  const auto& shapes = model.links[0].shapes;
  base_footprint_ = {1 << 14, -(1 << 14), 1 << 14, -(1 << 14)};
  base_layers_ = 1;
  base_reach2_ = 0;
  for (int k = 0; k < n_yaw; ++k) {
    const Eigen::Isometry3d R(Eigen::AngleAxisd(base_sample_yaw(k), Eigen::Vector3d::UnitZ()));
    std::vector<CollisionShape> rotated = shapes;
    Eigen::AlignedBox3d all;
    all.setEmpty();
    for (auto& s : rotated) {
      s.T_parent_shape = R * s.T_parent_shape;
      all.extend(shape_bounds(s));
    }
    const int x0 = static_cast<int>(std::ceil((all.min().x() - e0) / h)) - 1;
    const int x1 = static_cast<int>(std::floor((all.max().x() + e0) / h)) + 1;
    const int y0 = static_cast<int>(std::ceil((all.min().y() - e0) / h)) - 1;
    const int y1 = static_cast<int>(std::floor((all.max().y() + e0) / h)) + 1;
    const int z0 = std::max(0, static_cast<int>(std::ceil(all.min().z() / h)) - 1);
    const int z1 = static_cast<int>(std::floor(all.max().z() / h));
    const int nx = x1 - x0 + 1, ny = y1 - y0 + 1, nz = std::max(0, z1 - z0 + 1);
    std::vector<std::uint8_t> hit(static_cast<std::size_t>(nx) * ny * nz, 0);
    for (const auto& s : rotated) {
      const Eigen::AlignedBox3d b = shape_bounds(s);
      for (int dz = z0; dz <= z1; ++dz)
        for (int dy = y0; dy <= y1; ++dy)
          for (int dx = x0; dx <= x1; ++dx) {
            std::uint8_t& cell = hit[static_cast<std::size_t>((dx - x0) + nx * ((dy - y0) + ny * (dz - z0)))];
            if (cell) continue;
            const Eigen::AlignedBox3d box(Eigen::Vector3d((dx - 1) * h - e0, (dy - 1) * h - e0, dz * h),
                                          Eigen::Vector3d((dx + 1) * h + e0, (dy + 1) * h + e0, (dz + 1) * h));
            if (!box.intersects(b)) continue;
            if (shape_intersects_aabb(s, box)) cell = 1;
          }
    }
    // Rows per (dy, dz), tiles per 4 dy rows.
    for (int ty = y0; ty <= y1; ty += 4) {
      BaseKernelTile tile;
      tile.row_begin = static_cast<std::uint32_t>(base_rows_.size());
      tile.dx_lo = static_cast<std::int16_t>(1 << 14);
      tile.dx_hi = static_cast<std::int16_t>(-(1 << 14));
      tile.dy_lo = static_cast<std::int16_t>(ty);
      tile.dy_hi = static_cast<std::int16_t>(std::min(ty + 3, y1));
      for (int dy = ty; dy <= tile.dy_hi; ++dy)
        for (int dz = z0; dz <= z1; ++dz) {
          int first = 0;
          bool open = false;  // a run [first, dx) is being collected
          for (int dx = x0; dx <= x1 + 1; ++dx) {
            const bool on = dx <= x1 && hit[static_cast<std::size_t>((dx - x0) + nx * ((dy - y0) + ny * (dz - z0)))];
            if (on && !open) {
              first = dx;
              open = true;
            }
            if (open && (!on || dx - first == 64)) {
              // Emit [first, dx) as one row (at most 64 voxels).
              BaseKernelRow r;
              r.dx0 = static_cast<std::int16_t>(first);
              r.dy = static_cast<std::int16_t>(dy);
              r.dz = static_cast<std::int16_t>(dz);
              for (int i = first; i < dx; ++i) {
                r.mask |= std::uint64_t{1} << (i - first);
                base_reach2_ = std::max(base_reach2_, i * i + dy * dy);
              }
              base_rows_.push_back(r);
              tile.dx_lo = static_cast<std::int16_t>(std::min<int>(tile.dx_lo, first));
              tile.dx_hi = static_cast<std::int16_t>(std::max<int>(tile.dx_hi, dx - 1));
              base_layers_ = std::max(base_layers_, dz + 1);
              first = dx;
              open = on;
            }
          }
        }
      tile.row_end = static_cast<std::uint32_t>(base_rows_.size());
      if (tile.row_end > tile.row_begin) {
        base_tiles_.push_back(tile);
        base_footprint_[0] = std::min<int>(base_footprint_[0], tile.dx_lo);
        base_footprint_[1] = std::max<int>(base_footprint_[1], tile.dx_hi);
        base_footprint_[2] = std::min<int>(base_footprint_[2], tile.dy_lo);
        base_footprint_[3] = std::max<int>(base_footprint_[3], tile.dy_hi);
      }
    }
    base_tile_begin_.push_back(base_tiles_.size());
  }
}

void RobotKernels::build_link(const RobotModel& model, int link, double target_error_m) {
  const auto j = static_cast<std::size_t>(link);
  const LinkDistance geometry(model.links[j].shapes);
  WidePointTreePool& pool = pools_[j];
  const double base_radius = 0.5 * kSqrt3 * spacing_;
  if (link == kEndEffectorLink) {
    num_samples_[j] = 1;
    sample_error_[j] = 0.0;
    kernel_radius_[j] = base_radius;
    Eigen::AlignedBox3d b = geometry.bounds();
    if (!b.isEmpty()) b = Eigen::AlignedBox3d(b.min().array() - base_radius, b.max().array() + base_radius);
    pool.add_tree(lattice_points_within(geometry, Eigen::Isometry3d::Identity(), spacing_, base_radius, b));
    return;
  }
  const ArmJoint& joint = model.joints[j - 1];
  const double range = joint.upper_rad - joint.lower_rad;
  const double r = radii_.link_radius_m[j];
  int n = 2;
  if (r > 0.0 && range > 0.0) n = std::max(2, static_cast<int>(std::ceil(r * range / (2.0 * target_error_m))) + 1);
  num_samples_[j] = n;
  lower_[j] = joint.lower_rad;
  step_[j] = range > 0.0 ? range / (n - 1) : 1.0;
  inv_step_[j] = 1.0 / step_[j];
  sample_error_[j] = r * step_[j] * 0.5;
  kernel_radius_[j] = base_radius + sample_error_[j];
  const Eigen::Vector3d axis = joint.axis.normalized();
  for (int k = 0; k < n; ++k) {
    const Eigen::Isometry3d T_J_L(Eigen::AngleAxisd(joint_sample_value(link, k), axis));
    Eigen::AlignedBox3d b;
    b.setEmpty();
    for (const auto& s : model.links[j].shapes) b.extend(shape_bounds(s, T_J_L));
    if (!b.isEmpty()) b = Eigen::AlignedBox3d(b.min().array() - kernel_radius_[j], b.max().array() + kernel_radius_[j]);
    pool.add_tree(lattice_points_within(geometry, T_J_L.inverse(), spacing_, kernel_radius_[j], b));
  }
}

std::vector<Eigen::Vector3i> RobotKernels::base_offsets(int k) const {
  std::vector<Eigen::Vector3i> out;
  std::size_t n = 0;
  const BaseKernelTile* tiles = base_tiles(k, &n);
  for (std::size_t t = 0; t < n; ++t)
    for (std::uint32_t r = tiles[t].row_begin; r < tiles[t].row_end; ++r) {
      const BaseKernelRow& row = base_rows_[r];
      for (int i = 0; i < 64; ++i)
        if ((row.mask >> i) & 1u) out.emplace_back(row.dx0 + i, row.dy, row.dz);
    }
  return out;
}

int RobotKernels::kernel_count() const {
  int n = 0;
  for (int s : num_samples_) n += s;
  return n;
}

std::size_t RobotKernels::bytes() const {
  std::size_t b = base_rows_.size() * sizeof(BaseKernelRow) + base_tiles_.size() * sizeof(BaseKernelTile) +
                  base_tile_begin_.size() * sizeof(std::size_t);
  for (const auto& p : pools_) b += p.bytes();
  return b;
}

}  // namespace porter::planner
