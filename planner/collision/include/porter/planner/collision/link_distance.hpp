#pragma once
// Signed distance to one planning link's exact geometry (the union of its collision shapes),
// and a rasterized distance grid of it used as a cheap lower bound. Used by the self-collision check and by
// its build-time proofs; nothing here approximates: DistanceGrid holds lower bounds.
//
// Frames and units: the link frame L (the frame the shapes are given in), metres.
// Thread-safety: immutable after construction; concurrent reads are safe.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "porter/core/geometry.hpp"
#include "porter/planner/collision/simd8.hpp"

namespace porter::planner {

class LinkDistance {
 public:
  LinkDistance() = default;
  explicit LinkDistance(const std::vector<CollisionShape>& shapes_L);

  bool empty() const { return shapes_.empty(); }
  /// Bounds of all shapes (link frame); empty box when the link has no shapes.
  const Eigen::AlignedBox3d& bounds() const { return bounds_; }

  /// min over shapes of the shape's signed distance: the exact distance to the union outside
  /// it, <= 0 inside it (sign exact; the depth is a shape's, not the union's). +inf when empty.
  double signed_distance(const Eigen::Vector3d& p_L) const;

  /// True when signed_distance(p_L) <= threshold_m (exits at the first shape that is close).
  bool within(const Eigen::Vector3f& p_L, float threshold_m) const;

 private:
  enum class Kind { kBox, kCylinder, kSphere, kMesh };
  struct Prim {
    Kind kind = Kind::kBox;
    Eigen::Matrix3f R_S_L = Eigen::Matrix3f::Identity();  ///< link -> shape rotation
    Eigen::Vector3f t_S_L = Eigen::Vector3f::Zero();
    Eigen::Vector3f half_m = Eigen::Vector3f::Zero();  ///< box half sizes; cylinder (r, r, l/2)
    Eigen::AlignedBox3f bounds_L;                      ///< of the shape, link frame
    int shape = 0;                                     ///< index into shapes_
  };
  static float prim_distance(const Prim& prim, const Eigen::Vector3f& p_L);

  std::vector<CollisionShape> shapes_;
  std::vector<Prim> prims_;
  Eigen::AlignedBox3d bounds_;
};

/// A lower bound of the distance to a link's geometry far from it: the distance to the union of
/// at most kMaxBoxes axis-aligned boxes (link frame) that contain the shapes (their bounding
/// boxes; beyond kMaxBoxes shapes, merged pairwise where that adds the least volume; grown by
/// 0.01 mm for float rounding). Where a DistanceGrid is capped (32 cm at s = 1 cm) or falls back
/// to the distance to its own box (which holds the margin and the empty space between the
/// shapes), this keeps its precision: on 5 000 free-near forest configurations the payload's
/// root sphere (0.6 m) was proven clear of the base (8 shapes, 8 boxes) in 63 % of them this
/// way, in 20 % by the base's grid (the exact distance: 63 %); with 4 merged boxes, 49 %.
class BoxUnionBound {
 public:
  static constexpr int kMaxBoxes = 8;
  BoxUnionBound() = default;
  explicit BoxUnionBound(const std::vector<CollisionShape>& shapes_L);

  int num_boxes() const { return count_; }
  /// Bit i set when point i is farther than distance_i from every box (so from the geometry).
  PORTER_SIMD_INLINE std::uint32_t clear_of8(const v8f& px, const v8f& py, const v8f& pz, const v8f& distance_m) const {
    const v8f zero = v8f_splat(0.f);
    v8i clear = v8i_splat(-1);
    for (int b = 0; b < count_; ++b) {
      const Box& box = boxes_[static_cast<std::size_t>(b)];
      auto gap = [&zero](const v8f& p, float lo, float hi) PORTER_SIMD_LAMBDA {
        const v8f below = v8f_splat(lo) - p, above = p - v8f_splat(hi);
        const v8f g = below > above ? below : above;  // NaN when p is
        return g < zero ? zero : g;                   // and stays NaN: never clear
      };
      const v8f gx = gap(px, box.lo[0], box.hi[0]), gy = gap(py, box.lo[1], box.hi[1]), gz = gap(pz, box.lo[2], box.hi[2]);
      clear &= gx * gx + gy * gy + gz * gz > distance_m * distance_m;
    }
    return lane_mask(clear & (distance_m >= zero)) & (count_ > 0 ? 0xffu : 0u);
  }

 private:
  struct Box {
    float lo[3], hi[3];
  };
  std::array<Box, kMaxBoxes> boxes_{};
  int count_ = 0;
};

/// A link rasterized on the lattice of voxels of edge s whose corners are s Z^3 (link frame):
/// the voxels its shapes intersect (exact, porter::voxelize_shape: closed boxes, touching
/// counts), and for every voxel of the box around them (the shapes' bounds grown by margin_m) a
/// lower bound of the distance from any point of the voxel to the geometry: s times the
/// distance between voxel centres to the 26-dilated occupied set, which is exactly the smallest
/// gap between the voxel's box and an occupied voxel's box. Stored as bytes in units of s / 8,
/// rounded down and clamped at 255 (a clamped value is still a lower bound).
class DistanceGrid {
 public:
  DistanceGrid() = default;
  DistanceGrid(const std::vector<CollisionShape>& shapes_L, double voxel_m, double margin_m);

