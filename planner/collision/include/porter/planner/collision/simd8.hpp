#pragma once
// Eight-lane float / int vectors for the kernel queries' node and point tests, written with
// GCC/Clang vector extensions like pose4f.hpp: baseline x86-64 code runs each as two SSE2
// operations, AVX2 code (the PORTER_KERNEL_CLONES copies below, or PORTER_NATIVE_KERNELS) as one. Lanes are read and written by index
// (the compiler spills to the stack where it has no better instruction), so no intrinsics are
// needed except the sign-mask extraction, which has a portable fallback.
//
// Thread-safety: value types and pure functions.

#include <cstdint>
#include <cstring>

#include "porter/planner/collision/pose4f.hpp"

#if defined(__SSE2__)
#include <immintrin.h>
#endif

// Every function taking or returning an eight-lane vector is forced inline: the collision
// library may be compiled with -march=native (PORTER_NATIVE_KERNELS) and its callers without,
// and an out-of-line copy would be one symbol with two calling conventions. GCC's note that the
// AVX calling convention differs (-Wpsabi) is therefore moot. It is silenced for the rest of
// every file that includes this header (a push/pop here would not cover the eight-lane helpers
// defined in map_kernel.hpp, link_distance.hpp and the query sources); Porter has no other
// vector type wider than 16 bytes, which is all the note is about.
#pragma GCC diagnostic ignored "-Wpsabi"
#define PORTER_SIMD_INLINE inline __attribute__((always_inline))
#define PORTER_SIMD_LAMBDA __attribute__((always_inline))

// The query functions that walk the kernels are compiled twice on x86-64 builds for the
// baseline ISA: for x86-64-v3 (AVX2 + FMA: one instruction per eight-lane operation, lane
// multiplies, no SSE2 emulation) and for the baseline, picked once at load time by the CPU
// (GCC function multi-versioning). A -march build that already has AVX2 needs neither.
#if defined(__x86_64__) && !defined(__AVX2__) && defined(__GNUC__) && !defined(__clang__)
#define PORTER_KERNEL_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define PORTER_KERNEL_CLONES
#endif

