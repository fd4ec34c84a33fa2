#pragma once
// Chain geometry the kernel checker needs besides the kernels themselves:
//   - ChainRadii: configuration-independent bounds on how far link points lie from joint
//     origins, which set the joint sample counts, the map padding and the motion-check step;
//   - KernelKinematics: forward kinematics in the base frame B, float32 with 4-lane columns and a
//     table-based sin/cos, several times faster than porter::arm_forward_kinematics.
//
// Frames: B base, J_j the frame a kernel of link j is voxelized in (parent frame after joint j's
// origin, before its rotation; J_7 = L_7 = EE), L_j the link frame. Units: metres, radians.
// Thread-safety: immutable after construction; concurrent reads are safe.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "porter/core/robot_model.hpp"
#include "porter/core/types.hpp"
#include "porter/planner/collision/pose4f.hpp"
#include "porter/planner/collision/simd8.hpp"

namespace porter::planner {

struct ChainRadii {
  /// r_j: largest distance of link j's geometry from its frame origin (base origin for 0,
  /// joint j's origin for 1..6, EE origin for 7). Bounds the distance from joint j's axis too.
  std::array<double, kNumLinks> link_radius_m{};
  /// rho_j (index j-1): largest distance of any point of links j..7 from joint j's origin, over
  /// all configurations (chain of joint offsets plus link radii).
  std::array<double, kNumArmJoints> sweep_radius_m{};
  /// Largest distance of any robot point from the base origin, over all configurations.
  double reach_m = 0.0;
};

ChainRadii compute_chain_radii(const RobotModel& model);

namespace sincos_detail {
constexpr double kTwoOverPi = 0.63661977236758134308;
constexpr double kPiOver2Hi = 1.5707963267948966192;
constexpr double kRound = 6755399441055744.0;  // 1.5 * 2^52: adding it rounds to an integer
/// Cephes sinf/cosf minimax polynomials on [-pi/4, pi/4], for float or eight-lane r and r2 = r^2
/// (scalar coefficients broadcast in the vector case).
template <class F>
PORTER_SIMD_INLINE F sin_poly(const F& r, const F& r2) {
  return r + r * r2 * (-1.6666654611e-1f + r2 * (8.3321608736e-3f + r2 * -1.9515295891e-4f));
}
template <class F>
PORTER_SIMD_INLINE F cos_poly(const F& r2) {
  return 1.f - 0.5f * r2 + r2 * r2 * (4.166664568298827e-2f + r2 * (-1.388731625493765e-3f + r2 * 2.443315711809948e-5f));
}
}  // namespace sincos_detail

/// sin and cos of x (finite, |x| < 1e6) in float32: exact quadrant reduction in double, then
/// the Cephes sinf/cosf minimax polynomials on [-pi/4, pi/4] (error < 2e-7). Inline, no libm.
inline void fast_sincos(double x, float* s, float* c) {
  using namespace sincos_detail;
  const double k = (x * kTwoOverPi + kRound) - kRound;
  const auto r = static_cast<float>(x - k * kPiOver2Hi);
  const float r2 = r * r;
  const float sr = sin_poly(r, r2), cr = cos_poly(r2);
  // Quadrant q: swap sin and cos for odd q, negate sin for q = 2, 3 and cos for q = 1, 2, with
  // bit masks rather than branches (the quadrant of a random joint angle is unpredictable).
  const auto q = static_cast<std::uint32_t>(static_cast<long long>(k) & 3);
  std::uint32_t sb, cb;
  std::memcpy(&sb, &sr, 4);
  std::memcpy(&cb, &cr, 4);
  const std::uint32_t swap = 0u - (q & 1u);
  const std::uint32_t sq = (sb & ~swap) | (cb & swap), cq = (cb & ~swap) | (sb & swap);
  const std::uint32_t so = sq ^ ((q & 2u) << 30), co = cq ^ (((q + 1u) & 2u) << 30);
  std::memcpy(s, &so, 4);
  std::memcpy(c, &co, 4);
}

typedef double v4d __attribute__((vector_size(32)));

/// fast_sincos of eight angles at once, lanes 0-3 from x_lo and 4-7 from x_hi (same reduction,
/// polynomials and quadrant masks), for the joint angles of one forward-kinematics pass. The
/// halves are joined in registers: through memory, two 16-byte stores read back as one 32-byte
/// load would miss store forwarding.
PORTER_SIMD_INLINE void fast_sincos8(const v4d& x_lo, const v4d& x_hi, v8f* s, v8f* c) {
  using namespace sincos_detail;
  const v4d k_lo = (x_lo * kTwoOverPi + kRound) - kRound, k_hi = (x_hi * kTwoOverPi + kRound) - kRound;
  const v4f r_lo = __builtin_convertvector(x_lo - k_lo * kPiOver2Hi, v4f);
  const v4f r_hi = __builtin_convertvector(x_hi - k_hi * kPiOver2Hi, v4f);
  const v4i q_lo = __builtin_convertvector(k_lo, v4i), q_hi = __builtin_convertvector(k_hi, v4i);
  const v8f r = __builtin_shufflevector(r_lo, r_hi, 0, 1, 2, 3, 4, 5, 6, 7);
  const v8i q = __builtin_shufflevector(q_lo, q_hi, 0, 1, 2, 3, 4, 5, 6, 7);
  const v8f r2 = r * r;
  const v8f sr = sin_poly(r, r2), cr = cos_poly(r2);
  const v8i swap = -(q & 1), sb = (v8i)sr, cb = (v8i)cr;  // vector casts reinterpret the bits
  const v8i sq = (sb & ~swap) | (cb & swap), cq = (cb & ~swap) | (sb & swap);
  *s = (v8f)(sq ^ ((q & 2) << 30));
  *c = (v8f)(cq ^ (((q + 1) & 2) << 30));
}

/// Link poses in the base frame B (float32): the kernel frames T_B_J (index 1..7; [0] = B)
/// and the link frames T_B_L (index 0..7; [0] = B).
struct ArmPoses {
  std::array<Pose4f, kNumLinks> T_B_J;
  std::array<Pose4f, kNumLinks> T_B_L;
};

/// ArmPoses of eight configurations, one per lane (PoseLanes): the poses of a batch.
struct ArmPoseLanes {
  std::array<PoseLanes, kNumLinks> T_B_J;
  std::array<PoseLanes, kNumLinks> T_B_L;
  /// Configuration i's poses.
  ArmPoses lane(int i) const {
    ArmPoses p;
    for (std::size_t k = 0; k < static_cast<std::size_t>(kNumLinks); ++k) {
      p.T_B_J[k] = T_B_J[k].lane(i);
      p.T_B_L[k] = T_B_L[k].lane(i);
    }
    return p;
  }
};

class KernelKinematics {
 public:
  KernelKinematics() = default;
  explicit KernelKinematics(const RobotModel& model);
  /// Same result as porter::arm_forward_kinematics to float rounding (< 1e-6 m for arm-sized
  /// chains), no heap allocation.
  void compute(const JointVector& q_rad, ArmPoses& poses) const;
  /// compute() of eight configurations at once, configuration i in lane i (same operations per
  /// lane; results agree with compute() to float rounding).
  void compute_lanes(const std::array<const JointVector*, 8>& q_rad, ArmPoseLanes& poses) const;

