#include "porter/backend/backend_problem.hpp"

#include <cmath>
#include <limits>

#include "porter/minco/time_map.hpp"

namespace porter::backend {
namespace {

constexpr int kGearVars = kTrajDim + 1 + 2 * kNumArmJoints;  // [z, theta, qd, qdd]

}  // namespace

BackendProblem::BackendProblem(midend::ReferencePath reference, const midend::MidendLimits& limits,
                               const midend::MidendSettings& settings, SafetyTerm& safety)
    : reference_(reference), limits_(limits), midend_(std::move(reference), limits, settings), safety_(&safety) {
  // The decision-vector layout of midend_problem.hpp.
  const int segments = static_cast<int>(reference_.segments.size());
  int offset = 0, piece = 0;
  for (int s = 0; s < segments; ++s) {
    const int m = reference_.segments[static_cast<std::size_t>(s)].num_pieces();
    first_piece_.push_back(piece);
    piece += m;
    q_offset_.push_back(offset);
    offset += kTrajDim * (m - 1);
    tau_offset_.push_back(offset);
    offset += m;
  }
  first_piece_.push_back(piece);
  for (int g = 0; g + 1 < segments; ++g) {
    gear_offset_.push_back(offset);
    offset += kGearVars;
  }
}

bool BackendProblem::decision_from_trajectory(const Trajectory& traj, Eigen::VectorXd& x) const {
  if (traj.num_pieces() != midend_.num_pieces()) return false;
  x.setZero(midend_.num_variables());
  const int segments = static_cast<int>(reference_.segments.size());
  for (int s = 0; s < segments; ++s) {
    const int eta = reference_.segments[static_cast<std::size_t>(s)].eta;
    const int p0 = first_piece_[static_cast<std::size_t>(s)], p1 = first_piece_[static_cast<std::size_t>(s) + 1];
    for (int i = p0; i < p1; ++i) {
      const TrajectoryPiece& piece = traj.piece(i);
      if (piece.eta != eta) return false;
      if (i > p0) x.segment<kTrajDim>(q_offset_[static_cast<std::size_t>(s)] + kTrajDim * (i - p0 - 1)) = piece.coeffs.row(0).transpose();
      x[tau_offset_[static_cast<std::size_t>(s)] + (i - p0)] = minco::tau_from_duration(piece.duration_s);
    }
    if (s + 1 < segments) {
      const TrajectoryPiece& last = traj.piece(p1 - 1);
      const TrajVector z = piece_derivative(last.coeffs, last.duration_s, 0);
      const TrajVector v = piece_derivative(last.coeffs, last.duration_s, 1);
      const TrajVector a = piece_derivative(last.coeffs, last.duration_s, 2);
      const int o = gear_offset_[static_cast<std::size_t>(s)];
      x.segment<kTrajDim>(o) = z;
      x[o + kTrajDim] = std::atan2(eta * v[1], eta * v[0]);
      x.segment<kNumArmJoints>(o + kTrajDim + 1) = v.tail<kNumArmJoints>();
      x.segment<kNumArmJoints>(o + kTrajDim + 1 + kNumArmJoints) = a.tail<kNumArmJoints>();
    }
  }
  return x.allFinite();
}

std::optional<Trajectory> BackendProblem::trajectory(const double* x) {
  std::vector<TrajectoryPiece> pieces = midend_.pieces(x);
  if (pieces.empty()) return std::nullopt;
  TrajectoryResult r = Trajectory::create(std::move(pieces), midend_.start_yaw_rad());
  return std::move(r.trajectory);
}

double BackendProblem::evaluate(const double* x, double* grad, BackendCost* cost) {
  BackendCost local;
  BackendCost& c = cost ? *cost : local;
  c = BackendCost{};
  const double f_mid = midend_.evaluate(x, grad, &c.midend);
  const auto fail = [&]() {
    if (grad) std::fill(grad, grad + num_variables(), 0.0);
    return std::numeric_limits<double>::infinity();
  };
  if (!std::isfinite(f_mid)) return fail();
  const std::optional<Trajectory> traj = trajectory(x);
  if (!traj) return fail();
  tgrad_.reset(traj->num_pieces());
  c.safety = safety_->evaluate(*traj, tgrad_, &c.safety_stats);
  if (!std::isfinite(c.safety)) return fail();
  if (grad && !add_safety_gradient(*traj, tgrad_, x, grad)) return fail();
  return f_mid + c.safety;
}

bool BackendProblem::add_safety_gradient(const Trajectory& traj, const TrajectoryGradient& tgrad,
                                         const double* x, double* grad) {
  const int segments = static_cast<int>(reference_.segments.size());
  const double vns = limits_.nonsingular_speed_mps;
  for (int s = 0; s < segments; ++s) {
    const auto su = static_cast<std::size_t>(s);
    const int p0 = first_piece_[su], m = first_piece_[su + 1] - p0;
    const int eta = reference_.segments[su].eta;
    // Rebuild the segment's MINCO from its pieces (same boundary data -> same coefficients).
    Minco::BoundaryState head, tail;
    const TrajectoryPiece& first = traj.piece(p0);
    const TrajectoryPiece& last = traj.piece(p0 + m - 1);
    for (int k = 0; k < 3; ++k) {
      head.col(k) = piece_derivative(first.coeffs, 0.0, k);
      tail.col(k) = piece_derivative(last.coeffs, last.duration_s, k);
    }
    Minco::Waypoints waypoints(kTrajDim, m - 1);
    Eigen::VectorXd durations(m);
    partial_c_.resize(minco::kPieceCoeffs * m, kTrajDim);
    partial_t_.resize(m);
    for (int i = 0; i < m; ++i) {
      const TrajectoryPiece& piece = traj.piece(p0 + i);
      if (i > 0) waypoints.col(i - 1) = piece.coeffs.row(0).transpose();
      durations[i] = piece.duration_s;
      partial_c_.middleRows<minco::kPieceCoeffs>(minco::kPieceCoeffs * i) = tgrad.coeffs(p0 + i);
      partial_t_[i] = tgrad.duration(p0 + i);
    }
    if (!minco_.generate(head, tail, waypoints, durations)) return false;
    Minco::BoundaryState gh, gt;
    minco_.propagate_gradient(partial_c_, partial_t_, grad_q_, grad_t_, gh, gt);
    for (int i = 0; i + 1 < m; ++i) {
      for (int d = 0; d < kTrajDim; ++d) grad[q_offset_[su] + kTrajDim * i + d] += grad_q_(d, i);
    }
    for (int i = 0; i < m; ++i) {
      const int k = tau_offset_[su] + i;
      grad[k] += grad_t_[i] * minco::duration_derivative(x[k]);
    }
    // Gear states: head of segment s (> 0) is gear s-1, tail of segment s (< last) is gear s.
    auto add_gear = [&](int g, const Minco::BoundaryState& gs) {
      const int o = gear_offset_[static_cast<std::size_t>(g)];
      const double theta = x[o + kTrajDim];
      for (int d = 0; d < kTrajDim; ++d) grad[o + d] += gs(d, 0);
      grad[o + kTrajDim] += eta * vns * (-gs(0, 1) * std::sin(theta) + gs(1, 1) * std::cos(theta));
      for (int d = 0; d < kNumArmJoints; ++d) {
        grad[o + kTrajDim + 1 + d] += gs(2 + d, 1);
        grad[o + kTrajDim + 1 + kNumArmJoints + d] += gs(2 + d, 2);
      }
    };
    if (s > 0) add_gear(s - 1, gh);
    if (s + 1 < segments) add_gear(s, gt);
  }
  for (int k = 0; k < num_variables(); ++k) {
    if (!std::isfinite(grad[k])) return false;
  }
  return true;
}

}  // namespace porter::backend
