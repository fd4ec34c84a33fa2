#include "porter/backend/link_sdf.hpp"

#include <algorithm>
#include <cmath>

#include "sdf_builder.hpp"

namespace porter::backend {

double choose_sdf_resolution(const Eigen::AlignedBox3d& body_bounds, const SdfGridSettings& s) {
  const Eigen::Vector3d padded =
      body_bounds.sizes() + Eigen::Vector3d::Constant(2.0 * s.fine_padding_m);
  const double h = std::cbrt(padded.prod() / std::max(1.0, s.node_budget));
  return std::clamp(h, s.min_resolution_m, s.max_resolution_m);
}

LinkSdf LinkSdf::build(const std::vector<CollisionShape>& shapes_L, const SdfGridSettings& s) {
  LinkSdf sdf;
  Eigen::AlignedBox3d bounds;
  for (const CollisionShape& shape : shapes_L) bounds.extend(shape_bounds(shape));
  if (bounds.isEmpty() || !bounds.sizes().allFinite()) return sdf;
  sdf.body_bounds_ = bounds;

  const double h = choose_sdf_resolution(bounds, s);
  const Eigen::Vector3d fine_pad = Eigen::Vector3d::Constant(s.fine_padding_m);
  sdf.fine_ = SdfGrid::covering(Eigen::AlignedBox3d(bounds.min() - fine_pad, bounds.max() + fine_pad), h);
  detail::fill_exact_sdf(shapes_L, sdf.fine_);

  const double hc = std::max(h, s.coarse_resolution_m);
  const Eigen::Vector3d coarse_pad = Eigen::Vector3d::Constant(std::max(s.coarse_padding_m, s.fine_padding_m));
  Eigen::AlignedBox3d coarse_box(bounds.min() - coarse_pad, bounds.max() + coarse_pad);
  coarse_box.extend(sdf.fine_.bounds());
  sdf.coarse_ = SdfGrid::covering(coarse_box, hc);
  detail::fill_exact_sdf(shapes_L, sdf.coarse_);
  sdf.blend_width_m_ = 2.0 * hc;
  sdf.coarse_padding_m_ = coarse_pad.x();
  return sdf;
}

double LinkSdf::distance(const Eigen::Vector3d& p_L, Eigen::Vector3d* grad_L) const {
  if (fine_.empty()) {
    if (grad_L) grad_L->setZero();
    return kNoGeometryDistance_m;
  }
  if (fine_.contains(p_L)) {
    // Blend into the coarse field over the fine grid's outer band so that the field stays C^1
    // where the two grids meet (their values differ by up to both error bounds).
    const Eigen::AlignedBox3d& box = fine_.smooth_bounds();
    double alpha = 1.0;
    Eigen::Vector3d dalpha = Eigen::Vector3d::Zero();
    double ramp[3], dramp[3];
    for (int a = 0; a < 3; ++a) {
      const double to_lo = p_L[a] - box.min()[a], to_hi = box.max()[a] - p_L[a];
      const double u = std::min(to_lo, to_hi) / blend_width_m_;
      if (u >= 1.0) {
        ramp[a] = 1.0;
        dramp[a] = 0.0;
      } else {
        ramp[a] = u * u * (3.0 - 2.0 * u);
        dramp[a] = 6.0 * u * (1.0 - u) / blend_width_m_ * (to_lo < to_hi ? 1.0 : -1.0);
      }
      alpha *= ramp[a];
    }
    if (alpha >= 1.0) return fine_.smooth(p_L, grad_L);
    Eigen::Vector3d gf, gc;
    const double vf = fine_.smooth(p_L, grad_L ? &gf : nullptr);
    const double vc = coarse_.smooth(p_L, grad_L ? &gc : nullptr);
    if (grad_L) {
      dalpha << dramp[0] * ramp[1] * ramp[2], ramp[0] * dramp[1] * ramp[2], ramp[0] * ramp[1] * dramp[2];
      *grad_L = alpha * gf + (1.0 - alpha) * gc + (vf - vc) * dalpha;
    }
    return alpha * vf + (1.0 - alpha) * vc;
  }
  if (coarse_.contains(p_L)) return coarse_.smooth(p_L, grad_L);
  // Outside both grids: d(q) + |p - q|, q the nearest point of the coarse box.
  const Eigen::AlignedBox3d& box = coarse_.smooth_bounds();
  const Eigen::Vector3d q = p_L.cwiseMax(box.min()).cwiseMin(box.max());
  const Eigen::Vector3d offset = p_L - q;
  const double len = offset.norm();
  Eigen::Vector3d gq;
  const double dq = coarse_.smooth(q, grad_L ? &gq : nullptr);
  if (grad_L) {
    for (int a = 0; a < 3; ++a) {
      if (p_L[a] < box.min()[a] || p_L[a] > box.max()[a]) gq[a] = 0.0;  // q does not move
    }
    *grad_L = gq + (len > 0.0 ? Eigen::Vector3d(offset / len) : Eigen::Vector3d::Zero());
  }
  return dq + len;
}

}  // namespace porter::backend

namespace porter::backend {

double LinkSdf::distance_fast(const Eigen::Vector3d& p_L) const {
  if (fine_.empty()) return kNoGeometryDistance_m;
  if (fine_.contains(p_L)) return fine_.trilinear(p_L, nullptr);
  if (coarse_.contains(p_L)) return coarse_.trilinear(p_L, nullptr);
  const Eigen::AlignedBox3d& box = coarse_.smooth_bounds();
  const Eigen::Vector3d q = p_L.cwiseMax(box.min()).cwiseMin(box.max());
  return coarse_.trilinear(q, nullptr) + (p_L - q).norm();
}

double LinkSdf::distance_fast(const Eigen::Vector3d& p_L, double* sd_lower) const {
  if (fine_.empty()) {
    *sd_lower = kNoGeometryDistance_m;
    return kNoGeometryDistance_m;
  }
  if (fine_.contains(p_L)) {
    const double v = fine_.trilinear(p_L, nullptr);
    *sd_lower = v - fine_.error_bound_m();
    return v;
  }
  if (coarse_.contains(p_L)) {
    const double v = coarse_.trilinear(p_L, nullptr);
    *sd_lower = v - coarse_.error_bound_m();
    return v;
  }
  // Outside the coarse grid's B-spline region, p is at least coarse_padding - h_c / 2 from the
  // body's bounds.
  const Eigen::AlignedBox3d& box = coarse_.smooth_bounds();
  const Eigen::Vector3d q = p_L.cwiseMax(box.min()).cwiseMin(box.max());
  *sd_lower = coarse_padding_m_ - 0.5 * coarse_.resolution_m();
  return coarse_.trilinear(q, nullptr) + (p_L - q).norm();
}

}  // namespace porter::backend
