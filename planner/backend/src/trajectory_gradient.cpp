#include "porter/backend/trajectory_gradient.hpp"

#include "porter/minco/polynomial.hpp"

namespace porter::backend {

void TrajectoryGradient::reset(int num_pieces) {
  const auto n = static_cast<std::size_t>(num_pieces);
  coeffs_.resize(n);
  for (auto& c : coeffs_) c.setZero();
  durations_.assign(n, 0.0);
  shift_.assign(n, 0.0);
}

void TrajectoryGradient::add_local(int piece, double tau_s, const TrajVector& d_z, int order,
                                   const TrajVector& d_zk, double weight) {
  PieceCoeffs& c = coeffs_[static_cast<std::size_t>(piece)];
  c.noalias() += (weight * minco::basis(tau_s, 0)) * d_z.transpose();
  c.noalias() += (weight * minco::basis(tau_s, order)) * d_zk.transpose();
}

void TrajectoryGradient::add(const Trajectory& traj, const PointSensitivity& s, double weight) {
  add_local(s.piece, s.tau_s, s.d_z, s.heading_order, s.d_heading, weight);
  if (s.stationary) return;
  const PieceCoeffs& c = traj.piece(s.piece).coeffs;
  const TrajVector zdot = piece_derivative(c, s.tau_s, 1);
  const TrajVector zk1 = piece_derivative(c, s.tau_s, s.heading_order + 1);
  const double rate = weight * (s.d_z.dot(zdot) + s.d_heading.dot(zk1));
  if (s.at_end) {
    durations_[static_cast<std::size_t>(s.piece)] += rate;
  } else {
    shift_[static_cast<std::size_t>(s.piece)] += rate;
  }
}

void TrajectoryGradient::add(const TrajectoryGradient& other) {
  for (std::size_t i = 0; i < coeffs_.size(); ++i) {
    coeffs_[i] += other.coeffs_[i];
    durations_[i] += other.durations_[i];
    shift_[i] += other.shift_[i];
  }
}

double TrajectoryGradient::duration(int piece) const {
  // A shift recorded on piece i applies, negated, to every piece k < i.
  double later = 0.0;
  for (std::size_t i = static_cast<std::size_t>(piece) + 1; i < shift_.size(); ++i) later += shift_[i];
  return durations_[static_cast<std::size_t>(piece)] - later;
}

}  // namespace porter::backend