 private:
  /// A fixed transform, with the shape of its rotation recorded so that composing with it costs
  /// only what it must (URDF joint origins are mostly axis permutations or pure offsets).
  struct FixedTransform {
    enum class Kind { kTranslation, kPermutation, kGeneral } kind = Kind::kGeneral;
    Pose4f T;
    std::array<int, 3> column{};  ///< kPermutation: column j of R is sign[j] * e_column[j]
    std::array<float, 3> sign{};
    explicit FixedTransform(const Eigen::Isometry3d& T = Eigen::Isometry3d::Identity());
    /// parent * T
    Pose4f after(const Pose4f& parent) const {  // inline: a 64-byte result through memory stalls
      if (kind == Kind::kGeneral) return parent * T;
      Pose4f r;
      r.t = parent.rotate(T.t) + parent.t;
      if (kind == Kind::kTranslation) {
        r.c0 = parent.c0;
        r.c1 = parent.c1;
        r.c2 = parent.c2;
        return r;
      }
      const v4f* cols[3] = {&parent.c0, &parent.c1, &parent.c2};
      r.c0 = *cols[column[0]] * v4f_splat(sign[0]);
      r.c1 = *cols[column[1]] * v4f_splat(sign[1]);
      r.c2 = *cols[column[2]] * v4f_splat(sign[2]);
      return r;
    }
    /// out = parent * T, lane by lane (out must not alias parent).
    PORTER_SIMD_INLINE void after(const PoseLanes& parent, PoseLanes& out) const {
      if (kind == Kind::kGeneral) {
        const v4f* cols[3] = {&T.c0, &T.c1, &T.c2};
#pragma GCC unroll 3
        for (int i = 0; i < 3; ++i) {
#pragma GCC unroll 3
          for (int j = 0; j < 3; ++j)
            out.r[i][j] = parent.r[i][0] * v8f_splat((*cols[j])[0]) + parent.r[i][1] * v8f_splat((*cols[j])[1]) +
                          parent.r[i][2] * v8f_splat((*cols[j])[2]);
          out.t[i] = parent.r[i][0] * v8f_splat(T.t[0]) + parent.r[i][1] * v8f_splat(T.t[1]) +
                     parent.r[i][2] * v8f_splat(T.t[2]) + parent.t[i];
        }
        return;
      }
#pragma GCC unroll 3
      for (int i = 0; i < 3; ++i) {
        out.t[i] = parent.r[i][0] * v8f_splat(T.t[0]) + parent.r[i][1] * v8f_splat(T.t[1]) +
                   parent.r[i][2] * v8f_splat(T.t[2]) + parent.t[i];
#pragma GCC unroll 3
        for (int j = 0; j < 3; ++j) {
          if (kind == Kind::kTranslation) {
            out.r[i][j] = parent.r[i][j];
          } else {
            const v8f& col = parent.r[i][column[static_cast<std::size_t>(j)]];
            out.r[i][j] = sign[static_cast<std::size_t>(j)] > 0.f ? col : -col;
          }
        }
      }
    }
  };

  std::array<FixedTransform, kNumArmJoints> T_parent_joint_;
  std::array<Eigen::Matrix3d, kNumArmJoints> K_, K2_;  ///< [axis]x and its square (Rodrigues)
  std::array<int, kNumArmJoints> z_axis_{};            ///< +1 / -1 when the axis is +z / -z, else 0
  FixedTransform T_L6_EE_;
};

}  // namespace porter::planner
