#include "porter/validation/flat_trajectory.hpp"

#include <algorithm>
#include <cmath>

namespace porter::validation {
namespace {

constexpr double kVanishing = 1e-12;  // a derivative of p below this (m/s^k) counts as zero

double falling(int k, int order) {  // k (k-1) ... (k-order+1)
  double f = 1.0;
  for (int m = 0; m < order; ++m) f *= static_cast<double>(k - m);
  return f;
}

double wrap(double a) {
  a = std::remainder(a, 2.0 * M_PI);
  return a <= -M_PI ? a + 2.0 * M_PI : a;
}

}  // namespace

FlatVector poly_derivative(const PolyCoeffs& c, double tau_s, int order) {
  FlatVector out = FlatVector::Zero();
  if (order < 0) order = 0;
  if (order >= kPolyCoeffs) return out;
  // Horner over k = order .. 5 of falling(k, order) c_k tau^(k - order).
  for (int k = kPolyCoeffs - 1; k >= order; --k)
    out = out * tau_s + falling(k, order) * c.row(k).transpose();
  return out;
}

FlatTrajectory::FlatTrajectory(std::vector<PolyPiece> pieces, double start_yaw_rad)
    : pieces_(std::move(pieces)) {
  starts_s_.push_back(0.0);
  for (const auto& p : pieces_) starts_s_.push_back(starts_s_.back() + p.duration_s);
  // Heading held by each piece if it does not move the base: the heading at the end of the last
  // earlier piece that moves it.
  double held = start_yaw_rad;
  for (size_t i = 0; i < pieces_.size(); ++i) {
    held_yaw_rad_.push_back(held);
    bool moves = false;
    for (int k = 1; k < kPolyCoeffs; ++k)
      if (pieces_[i].coeffs.row(k).head<2>().norm() > kVanishing) moves = true;
    if (moves) held = heading_at(static_cast<int>(i), pieces_[i].duration_s, /*at_end=*/true);
  }
}

int FlatTrajectory::locate(double t_s, double* tau_s) const {
  if (!(t_s > 0.0)) t_s = 0.0;  // NaN too
  if (t_s > duration_s()) t_s = duration_s();
  auto it = std::upper_bound(starts_s_.begin(), starts_s_.end(), t_s);
  int i = static_cast<int>(it - starts_s_.begin()) - 1;
  i = std::clamp(i, 0, num_pieces() - 1);
  *tau_s = std::min(t_s - starts_s_[static_cast<size_t>(i)], pieces_[static_cast<size_t>(i)].duration_s);
  return i;
}

FlatVector FlatTrajectory::derivative(double t_s, int order) const {
  double tau = 0.0;
  const int i = locate(t_s, &tau);
  return poly_derivative(pieces_[static_cast<size_t>(i)].coeffs, tau, order);
}

double FlatTrajectory::heading_at(int i, double tau_s, bool at_end) const {
  const PolyPiece& p = pieces_[static_cast<size_t>(i)];
  const double eta = static_cast<double>(p.eta);
  const Eigen::Vector2d v = poly_derivative(p.coeffs, tau_s, 1).head<2>();
  if (v.norm() >= kRestSpeed_mps) return wrap(std::atan2(eta * v.y(), eta * v.x()));
  for (int k = 2; k < kPolyCoeffs; ++k) {
    const Eigen::Vector2d dk = poly_derivative(p.coeffs, tau_s, k).head<2>();
    if (dk.norm() < kVanishing) continue;
    // v ~ dk h^(k-1) / (k-1)!: ahead of the rest instant (h > 0) the direction is +dk; arriving
    // at it (h < 0, the trajectory's end) it is (-1)^(k-1) dk.
    Eigen::Vector2d u = dk;
    if (at_end && (k - 1) % 2 == 1) u = -dk;
    return wrap(std::atan2(eta * u.y(), eta * u.x()));
  }
  return held_yaw_rad_.empty() ? 0.0 : held_yaw_rad_[static_cast<size_t>(i)];
}

double FlatTrajectory::yaw_rad(double t_s) const {
  double tau = 0.0;
  const int i = locate(t_s, &tau);
  const bool at_end = !(t_s < duration_s());
  return heading_at(i, tau, at_end);
}

PlanarRates FlatTrajectory::planar_rates(double t_s) const {
  double tau = 0.0;
  const int i = locate(t_s, &tau);
  const PolyPiece& p = pieces_[static_cast<size_t>(i)];
  const Eigen::Vector2d d1 = poly_derivative(p.coeffs, tau, 1).head<2>();
  const Eigen::Vector2d d2 = poly_derivative(p.coeffs, tau, 2).head<2>();
  const Eigen::Vector2d d3 = poly_derivative(p.coeffs, tau, 3).head<2>();
  PlanarRates r;
  r.speed_mps = d1.norm();
  if (r.speed_mps < kRestSpeed_mps) return r;
  const double s2 = d1.squaredNorm();
  const double cross12 = d1.x() * d2.y() - d1.y() * d2.x();
  const double cross13 = d1.x() * d3.y() - d1.y() * d3.x();
  const double dot12 = d1.dot(d2);
  r.v_mps = p.eta * r.speed_mps;
  r.a_mps2 = p.eta * dot12 / r.speed_mps;
  r.omega_radps = cross12 / s2;
  r.alpha_radps2 = cross13 / s2 - 2.0 * cross12 * dot12 / (s2 * s2);
  return r;
}

}  // namespace porter::validation
