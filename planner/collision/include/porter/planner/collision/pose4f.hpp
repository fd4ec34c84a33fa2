#pragma once
// A rigid transform in float32 with 4-lane columns, for the kernel queries' hot loops, written
// with GCC/Clang vector extensions (portable to SSE2 and NEON; no intrinsics, no -march flags
// needed). The eight-lane counterparts are in simd8.hpp.
//
// Precision: float32 (relative 6e-8); used on robot-sized coordinates (base frame, or voxel
// coordinates relative to the map's corner), where rounding stays below 1e-5 m.
// Thread-safety: a value type.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>

namespace porter::planner {

typedef float v4f __attribute__((vector_size(16)));

typedef std::int32_t v4i __attribute__((vector_size(16)));

/// A shuffle of lane 0 (one broadcast), not v4f{x, x, x, x}: see v8f_splat in simd8.hpp.
inline v4f v4f_splat(float x) { return __builtin_shuffle(v4f{x}, v4i{}); }

struct Pose4f {
  v4f c0, c1, c2;  ///< rotation columns (lane 3 unused)
  v4f t;           ///< translation

  /// Uninitialized (hot loops fill whole arrays of poses); use identity() for the identity.
  Pose4f() = default;
  static Pose4f identity() {
    Pose4f p;
    p.c0 = v4f{1.f, 0.f, 0.f, 0.f};
    p.c1 = v4f{0.f, 1.f, 0.f, 0.f};
    p.c2 = v4f{0.f, 0.f, 1.f, 0.f};
    p.t = v4f{0.f, 0.f, 0.f, 0.f};
    return p;
  }
  explicit Pose4f(const Eigen::Isometry3d& T) {
    const Eigen::Matrix3d& R = T.linear();
    c0 = v4f{float(R(0, 0)), float(R(1, 0)), float(R(2, 0)), 0.f};
    c1 = v4f{float(R(0, 1)), float(R(1, 1)), float(R(2, 1)), 0.f};
    c2 = v4f{float(R(0, 2)), float(R(1, 2)), float(R(2, 2)), 0.f};
    t = v4f{float(T.translation().x()), float(T.translation().y()), float(T.translation().z()), 0.f};
  }
  Eigen::Isometry3d isometry() const {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    for (int r = 0; r < 3; ++r) {
      T.linear()(r, 0) = c0[r];
      T.linear()(r, 1) = c1[r];
      T.linear()(r, 2) = c2[r];
      T.translation()[r] = t[r];
    }
    return T;
  }
  /// R v (rotation only).
  v4f rotate(v4f v) const { return c0 * v4f_splat(v[0]) + c1 * v4f_splat(v[1]) + c2 * v4f_splat(v[2]); }
  /// R p + t.
  v4f apply(float x, float y, float z) const { return c0 * v4f_splat(x) + c1 * v4f_splat(y) + c2 * v4f_splat(z) + t; }
  Pose4f operator*(const Pose4f& o) const {
    Pose4f r;
    r.c0 = rotate(o.c0);
    r.c1 = rotate(o.c1);
    r.c2 = rotate(o.c2);
    r.t = rotate(o.t) + t;
    return r;
  }
  Pose4f inverse() const {
    Pose4f r;
    r.c0 = v4f{c0[0], c1[0], c2[0], 0.f};
    r.c1 = v4f{c0[1], c1[1], c2[1], 0.f};
    r.c2 = v4f{c0[2], c1[2], c2[2], 0.f};
    const v4f nt = r.rotate(t);
    r.t = v4f{-nt[0], -nt[1], -nt[2], 0.f};
    return r;
  }
  /// Rotation about the frame's own z axis by (c, s): columns 0 and 1 mix.
  Pose4f rotated_z(float c, float s) const {
    Pose4f r = *this;
    r.c0 = c0 * v4f_splat(c) + c1 * v4f_splat(s);
    r.c1 = c1 * v4f_splat(c) - c0 * v4f_splat(s);
    return r;
  }
};

}  // namespace porter::planner
