#include "porter/planner_daemon/trajectory_ops.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace porter::planner_daemon {
namespace {

constexpr double kCutEpsilon_s = 1e-6;
constexpr double kEndPiece_s = 1e-3;
constexpr double kRestEpsilon = 1e-6;

/// Coefficients of p(tau + a) from those of p(tau) (Taylor shift: c'_k = sum_j c_j C(j,k) a^(j-k)).
PieceCoeffs shift(const PieceCoeffs& c, double a) {
  PieceCoeffs out = PieceCoeffs::Zero();
  for (int k = 0; k < kTrajNumCoeffs; ++k) {
    double binom = 1.0;  // C(j, k), starting at j = k
    double power = 1.0;  // a^(j - k)
    for (int j = k; j < kTrajNumCoeffs; ++j) {
      out.row(k) += binom * power * c.row(j);
      binom = binom * static_cast<double>(j + 1) / static_cast<double>(j + 1 - k);
      power *= a;
    }
  }
  return out;
}

/// A stationary piece at position z.
TrajectoryPiece rest_piece(const TrajVector& z, double duration_s, int eta) {
  TrajectoryPiece p;
  p.duration_s = duration_s;
  p.eta = eta;
  p.coeffs.row(0) = z.transpose();
  return p;
}

}  // namespace

Trajectory trajectory_tail(const Trajectory& trajectory, double t0_s) {
  const double total = trajectory.total_duration_s();
  const double t0 = std::clamp(t0_s, 0.0, total);
  const double yaw = trajectory.yaw_rad(t0);
  std::vector<TrajectoryPiece> pieces;
  double tau = 0.0;
  int i = trajectory.locate(t0, &tau);
  if (trajectory.piece(i).duration_s - tau < kCutEpsilon_s) {
    ++i;
    tau = 0.0;
  }
  if (i >= trajectory.num_pieces()) {
    const int eta = trajectory.piece(trajectory.num_pieces() - 1).eta;
    pieces.push_back(rest_piece(trajectory.position(total), kEndPiece_s, eta));
  } else {
    TrajectoryPiece first = trajectory.piece(i);
    if (tau > 0.0) {
      first.coeffs = shift(first.coeffs, tau);
      first.duration_s -= tau;
    }
    pieces.push_back(first);
    for (int k = i + 1; k < trajectory.num_pieces(); ++k) pieces.push_back(trajectory.piece(k));
  }
  // Valid by construction: finite coefficients, positive durations, eta from a valid trajectory.
  return *Trajectory::create(std::move(pieces), yaw).trajectory;
}

Trajectory braking_trajectory(const Trajectory& trajectory, double t_s, const BrakingLimits& limits) {
  const double total = trajectory.total_duration_s();
  const double t0 = std::clamp(t_s, 0.0, total);
  const TrajVector z0 = trajectory.position(t0);
  const TrajVector v0 = trajectory.velocity(t0);
  const TrajVector a0 = trajectory.acceleration(t0);
  double tau = 0.0;
  const int eta = trajectory.piece(trajectory.locate(t0, &tau)).eta;

  double T = limits.min_duration_s;
  T = std::max(T, 2.0 * v0.head<2>().norm() / limits.base_decel_mps2);
  for (int d = 2; d < kTrajDim; ++d) T = std::max(T, 2.0 * std::abs(v0[d]) / limits.joint_decel_radps2);

  const TrajVector on_path = trajectory.position(std::min(t0 + 0.5 * T, total));
  const bool base_at_rest = v0.head<2>().norm() < kRestEpsilon && a0.head<2>().norm() < kRestEpsilon;
  TrajVector z1 = on_path;
  if (base_at_rest) z1.head<2>() = z0.head<2>();
  for (int d = 2; d < kTrajDim; ++d) {
    if (std::abs(v0[d]) < kRestEpsilon && std::abs(a0[d]) < kRestEpsilon) z1[d] = z0[d];
  }

  // Quintic with z(0) = z0, z'(0) = v0, z''(0) = a0, z(T) = z1, z'(T) = z''(T) = 0.
  TrajectoryPiece p;
  p.duration_s = T;
  p.eta = eta;
  const double T2 = T * T, T3 = T2 * T, T4 = T3 * T, T5 = T4 * T;
  for (int d = 0; d < kTrajDim; ++d) {
    const double h = z1[d] - z0[d] - v0[d] * T - 0.5 * a0[d] * T2;
    const double dv = -v0[d] - a0[d] * T;
    const double da = -a0[d];
    p.coeffs(0, d) = z0[d];
    p.coeffs(1, d) = v0[d];
    p.coeffs(2, d) = 0.5 * a0[d];
    p.coeffs(3, d) = (10.0 * h - 4.0 * dv * T + 0.5 * da * T2) / T3;
    p.coeffs(4, d) = (-15.0 * h + 7.0 * dv * T - da * T2) / T4;
    p.coeffs(5, d) = (6.0 * h - 3.0 * dv * T + 0.5 * da * T2) / T5;
  }
  std::vector<TrajectoryPiece> pieces{p};
  return *Trajectory::create(std::move(pieces), trajectory.yaw_rad(t0)).trajectory;
}

}  // namespace porter::planner_daemon
