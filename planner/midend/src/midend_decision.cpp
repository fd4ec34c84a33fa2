// MidendProblem::decision_from_trajectory: the inverse of pieces() for a trajectory of the same
// reference path (the layout is documented in midend_problem.hpp).
#include <cmath>

#include "porter/midend/midend_problem.hpp"
#include "porter/minco/time_map.hpp"

namespace porter::midend {

bool MidendProblem::decision_from_trajectory(const Trajectory& traj, Eigen::VectorXd& x, bool exact) {
  const int segments = static_cast<int>(reference_.segments.size());
  if (segments == 0 || traj.num_pieces() != reference_.num_pieces()) return false;
  x.setZero(num_variables_);  // sigma = 0: the durations are carried by tau alone
  int piece = 0;
  for (int s = 0; s < segments; ++s) {
    const ReferenceSegment& seg = reference_.segments[static_cast<std::size_t>(s)];
    const SegmentLayout& l = segment_layout_[static_cast<std::size_t>(s)];
    for (int i = 0; i < l.pieces; ++i) {
      const TrajectoryPiece& p = traj.piece(piece + i);
      if (p.eta != seg.eta || !(p.duration_s > 0.0)) return false;
      if (i > 0) x.segment<kTrajDim>(l.q_offset + kTrajDim * (i - 1)) = p.coeffs.row(0).transpose();
      x[l.tau_offset + i] = minco::tau_from_duration(p.duration_s);
    }
    piece += l.pieces;
    if (s + 1 < segments) {
      const TrajectoryPiece& last = traj.piece(piece - 1);
      const TrajVector v = piece_derivative(last.coeffs, last.duration_s, 1);
      const int o = gear_layout_[static_cast<std::size_t>(s)].offset;
      x.segment<kTrajDim>(o) = piece_derivative(last.coeffs, last.duration_s, 0);
      x[o + kTrajDim] = std::atan2(seg.eta * v[1], seg.eta * v[0]);
      x.segment<kNumArmJoints>(o + kTrajDim + 1) = v.tail<kNumArmJoints>();
      x.segment<kNumArmJoints>(o + kTrajDim + 1 + kNumArmJoints) =
          piece_derivative(last.coeffs, last.duration_s, 2).tail<kNumArmJoints>();
    }
  }
  if (!x.allFinite()) return false;
  // The map back must give the same pieces.
  const std::vector<TrajectoryPiece> back = pieces(x.data());
  if (static_cast<int>(back.size()) != traj.num_pieces()) return false;
  if (!exact) return true;
  for (int i = 0; i < traj.num_pieces(); ++i) {
    const TrajectoryPiece& a = back[static_cast<std::size_t>(i)];
    const TrajectoryPiece& b = traj.piece(i);
    if (a.eta != b.eta || std::abs(a.duration_s - b.duration_s) > 1e-6 * b.duration_s ||
        !((a.coeffs - b.coeffs).norm() <= 1e-6 * (1.0 + b.coeffs.norm())))
      return false;
  }
  return true;
}

}  // namespace porter::midend