namespace porter::planner {

typedef float v8f __attribute__((vector_size(32)));
typedef std::int32_t v8i __attribute__((vector_size(32)));
/// For unsigned lane comparisons (range checks in one compare): v8u(x) reinterprets a v8i.
typedef std::uint32_t v8u __attribute__((vector_size(32)));

// Splats are shuffles of lane 0: GCC 12 builds v8f{x, x, ..., x} in the AVX2 clones from four
// 8-byte stores read back as one 32-byte load (a missed store forwarding each time), where the
// shuffle becomes one vbroadcastss (shufps in the baseline).
PORTER_SIMD_INLINE v8f v8f_splat(float x) { return __builtin_shuffle(v8f{x}, v8i{}); }
PORTER_SIMD_INLINE v8i v8i_splat(std::int32_t x) { return __builtin_shuffle(v8i{x}, v8i{}); }

/// Eight floats from memory (any alignment).
PORTER_SIMD_INLINE v8f v8f_load(const float* p) {
  v8f v;
  std::memcpy(&v, p, sizeof(v));
  return v;
}

/// Eight 4-lane rows r[i] = (x_i, y_i, z_i, w_i) as four 8-lane columns, in registers. Filling
/// a float[8] lane by lane and loading it as one vector would miss store forwarding.
PORTER_SIMD_INLINE void transpose8x4(const v4f* r, v8f* x, v8f* y, v8f* z, v8f* w) {
  v4f c[2][4];
  for (int h = 0; h < 2; ++h) {
    const v4f* q = r + 4 * h;
    const v4f xy01 = __builtin_shuffle(q[0], q[1], v4i{0, 4, 1, 5});  // x0 x1 y0 y1
    const v4f xy23 = __builtin_shuffle(q[2], q[3], v4i{0, 4, 1, 5});
    const v4f zw01 = __builtin_shuffle(q[0], q[1], v4i{2, 6, 3, 7});  // z0 z1 w0 w1
    const v4f zw23 = __builtin_shuffle(q[2], q[3], v4i{2, 6, 3, 7});
    c[h][0] = __builtin_shuffle(xy01, xy23, v4i{0, 1, 4, 5});
    c[h][1] = __builtin_shuffle(xy01, xy23, v4i{2, 3, 6, 7});
    c[h][2] = __builtin_shuffle(zw01, zw23, v4i{0, 1, 4, 5});
    c[h][3] = __builtin_shuffle(zw01, zw23, v4i{2, 3, 6, 7});
  }
  *x = __builtin_shufflevector(c[0][0], c[1][0], 0, 1, 2, 3, 4, 5, 6, 7);
  *y = __builtin_shufflevector(c[0][1], c[1][1], 0, 1, 2, 3, 4, 5, 6, 7);
  *z = __builtin_shufflevector(c[0][2], c[1][2], 0, 1, 2, 3, 4, 5, 6, 7);
  *w = __builtin_shufflevector(c[0][3], c[1][3], 0, 1, 2, 3, 4, 5, 6, 7);
}

/// Bit i set when lane i of a comparison result (0 or -1 per lane) is -1.
PORTER_SIMD_INLINE std::uint32_t lane_mask(const v8i& m) {
#if defined(__AVX__)
  return static_cast<std::uint32_t>(_mm256_movemask_ps(reinterpret_cast<__m256>(m)));
#elif defined(__SSE2__)
  __m128i lo, hi;
  std::memcpy(&lo, &m, 16);
  std::memcpy(&hi, reinterpret_cast<const char*>(&m) + 16, 16);
  return static_cast<std::uint32_t>(_mm_movemask_ps(_mm_castsi128_ps(lo)) |
                                    (_mm_movemask_ps(_mm_castsi128_ps(hi)) << 4));
#else
  std::uint32_t out = 0;
  for (int i = 0; i < 8; ++i) out |= static_cast<std::uint32_t>(m[i] & 1) << i;
  return out;
#endif
}

/// Lane-wise truncation towards zero (static_cast<int> per lane; out-of-range lanes are
/// unspecified, as for the scalar cast: callers range-check before using them).
PORTER_SIMD_INLINE v8i v8_trunc(const v8f& x) { return __builtin_convertvector(x, v8i); }
PORTER_SIMD_INLINE v8f v8_float(const v8i& x) { return __builtin_convertvector(x, v8f); }

/// Cells of eight points in a grid of cells of edge 1 starting at 0 (u = point / cell edge,
/// grid-relative): floor(u) per lane, exact for u >= -1 (lanes below that are outside anyway).
PORTER_SIMD_INLINE v8i v8_cell(const v8f& u) { return v8_trunc(u + v8f_splat(1.f)) - 1; }

/// values[x + nx (y + ny z)] of a byte grid of nx x ny x nz cells at eight cells (x, y, z), 0 in
/// the lanes outside the grid; *inside is -1 in the lanes inside, 0 elsewhere.
PORTER_SIMD_INLINE v8i grid_bytes8(const std::uint8_t* values, int nx, int ny, int nz, const v8i& x, const v8i& y,
                                   const v8i& z, v8i* inside) {
  const v8i Nx = v8i_splat(nx), Ny = v8i_splat(ny), Nz = v8i_splat(nz);
  *inside = (x >= 0) & (x < Nx) & (y >= 0) & (y < Ny) & (z >= 0) & (z < Nz);
  const v8i index = (x + Nx * (y + Ny * z)) & *inside;  // outside lanes read cell 0, then drop it
  v8i value;
  for (int i = 0; i < 8; ++i) value[i] = values[static_cast<std::uint32_t>(index[i])];
  return value & *inside;
}

/// Eight rigid transforms, one per lane: lane i of every entry belongs to transform i. Two uses:
/// the poses of eight configurations checked together (KernelCollisionChecker::check_batch),
/// and one pose in every lane (splat()) applied to eight points of a tree node or block. The
/// operations that build a pose write into an output (which must not alias an input) rather
/// than return one: GCC copies a returned 384-byte struct into an array element with a loop.
struct PoseLanes {
  v8f r[3][3];  ///< rotation, r[row][column]
  v8f t[3];     ///< translation

