#include "warm_start.hpp"

#include <cmath>

#include "porter/minco/time_map.hpp"

namespace porter::backend::detail {

bool warm_start_decision(const midend::ReferencePath& reference, int num_variables,
                         const Trajectory& traj, Eigen::VectorXd& x) {
  constexpr int kGearVars = kTrajDim + 1 + 2 * kNumArmJoints;  // [z, theta, qd, qdd]
  const int segments = static_cast<int>(reference.segments.size());
  if (segments == 0 || traj.num_pieces() != reference.num_pieces()) return false;
  int expected = 1;  // sigma
  for (const auto& seg : reference.segments) expected += (kTrajDim + 1) * seg.num_pieces() - kTrajDim;
  expected += kGearVars * (segments - 1);
  if (expected != num_variables) return false;

  x.setZero(num_variables);  // sigma = 0: the durations are carried by tau alone
  int offset = 0, piece = 0;
  for (int s = 0; s < segments; ++s) {
    const midend::ReferenceSegment& seg = reference.segments[static_cast<std::size_t>(s)];
    const int m = seg.num_pieces();
    const int q_offset = offset, tau_offset = offset + kTrajDim * (m - 1);
    offset = tau_offset + m;
    for (int i = 0; i < m; ++i) {
      const TrajectoryPiece& p = traj.piece(piece + i);
      if (p.eta != seg.eta || !(p.duration_s > 0.0)) return false;
      if (i > 0) x.segment<kTrajDim>(q_offset + kTrajDim * (i - 1)) = p.coeffs.row(0).transpose();
      x[tau_offset + i] = minco::tau_from_duration(p.duration_s);
    }
    piece += m;
  }
  piece = 0;
  for (int g = 0; g + 1 < segments; ++g) {
    const midend::ReferenceSegment& seg = reference.segments[static_cast<std::size_t>(g)];
    piece += seg.num_pieces();
    const TrajectoryPiece& last = traj.piece(piece - 1);
    const TrajVector v = piece_derivative(last.coeffs, last.duration_s, 1);
    const int o = offset + kGearVars * g;
    x.segment<kTrajDim>(o) = piece_derivative(last.coeffs, last.duration_s, 0);
    x[o + kTrajDim] = std::atan2(seg.eta * v[1], seg.eta * v[0]);
    x.segment<kNumArmJoints>(o + kTrajDim + 1) = v.tail<kNumArmJoints>();
    x.segment<kNumArmJoints>(o + kTrajDim + 1 + kNumArmJoints) =
        piece_derivative(last.coeffs, last.duration_s, 2).tail<kNumArmJoints>();
  }
  return x.allFinite();
}

}  // namespace porter::backend::detail
