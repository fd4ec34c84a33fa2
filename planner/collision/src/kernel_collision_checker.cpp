#include "porter/planner/collision/kernel_collision_checker.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
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

/// Joint values of the lanes a batch leaves unused (any valid values would do).
const JointVector kRestJoints = JointVector::Zero();

/// Link order of the environment check: payload first, then down the chain.
constexpr int kArmOrder[] = {7, 6, 5, 4, 3, 2, 1};

}  // namespace

namespace {
std::shared_ptr<const KernelRobot> require(std::shared_ptr<const KernelRobot> robot) {
  if (!robot) throw std::invalid_argument("KernelCollisionChecker: no robot side");
  return robot;
}
}  // namespace

KernelCollisionChecker::KernelCollisionChecker(const RobotModel& model, const KernelCheckerSettings& settings)
    : KernelCollisionChecker(std::make_shared<const KernelRobot>(model, settings), settings.map) {}

KernelCollisionChecker::KernelCollisionChecker(std::shared_ptr<const KernelRobot> robot, const MapKernelSettings& map)
    : robot_(require(std::move(robot))),
      settings_(robot_->settings()),
      kernels_(robot_->kernels()),
      kinematics_(robot_->kinematics()),
      self_(robot_->self_collision()),
      map_(map, kernels_.max_extent_voxels() + 2, kernels_.base_layers(), kernels_.base_reach2()),
      motion_step_m_(robot_->motion_step_m()) {
  settings_.map = map;
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
  // No projected column within reach of any yaw's kernel; then none in the footprint rectangle
  // (neither test implies the other: the rectangle's corners lie outside the disc, and the disc
  // reaches past the rectangle where the kernels are not symmetric about the base's column);
  // then tile by tile, row by row.
  if (map_.base_disc_clear(bx, by)) return false;
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
// than d_j from the core set, i.e. when the map's clearance bound at its centre exceeds its
// radius + d_j (MapKernel::clear8(); clearance units, with the same float slack as d_j). T_V_J
// maps metres to padded voxels.
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
  return ~map_.clear8(x, y, z, need) & 0xfeu;
}

