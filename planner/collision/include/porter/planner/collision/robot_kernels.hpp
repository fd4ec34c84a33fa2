#pragma once
// The chain-decomposed robot kernels K = {K^0, K^1..K^6, K^7} (paper §IV-C), at map resolution h.
//
// K^0 (base, link 0): for each of N_0 yaw samples psi_k = -pi + 2 pi k / N_0, the set of integer
// voxel offsets d = (dx, dy, dz), dz >= 0, relative to the voxel that contains the base origin
// (the ground z = 0 is a voxel boundary, so the origin sits on the bottom face of layer dz = 0)
// such that the base geometry rotated by psi_k intersects the box
//     [(dx-1)h - e_0, (dx+1)h + e_0] x [(dy-1)h - e_0, (dy+1)h + e_0] x [dz h, (dz+1) h],
// e_0 = r_0 pi / N_0 (r_0: base radius about the vertical axis). The box holds voxel d for every
// position of the origin inside its voxel (hence the extra voxel towards -x, -y) and every yaw
// within half a bin of
// psi_k (a point at radius r moves at most r pi / N_0), so the offsets are a superset of the
// voxels the base meets at any pose that selects this sample: testing them against the
// undilated base set of the map kernel is conservative, with pure integer offsets. Offsets are
// stored as rows along x (a 64-bit mask per (dy, dz)) grouped into tiles of 4 dy rows whose x-y
// rectangle is first tested against the map's projected base columns.
// Inflation bound: a base flagged in collision is within sqrt(2) (h + e_0) + e_0 of a base-set
// voxel.
//
// K^j, j = 1..6: link j's geometry, in the frame J_j (parent frame after joint j's origin, before
// its rotation), voxelized for N_j samples alpha_k = lower + k (upper - lower) / (N_j - 1) of q_j:
// the points of the lattice s Z^3 of J_j (s = h / lattice_subdivision) within
// d_j = s sqrt(3)/2 + e_j of the geometry rotated by alpha_k, with
// e_j = r_j (upper - lower) / (2 (N_j - 1)) (r_j: largest distance of the link from joint j's
// origin; the nearest sample moves a link point at most r_j * step / 2).
// K^7: gripper + payload in the EE frame, one kernel (no joint), d_7 = s sqrt(3)/2.
// Each kernel is an eight-wide sphere tree (wide_point_tree.hpp). A query transforms the points of the sample
// nearest q_j by T_W_J; a point hits when it lies within d_j of the box of a core voxel
// (occupied / outside / below ground, map_kernel.hpp): one bit of the map kernel's dilated arm
// set first, then the exact point-to-box distances of the 27 voxels around it (MapKernel::arm_near).
// Why that is conservative: let x be a point of link j at the query, inside a core voxel V. The
// lattice point k nearest to x (in J_j) is within s sqrt(3)/2 of x, and x rotated back to
// alpha_k lies in the sampled geometry within e_j of x, so k is in K^j. Its world image u lies
// within s sqrt(3)/2 + e_j = d_j of x, hence within d_j of V's box; d_j < h (checked at build
// time), so V is u's voxel or one of its 26 neighbours and u is in the dilated arm set. The
// distance test uses d_j grown by 1e-4 voxel for float32 rounding of poses and points.
// Inflation bound: a link flagged in collision is within 2 d_j + e_j = s sqrt(3) + 3 e_j of a
// core voxel (u is within d_j of the sampled geometry, which is within e_j of the link, and
// within d_j of the voxel). With the default s = h / 2 and e_j <= h / 10 that is 0.17 h + 0.87 h
// ~ 5.8 cm at h = 5 cm; a lattice of spacing h with a one-voxel dilation would allow
// (3 sqrt(3)/2) h + 2 e_j ~ 14 cm, enough to close the passages the payload is meant to fit.
//
// Counts grow as N_0 + sum N_j + 1, never as a product. Joint values outside
// [lower - step/2, upper + step/2] have no sample (joint_sample returns -1).
//
// Thread-safety: immutable after construction; concurrent reads are safe.

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "porter/core/robot_model.hpp"
#include "porter/planner/collision/kernel_kinematics.hpp"
#include "porter/planner/collision/wide_point_tree.hpp"

namespace porter::planner {

struct RobotKernelSettings {
  /// Voxel edge h (m); must equal the resolution of the maps the kernels are used with.
  double resolution_m = 0.05;
  /// Target for e_j, the largest displacement of a link point caused by snapping a joint to its
  /// nearest sample (m). <= 0 selects 0.1 * resolution_m. Sets N_j (and N_0 when
  /// base_yaw_samples is 0); smaller means more kernels and fewer false positives.
  double max_sample_error_m = 0.0;
  /// N_0; 0 derives it from max_sample_error_m and the base radius.
  int base_yaw_samples = 0;
  /// Point lattice of K^1..K^7: spacing s = resolution_m / lattice_subdivision (>= 1). Finer
  /// means less inflation (see above) and more points; d_j must stay below one voxel.
  int lattice_subdivision = 2;
};

/// One x-row of a base kernel: voxels dx0 + i for every set bit i of mask, at (dy, dz).
struct BaseKernelRow {
  std::uint64_t mask = 0;
  std::int16_t dx0 = 0, dy = 0, dz = 0, reserved = 0;
};

/// Rows [row_begin, row_end) whose voxels lie in the x-y rectangle [dx_lo, dx_hi] x [dy_lo, dy_hi].
struct BaseKernelTile {
  std::int16_t dx_lo = 0, dx_hi = -1, dy_lo = 0, dy_hi = -1;
  std::uint32_t row_begin = 0, row_end = 0;
};

class RobotKernels {
 public:
  /// Builds every kernel for `model` (payload attached). Throws std::invalid_argument for a
  /// non-positive resolution or a base with no geometry.
  RobotKernels(const RobotModel& model, const RobotKernelSettings& settings);

