#pragma once
// Shortest Reeds–Shepp curves for the base (forward and reverse arcs of a fixed turning radius
// and straight lines), computed with OMPL's ReedsSheppStateSpace and sampled here.
//
// Frames and units: base poses in the world frame W (m, rad). Lengths are arc lengths in metres,
// signed per segment: > 0 forward (eta = +1), < 0 reverse (eta = -1).
// Thread-safety: a ReedsShepp object keeps scratch OMPL states, so one object per thread.
// Failure: none; poses with non-finite values give a path of infinite length.

#include <array>
#include <memory>
#include <vector>

#include "porter/core/types.hpp"

namespace porter::frontend {

/// One primitive of a Reeds–Shepp curve.
struct RsSegment {
  enum class Kind { kLeft, kStraight, kRight };
  Kind kind = Kind::kStraight;
  double length_m = 0.0;  ///< signed: > 0 forward, < 0 reverse
};

struct RsPath {
  std::array<RsSegment, 5> segments{};
  int num_segments = 0;
  double radius_m = 1.0;
  double length_m = 0.0;  ///< sum of |segment lengths|
  /// Number of direction changes (cusps) along the curve.
  int cusps() const;
};

/// A pose on a curve and the driving direction of the motion that reaches it.
struct BaseSample {
  BasePose pose;
  int eta = 1;
};

/// Pose reached after driving the arc-length `length_m` (signed) on a circle of curvature
/// `curvature_1pm` (> 0 turns left) from `from` (exact, closed form).
BasePose drive_arc(const BasePose& from, double curvature_1pm, double length_m);

class ReedsShepp {
 public:
  explicit ReedsShepp(double turning_radius_m);
  ~ReedsShepp();
  ReedsShepp(const ReedsShepp&) = delete;
  ReedsShepp& operator=(const ReedsShepp&) = delete;

  double turning_radius_m() const { return radius_m_; }

  /// The shortest curve from `from` to `to`.
  RsPath shortest(const BasePose& from, const BasePose& to) const;
  /// Its length in metres (the obstacle-free heuristic).
  double distance(const BasePose& from, const BasePose& to) const;

 private:
  double radius_m_;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Pose at arc length s in [0, path.length_m] along `path` from `from`; *eta (optional) gets the
/// direction of the segment containing s.
BasePose rs_pose_at(const BasePose& from, const RsPath& path, double s_m, int* eta = nullptr);

/// Samples the curve so that consecutive samples are at most `max_step_m` apart in arc length
/// and every segment end (in particular every cusp) is a sample. The first sample is `from`
/// (with the direction of the first segment), the last is the curve's end. Appends to *out.
void sample_rs_path(const BasePose& from, const RsPath& path, double max_step_m,
                    std::vector<BaseSample>* out);

}  // namespace porter::frontend
