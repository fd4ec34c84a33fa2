#pragma once
// A scalar field (signed distance) sampled on a regular 3D grid of nodes, with two interpolants:
//   - smooth(): the quadratic B-spline quasi-interpolant s(p) = sum_i f(x_i) B2((p - x_i) / h)
//     (27 nodes, tensor product). It is C^1, so a minimum over time of s along a smooth path has
//     a zero time derivative and the envelope theorem holds exactly (the SVSDF gradients need it;
//     the trilinear interpolant's slope jumps at cell faces, and most minima sit on such jumps).
//     It reproduces affine fields exactly (flat faces);
//   - trilinear(): the usual 8-node interpolant, C^0, ~3x cheaper; used to rank candidates.
// Both are convex combinations of node values with weights whose second moment about p is at most
// 1/4 h^2 per axis (B-spline: exactly (n+1)/12 h^2 = h^2/4; trilinear: u(1-u) h^2 <= h^2/4), so for
// a 1-Lipschitz field (a distance) both err by at most sqrt(3)/2 * h (error_bound_m()).
//
// Nodes sit at origin + (i, j, k) * h for i in [0, nx), j in [0, ny), k in [0, nz); node (i, j, k)
// is stored at i + nx * (j + ny * k) as float (distances are < 1e3 m; float keeps 1e-4 mm there
// and halves the cache footprint of the hot loop). Frames and units are the caller's (metres).
//
// Gradients are the exact gradients of the returned interpolant. Queries outside the region an
// interpolant is defined on (bounds() for trilinear; bounds() shrunk by h/2 for the B-spline, whose
// support is 3 nodes wide) are clamped into it first; the gradient is then that of the clamped point.
//
// Thread-safety: const members are reentrant; no member allocates after construction.

#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace porter::backend {

class SdfGrid {
 public:
  SdfGrid() = default;
  /// All node values 0. dims are node counts, each >= 3 (smaller counts are raised); resolution_m > 0.
  SdfGrid(const Eigen::Vector3d& origin, double resolution_m, const Eigen::Vector3i& dims);

  /// The smallest grid of spacing resolution_m whose B-spline region (bounds() shrunk by h/2)
  /// contains `box`.
  static SdfGrid covering(const Eigen::AlignedBox3d& box, double resolution_m);

  bool empty() const { return values_.empty(); }
  const Eigen::Vector3d& origin() const { return origin_; }
  double resolution_m() const { return h_; }
  const Eigen::Vector3i& dims() const { return dims_; }
  std::size_t num_nodes() const { return values_.size(); }
  /// Box spanned by the nodes (the trilinear interpolant's domain).
  const Eigen::AlignedBox3d& bounds() const { return bounds_; }
  /// bounds() shrunk by h/2 on every side: the B-spline's domain.
  const Eigen::AlignedBox3d& smooth_bounds() const { return smooth_bounds_; }
  bool contains(const Eigen::Vector3d& p) const { return smooth_bounds_.contains(p); }
  double error_bound_m() const { return 0.8660254037844386 * h_; }

  Eigen::Vector3d node_position(int i, int j, int k) const {
    return origin_ + h_ * Eigen::Vector3d(i, j, k);
  }
  std::size_t index(int i, int j, int k) const {
    return static_cast<std::size_t>(i) +
           static_cast<std::size_t>(dims_.x()) *
               (static_cast<std::size_t>(j) + static_cast<std::size_t>(dims_.y()) * k);
  }
  float value(int i, int j, int k) const { return values_[index(i, j, k)]; }
  void set(int i, int j, int k, float v) { values_[index(i, j, k)] = v; }
  std::vector<float>& values() { return values_; }
  const std::vector<float>& values() const { return values_; }

  /// B-spline (C^1) value at p; its gradient to *grad when non-null. Needs >= 3 nodes per axis.
  double smooth(const Eigen::Vector3d& p, Eigen::Vector3d* grad) const;
  /// Trilinear value at p; its gradient (piecewise, jumps at cell faces) to *grad when non-null.
  double trilinear(const Eigen::Vector3d& p, Eigen::Vector3d* grad) const;

 private:
  Eigen::Vector3d origin_ = Eigen::Vector3d::Zero();
  double h_ = 1.0;
  double inv_h_ = 1.0;
  Eigen::Vector3i dims_ = Eigen::Vector3i::Zero();
  Eigen::AlignedBox3d bounds_;
  Eigen::AlignedBox3d smooth_bounds_;
  std::vector<float> values_;
};

}  // namespace porter::backend