PORTER_KERNEL_CLONES bool KernelCollisionChecker::link_hit(int link, int sample, const Pose4f& T_V_B,
                                                           const Pose4f& T_B_J) const {
  const float scale = clearance_units_per_m_;
  const MapKernel& map = map_;
  const WidePointTreePool& pool = kernels_.link_pool(link);
  const float reach2 = kernel_reach2_vox_[static_cast<std::size_t>(link)];
  const float reach_units = kernel_reach_units_[static_cast<std::size_t>(link)];
  const PoseLanes T_V_J = PoseLanes::splat(T_V_B * T_B_J);
  const v8f scale8 = v8f_splat(scale), reach8 = v8f_splat(reach_units);
  return wide_tree_any(
      pool, sample,
      [&](const WideNode& n) PORTER_SIMD_LAMBDA {
        v8f ux, uy, uz;
        T_V_J.apply(v8f_load(n.cx), v8f_load(n.cy), v8f_load(n.cz), &ux, &uy, &uz);
        // Open: not proven clear (NaN stays open).
        return ~map.clear8(ux, uy, uz, v8f_load(n.r) * scale8 + reach8);
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

// The tests before any kinematics, in check()'s order: a map is set, every joint has a kernel
// sample, the base origin is on the map, the base kernel is clear. Inlined into check_prepared()
// and check_lanes(), which run them for one configuration each.
PORTER_SIMD_INLINE int KernelCollisionChecker::first_tests(const RobotConfiguration& config,
                                                           std::array<int, kNumLinks>& sample, double* ux,
                                                           double* uy) const {
  if (!map_.has_map()) return 0;
  for (int j = 1; j <= kNumArmJoints; ++j) {
    sample[static_cast<std::size_t>(j)] = kernels_.joint_sample(j, config.q_rad[j - 1]);
    if (sample[static_cast<std::size_t>(j)] < 0) return j;
  }
  if (!base_voxel(config.base, ux, uy)) return 0;
  if (base_hit(static_cast<int>(*ux), static_cast<int>(*uy), kernels_.base_sample(config.base.yaw_rad))) return 0;
  return -1;
}

PORTER_KERNEL_CLONES CollisionResult KernelCollisionChecker::check_prepared(const RobotConfiguration& config,
                                                                            bool self) const {
  std::array<int, kNumLinks> sample{};  // nearest kernel sample per arm joint (index = link)
  double ux = 0.0, uy = 0.0;            // base origin, padded voxel coordinates
  const int first = first_tests(config, sample, &ux, &uy);
  if (first >= 0) return hit(first);
  ArmPoses poses;
  kinematics_.compute(config.q_rad, poses);
  const Pose4f T_V_B = base_to_voxels(config.base.yaw_rad, ux, uy);
  const std::uint32_t near = links_near(sample, T_V_B, poses);
  for (int link : kArmOrder) {
    const auto l = static_cast<std::size_t>(link);
    if (((near >> link) & 1u) && link_hit(link, sample[l], T_V_B, poses.T_B_J[l])) return hit(link);
  }
  if (self && settings_.check_self_collision) return self_.check(poses);
  return CollisionResult{};
}

CollisionResult KernelCollisionChecker::check(const RobotConfiguration& config) const {
  return check_prepared(config, true);
}

void KernelCollisionChecker::check_batch(const RobotConfiguration* configs, std::size_t count,
                                         CollisionResult* results) const {
  for (std::size_t i = 0; i < count; i += 8)
    check_lanes(configs + i, static_cast<int>(std::min<std::size_t>(8, count - i)), results + i);
}

// check_prepared() for up to eight configurations, configuration i in lane i: the per-configuration
// tests that have no tree below them (joint limits, base) one by one, forward kinematics and the
// root spheres of links 1..7 in lanes, the link trees per configuration in check()'s order, then
// self-collision in lanes (SelfCollisionChecker::check_lanes). Lanes >= count or resolved early
// compute on the rest pose and are ignored.
PORTER_KERNEL_CLONES void KernelCollisionChecker::check_lanes(const RobotConfiguration* configs, int count,
                                                              CollisionResult* results) const {
  std::array<const JointVector*, 8> q{};
  std::array<std::array<int, kNumLinks>, 8> sample{};
  std::array<Pose4f, 8> T_V_B4;
  std::uint32_t pending = 0;  // lanes not decided yet
  for (int i = 0; i < 8; ++i) {
    const auto li = static_cast<std::size_t>(i);
    q[li] = &kRestJoints;
    T_V_B4[li] = Pose4f::identity();
    if (i >= count) continue;
    const RobotConfiguration& config = configs[i];
    std::array<int, kNumLinks> s{};
    double ux = 0.0, uy = 0.0;
    const int first = first_tests(config, s, &ux, &uy);
    results[i] = first >= 0 ? hit(first) : CollisionResult{};
    if (first >= 0) continue;
    sample[li] = s;
    q[li] = &config.q_rad;
    T_V_B4[li] = base_to_voxels(config.base.yaw_rad, ux, uy);
    pending |= 1u << i;
  }
  if (pending == 0) return;
  ArmPoseLanes poses;
  kinematics_.compute_lanes(q, poses);
  PoseLanes T_V_B;  // every lane written below
  for (int i = 0; i < 8; ++i) T_V_B.set_lane(i, T_V_B4[static_cast<std::size_t>(i)]);
  // Root spheres of links 1..7, eight configurations per test (links_near() in lanes): the
  // first 16 bytes of a WideTreeRoot are its centre and radius, one row per lane.
  std::array<std::uint32_t, kNumLinks> near{};
  const v8f scale = v8f_splat(clearance_units_per_m_);
  for (int link = 1; link < kNumLinks; ++link) {
    const auto l = static_cast<std::size_t>(link);
    const WidePointTreePool& pool = kernels_.link_pool(link);
    v4f rows[8];
    std::uint32_t empty = 0;
    for (int i = 0; i < 8; ++i) {
      const WideTreeRoot& root = pool.root(sample[static_cast<std::size_t>(i)][l]);
      std::memcpy(&rows[i], &root, sizeof(v4f));
      empty |= static_cast<std::uint32_t>(root.num_points == 0) << i;
    }
    v8f x, y, z, radius;
    transpose8x4(rows, &x, &y, &z, &radius);
    poses.T_B_J[l].apply(x, y, z, &x, &y, &z);
    T_V_B.apply(x, y, z, &x, &y, &z);
    const v8f need = radius * scale + v8f_splat(kernel_reach_units_[l]);
    near[l] = ~map_.clear8(x, y, z, need) & pending & ~empty;
  }
  for (std::uint32_t m = pending; m != 0; m &= m - 1) {
    const int i = __builtin_ctz(m);
    const auto li = static_cast<std::size_t>(i);
    for (int link : kArmOrder) {
      const auto l = static_cast<std::size_t>(link);
      if (((near[l] >> i) & 1u) && link_hit(link, sample[li][l], T_V_B4[li], poses.T_B_J[l].lane(i))) {
        results[i] = hit(link);
        pending &= ~(1u << i);
        break;
      }
    }
  }
  if (pending != 0 && settings_.check_self_collision) self_.check_lanes(poses, pending, results);
}

CollisionResult KernelCollisionChecker::check_environment(const RobotConfiguration& config) const {
  return check_prepared(config, false);
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