  double resolution_m() const { return res_; }
  const ChainRadii& radii() const { return radii_; }

  /// N_0 for link 0, N_j for 1..6, 1 for link 7.
  int num_samples(int link) const { return num_samples_[static_cast<std::size_t>(link)]; }
  /// e_j (m) actually achieved; 0 for link 7.
  double sample_error_m(int link) const { return sample_error_[static_cast<std::size_t>(link)]; }
  /// Lattice spacing s of the point kernels (m).
  double lattice_spacing_m() const { return spacing_; }
  /// d_j = s sqrt(3)/2 + e_j (links 1..7).
  double kernel_radius_m(int link) const { return kernel_radius_[static_cast<std::size_t>(link)]; }
  /// Environment inflation bound of the link (m), see the header comment.
  double inflation_bound_m(int link) const;

  /// Yaw sample nearest yaw_rad (any finite angle; 0 for a non-finite one).
  int base_sample(double yaw_rad) const {
    // The usual case, yaw in about [-pi, pi]: round, and wrap the last half-sample to 0.
    const int n = num_samples_[0];
    const double t = (yaw_rad + 3.14159265358979323846) * inv_step_[0] + 0.5;
    if (t >= 0.0 && t < n + 1.0) {
      const int k = static_cast<int>(t);
      return k == n ? 0 : k;
    }
    return base_sample_wrapped(yaw_rad);
  }
  double base_sample_yaw(int k) const;
  /// base_sample() for any angle (reduction modulo 2 pi).
  int base_sample_wrapped(double yaw_rad) const;
  /// Sample nearest q for joint j (1..6), -1 outside the covered range or for NaN.
  int joint_sample(int joint, double q_rad) const {
    const auto j = static_cast<std::size_t>(joint);
    const double t = (q_rad - lower_[j]) * inv_step_[j] + 0.5;
    if (!(t >= 0.0) || !(t < num_samples_[j])) return -1;
    return static_cast<int>(t);
  }
  double joint_sample_value(int joint, int k) const;

  // Base kernel (link 0).
  const BaseKernelTile* base_tiles(int k, std::size_t* count) const {
    const auto s = static_cast<std::size_t>(k);
    *count = base_tile_begin_[s + 1] - base_tile_begin_[s];
    return base_tiles_.data() + base_tile_begin_[s];
  }
  const BaseKernelRow* base_rows() const { return base_rows_.data(); }
  /// x-y rectangle covering every base kernel (offsets, voxels), for a whole-footprint test.
  const std::array<int, 4>& base_footprint() const { return base_footprint_; }
  /// Number of voxel layers above the ground any base kernel reaches.
  int base_layers() const { return base_layers_; }
  /// Largest dx^2 + dy^2 over the voxels (dx, dy, dz) of every base kernel: no base kernel has a
  /// column farther than sqrt(base_reach2()) from the base's own column (MapKernel::base_disc_clear()).
  int base_reach2() const { return base_reach2_; }
  /// Offsets of yaw sample k (tests).
  std::vector<Eigen::Vector3i> base_offsets(int k) const;

  // Point kernels (links 1..7): tree k of pool `link_pool(j)` is sample k, frame J_j, metres.
  const WidePointTreePool& link_pool(int link) const { return pools_[static_cast<std::size_t>(link)]; }

  /// Total kernels (N_0 + sum N_j + 1) and the bytes they use.
  int kernel_count() const;
  std::size_t bytes() const;
  /// Largest |offset| of any kernel voxel or point from the base origin, in voxels (padding).
  int max_extent_voxels() const { return max_extent_voxels_; }

 private:
  void build_base(const RobotModel& model, int n_yaw);
  void build_link(const RobotModel& model, int link, double target_error_m);

  double res_ = 0.0;
  double spacing_ = 0.0;
  double base_horizontal_radius_ = 0.0;
  ChainRadii radii_;
  std::array<int, kNumLinks> num_samples_{};
  std::array<double, kNumLinks> sample_error_{}, kernel_radius_{};
  std::array<double, kNumLinks> lower_{}, step_{}, inv_step_{};
  std::vector<BaseKernelRow> base_rows_;
  std::vector<BaseKernelTile> base_tiles_;
  std::vector<std::size_t> base_tile_begin_{0};
  std::array<int, 4> base_footprint_{0, -1, 0, -1};
  int base_layers_ = 1;
  int base_reach2_ = 0;
  std::array<WidePointTreePool, kNumLinks> pools_;
  int max_extent_voxels_ = 0;
};

/// Lattice points p = s * i (i integer, frame F) whose distance to the link geometry is at most
/// radius_m, where the geometry is `link` (frame L) seen through T_L_F; only points inside
/// `bounds_F` are considered. Evaluated hierarchically (blocks of 4^3 decided from their centre's
/// distance when possible); the result equals testing every point. Used by the kernels and the
/// self-collision samples.
class LinkDistance;
std::vector<Eigen::Vector3f> lattice_points_within(const LinkDistance& link, const Eigen::Isometry3d& T_L_F,
                                                   double spacing_m, double radius_m,
                                                   const Eigen::AlignedBox3d& bounds_F);

}  // namespace porter::planner
