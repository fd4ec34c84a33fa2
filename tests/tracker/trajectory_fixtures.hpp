#pragma once
// Trajectories for the tracker tests, built from knot states with quintic_hermite (C2 pieces).

#include <cmath>
#include <stdexcept>
#include <vector>

#include "porter/core/robot_model.hpp"
#include "porter/core/trajectory.hpp"

namespace porter::test {

struct Knot {
  double t_s = 0.0;
  TrajVector p = TrajVector::Zero();
  TrajVector v = TrajVector::Zero();
  TrajVector a = TrajVector::Zero();
};

inline Trajectory from_knots(const std::vector<Knot>& knots, int eta, double start_yaw_rad) {
  std::vector<TrajectoryPiece> pieces;
  for (std::size_t i = 0; i + 1 < knots.size(); ++i) {
    TrajectoryPiece piece;
    piece.duration_s = knots[i + 1].t_s - knots[i].t_s;
    piece.eta = eta;
    piece.coeffs = quintic_hermite(knots[i].p, knots[i].v, knots[i].a, knots[i + 1].p,
                                   knots[i + 1].v, knots[i + 1].a, piece.duration_s);
    pieces.push_back(piece);
  }
  TrajectoryResult r = Trajectory::create(std::move(pieces), start_yaw_rad);
  if (!r.ok()) throw std::runtime_error(r.error);
  return std::move(*r.trajectory);
}

inline TrajVector planar(double x, double y, double q1 = 0.0) {
  TrajVector z = TrajVector::Zero();
  z[0] = x;
  z[1] = y;
  z[2] = q1;
  return z;
}

/// Along direction yaw: accelerate from rest to speed_mps in 1 s, cruise for cruise_s, stop in
/// 1 s. eta = -1 drives backwards (the path runs against yaw's direction, the heading stays yaw).
/// Joint 1 moves 0 -> 0.5 rad over the whole trajectory.
inline Trajectory straight(double speed_mps, double cruise_s, int eta, double yaw_rad = 0.0) {
  const double ux = eta * std::cos(yaw_rad), uy = eta * std::sin(yaw_rad);
  const double ramp_m = 0.5 * speed_mps;  // quintic from rest to speed in 1 s covers v/2
  const double total = 2.0 + cruise_s;
  auto at = [&](double s_m, double v) {
    Knot k;
    k.p = planar(ux * s_m, uy * s_m);
    k.v = planar(ux * v, uy * v);
    return k;
  };
  std::vector<Knot> knots{at(0.0, 0.0), at(ramp_m, speed_mps), at(ramp_m + speed_mps * cruise_s, speed_mps),
                          at(2.0 * ramp_m + speed_mps * cruise_s, 0.0)};
  const double times[] = {0.0, 1.0, 1.0 + cruise_s, total};
  for (int i = 0; i < 4; ++i) {
    knots[static_cast<std::size_t>(i)].t_s = times[i];
    knots[static_cast<std::size_t>(i)].p[2] = 0.5 * times[i] / total;
    knots[static_cast<std::size_t>(i)].v[2] = 0.5 / total;
  }
  knots.front().v[2] = knots.back().v[2] = 0.0;
  return from_knots(knots, eta, yaw_rad);
}

/// A circular arc of radius_m (left turn when > 0) at constant speed, starting at the origin
/// heading +x (eta = +1) or reversing away from +x (eta = -1, heading stays towards +x of the
/// tangent's opposite), sampled into pieces of piece_s.
inline Trajectory arc(double speed_mps, double radius_m, double duration_s, int eta,
                      double piece_s = 0.5) {
  std::vector<Knot> knots;
  const int n = static_cast<int>(std::ceil(duration_s / piece_s));
  for (int i = 0; i <= n; ++i) {
    const double t = duration_s * i / n;
    const double phi = speed_mps * t / radius_m;
    const double s = speed_mps, w = speed_mps / radius_m;
    Knot k;
    k.t_s = t;
    // Motion along the circle; eta = -1 traverses it with the velocity reversed.
    k.p = planar(radius_m * std::sin(phi) * eta, radius_m * (1.0 - std::cos(phi)));
    k.v = planar(s * std::cos(phi) * eta, s * std::sin(phi));
    k.a = planar(-s * w * std::sin(phi) * eta, s * w * std::cos(phi));
    knots.push_back(k);
  }
  return from_knots(knots, eta, 0.0);
}

inline BaseLimits scout_limits() {
  BaseLimits b;
  b.wheel_radius_m = 0.0875;
  b.track_width_m = 0.4165;
  b.wheel_omega_max_radps = 12.0;
  b.wheel_alpha_max_radps2 = 20.0;
  b.min_turning_radius_m = 0.4;
  b.nonsingular_speed_mps = 0.05;
  return b;
}

}  // namespace porter::test