  /// Centres of the occupied voxels: every point of the geometry lies in the voxel of one of
  /// them, hence within s sqrt(3)/2 of it.
  const std::vector<Eigen::Vector3f>& occupied_centres() const { return centres_; }

  /// A lower bound of the distance from p_L to the geometry (0 inside). Outside the box: the
  /// distance to the box plus margin_m (the geometry lies at least margin_m inside it).
  float lower_bound(const Eigen::Vector3f& p_L) const {
    const Eigen::Vector3f u = (p_L - origin_).array() * inv_voxel_;
    if ((u.array() >= 0.f).all() && (u.array() < extent_.array()).all()) {
      const int ix = static_cast<int>(u.x()), iy = static_cast<int>(u.y()), iz = static_cast<int>(u.z());
      return static_cast<float>(values_[static_cast<std::size_t>(ix + dims_.x() * (iy + dims_.y() * iz))]) * unit_;
    }
    const Eigen::Vector3f d = (u.cwiseMax(0.f).cwiseMin(extent_) - u) * voxel_;
    return d.norm() + margin_;
  }
  /// lower_bound(p_L) > distance_m, without a square root on the common paths.
  bool clear_of(const Eigen::Vector3f& p_L, float distance_m) const {
    const Eigen::Vector3f u = (p_L - origin_).array() * inv_voxel_;
    // floor(u) for u > -1 by truncating u + 1; anything below lands on -1 or less: outside.
    const int ix = static_cast<int>(u.x() + 1.f) - 1, iy = static_cast<int>(u.y() + 1.f) - 1,
              iz = static_cast<int>(u.z() + 1.f) - 1;
    if (static_cast<unsigned>(ix) < static_cast<unsigned>(dims_.x()) &&
        static_cast<unsigned>(iy) < static_cast<unsigned>(dims_.y()) &&
        static_cast<unsigned>(iz) < static_cast<unsigned>(dims_.z())) {
      return static_cast<float>(values_[static_cast<std::size_t>(ix + dims_.x() * (iy + dims_.y() * iz))]) * unit_ >
             distance_m;
    }
    const float need = distance_m - margin_;
    if (need < 0.f) return true;
    const Eigen::Vector3f d = (u.cwiseMax(0.f).cwiseMin(extent_) - u) * voxel_;
    return d.squaredNorm() > need * need;
  }

  /// clear_of() of eight points and distances, as a lane mask (bit i: point i is clear).
  PORTER_SIMD_INLINE std::uint32_t clear_of8(const v8f& px, const v8f& py, const v8f& pz, const v8f& distance_m) const {
    const v8f ux = (px - v8f_splat(origin_.x())) * v8f_splat(inv_voxel_);
    const v8f uy = (py - v8f_splat(origin_.y())) * v8f_splat(inv_voxel_);
    const v8f uz = (pz - v8f_splat(origin_.z())) * v8f_splat(inv_voxel_);
    const v8f zero = v8f_splat(0.f);
    v8i inside;
    const v8i value = grid_bytes8(values_.data(), dims_.x(), dims_.y(), dims_.z(), v8_cell(ux), v8_cell(uy), v8_cell(uz), &inside);
    const v8i clear_inside = v8_float(value) * v8f_splat(unit_) > distance_m;
    // Outside the box: the distance to the box plus the margin.
    const v8f need = distance_m - v8f_splat(margin_);
    const v8f ex = v8f_splat(extent_.x()), ey = v8f_splat(extent_.y()), ez = v8f_splat(extent_.z());
    const v8f cx = ux > zero ? ux : zero, cy = uy > zero ? uy : zero, cz = uz > zero ? uz : zero;
    const v8f s = v8f_splat(voxel_);
    const v8f dx = ((cx < ex ? cx : ex) - ux) * s, dy = ((cy < ey ? cy : ey) - uy) * s, dz = ((cz < ez ? cz : ez) - uz) * s;
    const v8i clear_outside = (need < zero) | (dx * dx + dy * dy + dz * dz > need * need);
    return lane_mask((inside & clear_inside) | (~inside & clear_outside));
  }

  std::size_t bytes() const { return values_.size(); }
  /// The largest distance the grid can prove inside its box (values are clamped at 255 units).
  float cap_m() const { return 255.f * unit_; }

 private:
  Eigen::Vector3f origin_ = Eigen::Vector3f::Zero();
  Eigen::Vector3i dims_ = Eigen::Vector3i::Zero();
  Eigen::Vector3f extent_ = Eigen::Vector3f::Zero();  ///< dims as floats
  float voxel_ = 1.f, inv_voxel_ = 1.f, margin_ = 0.f, unit_ = 1.f;
  std::vector<std::uint8_t> values_;
  std::vector<Eigen::Vector3f> centres_;
};

}  // namespace porter::planner
