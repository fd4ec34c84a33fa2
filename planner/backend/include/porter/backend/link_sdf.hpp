#pragma once
// Signed distance field of one rigid body R_j in its own frame Lj (paper eq. g's SDF^R): a
// planning link of the robot, with the payload for link 7. Negative inside.
//
// Node values are exact (see sdf_builder): primitives by shape_signed_distance, closed meshes by
// the nearest-triangle distance signed with the generalized winding number, so non-convex payloads
// (the T, the arc) get the right sign everywhere. With several shapes the field is the minimum of
// their signed distances: exact outside the union; inside, where shapes overlap, its magnitude may
// underestimate the depth (the conservative side, as g itself is, paper §VI-A).
//
// Two grids:
//   - fine  : body bounds padded by fine_padding_m, spacing chosen per body (below); covers every
//             distance the safety margin s_thr looks at;
//   - coarse: body bounds padded by coarse_padding_m at coarse_resolution_m; covers the ball search
//             of KC-SVSDF, whose samples lie up to its initial radius away from the query point.
// Beyond the coarse grid the value is d(q) + |p - q| with q the nearest point of the coarse box (an
// upper bound on the true distance, and >= coarse_padding_m), gradient the exact derivative.
// Inside the grids the field is the C^1 quadratic B-spline of the node values (sdf_grid.hpp: the
// SVSDF's envelope-theorem gradients need a C^1 field); over the fine grid's outer band (two coarse
// cells wide, beyond fine_padding_m - 8 cm from the body) it blends into the coarse field with a C^1
// weight, so the field stays C^1 where the grids meet (a convex blend keeps the error bounds).
// distance_fast() is the trilinear interpolant of the same nodes (no blend), for ranking samples.
//
// Resolution: both interpolants of a 1-Lipschitz field err by at most sqrt(3)/2 * h (exact where
// the field is affine, i.e. facing a flat face), so h is the finest spacing for which
// the padded fine grid stays within node_budget nodes, clamped to [min_resolution_m,
// max_resolution_m]: memory and build time are bounded per link (2.4 MB at the default budget)
// whatever the body size, small links get a finer grid than large ones, and the bound stays far
// below the 5 cm map voxels the obstacle points come from (Piper links ~4-5 mm -> <= 4.3 mm error;
// the base and a 1 m payload ~9-10 mm -> <= 8.7 mm).
//
// Thread-safety: immutable after build(); distance() is reentrant and does not allocate.

#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "porter/backend/sdf_grid.hpp"
#include "porter/core/geometry.hpp"

namespace porter::backend {

struct SdfGridSettings {
  /// Padding of the fine grid around the body's bounds, m. Must exceed the safety margin s_thr
  /// (0.15 m by default) so every penalized distance is read at full resolution.
  double fine_padding_m = 0.25;
  /// Padding of the coarse grid, m (>= fine_padding_m); the KC-SVSDF ball search reads up to its
  /// initial radius beyond the body.
  double coarse_padding_m = 0.8;
  double coarse_resolution_m = 0.04;
  /// Node budget of the fine grid (sets the resolution, see the header comment).
  double node_budget = 6.0e5;
  double min_resolution_m = 0.004;
  double max_resolution_m = 0.02;
};

class LinkSdf {
 public:
  /// Distance reported for a body without geometry, m.
  static constexpr double kNoGeometryDistance_m = 1e3;

  /// A body without geometry: distance() returns kNoGeometryDistance_m, zero gradient.
  LinkSdf() = default;

  /// Builds the field of `shapes_L` (placed in the body frame by their T_parent_shape). Settings
  /// must be positive and finite with coarse_padding_m >= fine_padding_m (not checked: internal).
  static LinkSdf build(const std::vector<CollisionShape>& shapes_L, const SdfGridSettings& settings);

  bool empty() const { return fine_.empty(); }
  /// Signed distance at p_L (body frame), m; its gradient (body frame) to *grad_L when non-null.
  /// C^1 inside the coarse grid.
  double distance(const Eigen::Vector3d& p_L, Eigen::Vector3d* grad_L = nullptr) const;
  /// Same field with trilinear interpolation (no gradient): within the same error bound of the
  /// true distance, ~3x cheaper. For coarse scans only.
  double distance_fast(const Eigen::Vector3d& p_L) const;
  /// distance_fast() and a lower bound on the exact signed distance at p_L to *sd_lower: the value
  /// minus the error bound of the grid read (fine or coarse); beyond the coarse grid (where the
  /// value is an upper bound) the coarse padding, which the exact distance exceeds there.
  double distance_fast(const Eigen::Vector3d& p_L, double* sd_lower) const;

  const SdfGrid& fine() const { return fine_; }
  const SdfGrid& coarse() const { return coarse_; }
  double resolution_m() const { return fine_.resolution_m(); }
  /// Bounds of the geometry in the body frame (empty for an empty body).
  const Eigen::AlignedBox3d& body_bounds() const { return body_bounds_; }

 private:
  SdfGrid fine_;
  SdfGrid coarse_;
  double blend_width_m_ = 0.0;
  double coarse_padding_m_ = 0.0;
  Eigen::AlignedBox3d body_bounds_;
};

/// The fine-grid spacing LinkSdf::build picks for a body with these bounds (header comment).
double choose_sdf_resolution(const Eigen::AlignedBox3d& body_bounds, const SdfGridSettings& settings);

}  // namespace porter::backend