  /// The same transform in every lane.
  PORTER_SIMD_INLINE void set_all(const Pose4f& T) {
    const v4f* cols[3] = {&T.c0, &T.c1, &T.c2};
#pragma GCC unroll 3
    for (int i = 0; i < 3; ++i) {
#pragma GCC unroll 3
      for (int j = 0; j < 3; ++j) r[i][j] = v8f_splat((*cols[j])[i]);
      t[i] = v8f_splat(T.t[i]);
    }
  }
  /// T in every lane.
  PORTER_SIMD_INLINE static PoseLanes splat(const Pose4f& T) {
    PoseLanes p;
    p.set_all(T);
    return p;
  }
  /// Lane i as a Pose4f.
  PORTER_SIMD_INLINE Pose4f lane(int i) const {
    Pose4f p;
    p.c0 = v4f{r[0][0][i], r[1][0][i], r[2][0][i], 0.f};
    p.c1 = v4f{r[0][1][i], r[1][1][i], r[2][1][i], 0.f};
    p.c2 = v4f{r[0][2][i], r[1][2][i], r[2][2][i], 0.f};
    p.t = v4f{t[0][i], t[1][i], t[2][i], 0.f};
    return p;
  }
  PORTER_SIMD_INLINE void set_lane(int i, const Pose4f& T) {
    const v4f* cols[3] = {&T.c0, &T.c1, &T.c2};
#pragma GCC unroll 3
    for (int a = 0; a < 3; ++a) {
#pragma GCC unroll 3
      for (int b = 0; b < 3; ++b) r[a][b][i] = (*cols[b])[a];
      t[a][i] = T.t[a];
    }
  }
  /// R p + t per lane; the outputs may alias the inputs.
  PORTER_SIMD_INLINE void apply(const v8f& x, const v8f& y, const v8f& z, v8f* ox, v8f* oy, v8f* oz) const {
    const v8f X = r[0][0] * x + r[0][1] * y + r[0][2] * z + t[0];
    const v8f Y = r[1][0] * x + r[1][1] * y + r[1][2] * z + t[1];
    *oz = r[2][0] * x + r[2][1] * y + r[2][2] * z + t[2];
    *ox = X;
    *oy = Y;
  }
  /// R^T (p - t) per lane (the inverse transform); the outputs may alias the inputs.
  PORTER_SIMD_INLINE void apply_inverse(const v8f& x, const v8f& y, const v8f& z, v8f* ox, v8f* oy, v8f* oz) const {
    const v8f dx = x - t[0], dy = y - t[1], dz = z - t[2];
    *ox = r[0][0] * dx + r[1][0] * dy + r[2][0] * dz;
    *oy = r[0][1] * dx + r[1][1] * dy + r[2][1] * dz;
    *oz = r[0][2] * dx + r[1][2] * dy + r[2][2] * dz;
  }
  /// out = a * b, lane by lane.
  PORTER_SIMD_INLINE static void compose(const PoseLanes& a, const PoseLanes& b, PoseLanes& out) {
#pragma GCC unroll 3
    for (int i = 0; i < 3; ++i) {
#pragma GCC unroll 3
      for (int j = 0; j < 3; ++j) out.r[i][j] = a.r[i][0] * b.r[0][j] + a.r[i][1] * b.r[1][j] + a.r[i][2] * b.r[2][j];
      out.t[i] = a.r[i][0] * b.t[0] + a.r[i][1] * b.t[1] + a.r[i][2] * b.t[2] + a.t[i];
    }
  }
  /// out = a * Rz, Rz the rotation about a's own z axis by (c, s) per lane (columns 0 and 1 mix,
  /// as Pose4f::rotated_z).
  PORTER_SIMD_INLINE static void rotated_z(const PoseLanes& a, const v8f& c, const v8f& s, PoseLanes& out) {
#pragma GCC unroll 3
    for (int i = 0; i < 3; ++i) {
      out.r[i][0] = a.r[i][0] * c + a.r[i][1] * s;
      out.r[i][1] = a.r[i][1] * c - a.r[i][0] * s;
      out.r[i][2] = a.r[i][2];
      out.t[i] = a.t[i];
    }
  }
};

}  // namespace porter::planner
