#include "porter/planner/collision/kernel_collision_checker.hpp"

#include <cmath>
#include <stdexcept>

namespace porter::planner {

namespace {

CollisionResult hit(int link, int other = -1) {
  CollisionResult r;
  r.in_collision = true;
  r.link = link;
  r.other_link = other;
  return r;
}

/// Link order of the environment check: payload first, then down the chain.
constexpr int kArmOrder[] = {7, 6, 5, 4, 3, 2, 1};

}  // namespace

KernelCollisionChecker::KernelCollisionChecker(const RobotModel& model, const KernelCheckerSettings& settings)
    : settings_(settings),
      kernels_(model, settings.kernels),
      kinematics_(model),
      self_(model, settings.self),
      map_(settings.map, kernels_.max_extent_voxels() + 2, kernels_.base_layers()),
      motion_step_m_(settings.motion_step_m > 0.0 ? settings.motion_step_m : settings.kernels.resolution_m) {
  clearance_units_per_m_ = static_cast<float>(4.0 / kernels_.resolution_m());
  // d_j in voxels, squared, grown by 1e-4 voxel for float32 rounding (robot_kernels.hpp).
  for (int j = 1; j < kNumLinks; ++j) {
    const double r = kernels_.kernel_radius_m(j) / kernels_.resolution_m() + 1e-4;
    kernel_reach2_vox_[static_cast<std::size_t>(j)] = static_cast<float>(r * r);
    kernel_reach_units_[static_cast<std::size_t>(j)] = static_cast<float>(4.0 * r);  // clearance units: h / 4
  }
}

void KernelCollisionChecker::set_map(const OccupancyGrid& occupancy_W) {
  const double h = kernels_.resolution_m();
  if (std::abs(occupancy_W.resolution_m() - h) > 1e-9 * h)
    throw std::invalid_argument("KernelCollisionChecker: map resolution " + std::to_string(occupancy_W.resolution_m()) +
                                " differs from the kernel resolution " + std::to_string(h));
  last_update_ = map_.set_map(occupancy_W);
}

PORTER_KERNEL_CLONES bool KernelCollisionChecker::base_hit(int bx, int by, int yaw_sample) const {
  const std::array<int, 4>& fp = kernels_.base_footprint();
  if (map_.base_columns_set(bx + fp[0], by + fp[2], bx + fp[1], by + fp[3]) == 0) return false;
  const int g = map_.ground_layer();
  std::size_t n = 0;
  const BaseKernelTile* tiles = kernels_.base_tiles(yaw_sample, &n);
  const BaseKernelRow* rows = kernels_.base_rows();
  for (std::size_t t = 0; t < n; ++t) {
    const BaseKernelTile& tile = tiles[t];
    if (map_.base_columns_set(bx + tile.dx_lo, by + tile.dy_lo, bx + tile.dx_hi, by + tile.dy_hi) == 0) continue;
    for (std::uint32_t r = tile.row_begin; r < tile.row_end; ++r) {
      const BaseKernelRow& row = rows[r];
      if (map_.base_window(bx + row.dx0, by + row.dy, g + row.dz) & row.mask) return true;
    }
  }
  return false;
}

// Clearance units are h / 4: a sphere of kernel points is clear when every point is farther
// than d_j from the core set, i.e. when its cell's clearance exceeds its radius + d_j (in
// clearance units, with the same float slack as d_j). T_V_J maps metres to padded voxels.
PORTER_KERNEL_CLONES std::uint32_t KernelCollisionChecker::links_near(const std::array<int, kNumLinks>& sample,
                                                                      const Pose4f& T_V_B,
                                                                      const ArmPoses& poses) const {
  const float scale = clearance_units_per_m_;
  // Row j = link j's root-sphere centre (padded voxels) and the clearance it needs; row 0 and
  // empty kernels need less than any clearance.
  v4f rows[8];
  rows[0] = v4f{0.f, 0.f, 0.f, -1e30f};
  for (int link = 1; link < kNumLinks; ++link) {
    const auto l = static_cast<std::size_t>(link);
    const WideTreeRoot& root = kernels_.link_pool(link).root(sample[l]);
    if (root.num_points == 0) {
      rows[l] = v4f{0.f, 0.f, 0.f, -1e30f};
      continue;
    }
    const v4f c_B = poses.T_B_J[l].apply(root.cx, root.cy, root.cz);
    rows[l] = T_V_B.apply(c_B[0], c_B[1], c_B[2]);
    rows[l][3] = root.radius_m * scale + kernel_reach_units_[l];
  }
  v8f x, y, z, need;
  transpose8x4(rows, &x, &y, &z, &need);
  const v8f clearance = map_.clearance_units8(x, y, z);
  return ~lane_mask(need < clearance) & 0xfeu;
}

PORTER_KERNEL_CLONES bool KernelCollisionChecker::link_hit(int link, int sample, const Pose4f& T_V_B,
                                                           const Pose4f& T_B_J) const {
  const float scale = clearance_units_per_m_;
  const MapKernel& map = map_;
  const WidePointTreePool& pool = kernels_.link_pool(link);
  const float reach2 = kernel_reach2_vox_[static_cast<std::size_t>(link)];
  const float reach_units = kernel_reach_units_[static_cast<std::size_t>(link)];
  const Pose8f T_V_J = Pose8f::from(T_V_B * T_B_J);
  const v8f scale8 = v8f_splat(scale), reach8 = v8f_splat(reach_units);
  return wide_tree_any(
      pool, sample,
      [&](const WideNode& n) PORTER_SIMD_LAMBDA {
        v8f ux, uy, uz;
        T_V_J.apply(v8f_load(n.cx), v8f_load(n.cy), v8f_load(n.cz), &ux, &uy, &uz);
        // Open: not proven clear (the negated test, so NaN stays open).
        return ~lane_mask(v8f_load(n.r) * scale8 + reach8 < map.clearance_units8(ux, uy, uz));
      },
      [&](const PointBlock& b) PORTER_SIMD_LAMBDA {
        v8f ux, uy, uz;
        T_V_J.apply(v8f_load(b.x), v8f_load(b.y), v8f_load(b.z), &ux, &uy, &uz);
        std::uint32_t m = map.arm_bits8(ux, uy, uz);
        while (m != 0) {
          const int i = __builtin_ctz(m);
          m &= m - 1;
          if (map.arm_near(ux[i], uy[i], uz[i], reach2)) return true;
        }
        return false;
      });
}

PORTER_KERNEL_CLONES CollisionResult KernelCollisionChecker::check_prepared(const RobotConfiguration& config, bool environment,
                                                       bool self) const {
  if (!map_.has_map() && environment) return hit(0);
  std::array<int, kNumLinks> sample{};  // nearest kernel sample per arm joint (index = link)
  for (int j = 1; j <= kNumArmJoints; ++j) {
    sample[static_cast<std::size_t>(j)] = kernels_.joint_sample(j, config.q_rad[j - 1]);
    if (sample[static_cast<std::size_t>(j)] < 0) return hit(j);
  }
  double ux = 0.0, uy = 0.0;  // base origin, padded voxel coordinates
  if (environment) {
    if (!base_voxel(config.base, &ux, &uy)) return hit(0);
    if (base_hit(static_cast<int>(ux), static_cast<int>(uy), kernels_.base_sample(config.base.yaw_rad))) return hit(0);
  }
  ArmPoses poses;
  kinematics_.compute(config.q_rad, poses);
  if (environment) {
    const double inv_h = 1.0 / kernels_.resolution_m();
    // Base frame -> padded voxel coordinates of the map kernel: u = (T_W_B p - corner) / h. The
    // large world offset is subtracted in double before rounding to float.
    float sy = 0.f, cy = 1.f;
    fast_sincos(config.base.yaw_rad, &sy, &cy);
    Pose4f T_V_B;
    const float c = cy * static_cast<float>(inv_h), s = sy * static_cast<float>(inv_h);
    T_V_B.c0 = v4f{c, s, 0.f, 0.f};
    T_V_B.c1 = v4f{-s, c, 0.f, 0.f};
    T_V_B.c2 = v4f{0.f, 0.f, static_cast<float>(inv_h), 0.f};
    T_V_B.t = v4f{static_cast<float>(ux), static_cast<float>(uy),
                  static_cast<float>(-map_.padded_origin_W().z() * inv_h), 0.f};
    const std::uint32_t near = links_near(sample, T_V_B, poses);
    for (int link : kArmOrder) {
      const auto l = static_cast<std::size_t>(link);
      if (((near >> link) & 1u) && link_hit(link, sample[l], T_V_B, poses.T_B_J[l])) return hit(link);
    }
  }
  if (self && settings_.check_self_collision) return self_.check(poses);
  return CollisionResult{};
}

CollisionResult KernelCollisionChecker::check(const RobotConfiguration& config) const {
  return check_prepared(config, true, true);
}

CollisionResult KernelCollisionChecker::check_environment(const RobotConfiguration& config) const {
  return check_prepared(config, true, false);
}

CollisionResult KernelCollisionChecker::check_self(const JointVector& q_rad) const {
  for (int j = 1; j <= kNumArmJoints; ++j)
    if (kernels_.joint_sample(j, q_rad[j - 1]) < 0) return hit(j);
  ArmPoses poses;
  kinematics_.compute(q_rad, poses);
  return self_.check(poses);
}

CollisionResult KernelCollisionChecker::check_base(const BasePose& base) const {
  if (!map_.has_map()) return hit(0);
  double ux = 0.0, uy = 0.0;
  if (!base_voxel(base, &ux, &uy)) return hit(0);
  if (base_hit(static_cast<int>(ux), static_cast<int>(uy), kernels_.base_sample(base.yaw_rad))) return hit(0);
  return CollisionResult{};
}

bool KernelCollisionChecker::base_voxel(const BasePose& base, double* ux, double* uy) const {
  const double inv_h = 1.0 / kernels_.resolution_m();
  *ux = (base.x_m - map_.padded_origin_W().x()) * inv_h;
  *uy = (base.y_m - map_.padded_origin_W().y()) * inv_h;
  const int P = map_.padding();
  // NaN fails both comparisons and lands here too.
  return *ux >= P && *ux < P + map_.grid_dims().x() && *uy >= P && *uy < P + map_.grid_dims().y() &&
         std::isfinite(base.yaw_rad);
}

KernelStorage KernelCollisionChecker::storage() const {
  KernelStorage s;
  s.kernel_count = kernels_.kernel_count();
  s.robot_kernel_bytes = kernels_.bytes();
  s.self_collision_bytes = self_.bytes();
  s.map_kernel_bytes = map_.bytes();
  return s;
}

}  // namespace porter::planner
