#include "porter/core/trajectory.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

#include "porter/core/robot_model.hpp"

namespace porter {
namespace {

constexpr double kPi = 3.14159265358979323846;

// kFalling[k][r] = k! / (k - r)!  (0 for r > k): the factor of tau^(k-r) in the r-th derivative.
struct FallingTable {
  double v[kTrajNumCoeffs][kTrajNumCoeffs]{};
  constexpr FallingTable() {
    for (int k = 0; k < kTrajNumCoeffs; ++k) {
      for (int r = 0; r <= k; ++r) {
        double f = 1.0;
        for (int m = k - r + 1; m <= k; ++m) f *= m;
        v[k][r] = f;
      }
    }
  }
};
constexpr FallingTable kFalling;

constexpr double factorial(int n) { return n <= 1 ? 1.0 : n * factorial(n - 1); }

// Highest derivative order of p_xy the heading rule may look at: k + 2 with k <= kTrajDegree.
constexpr int kMaxXyOrder = kTrajDegree + 2;

Eigen::Vector2d xy_derivative(const PieceCoeffs& c, double tau_s, int order) {
  Eigen::Vector2d out = Eigen::Vector2d::Zero();
  if (order > kTrajDegree) return out;
  for (int k = kTrajDegree; k >= order; --k) {
    out = out * tau_s + kFalling.v[k][order] * c.block<1, 2>(k, 0).transpose();
  }
  return out;
}

double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

double wrap_pi(double a) {
  // atan2 already returns [-pi, pi]; fold -pi (from a -0.0 argument) onto +pi.
  return a <= -kPi ? a + 2.0 * kPi : a;
}

double normalize_angle(double a) {
  if (a > -kPi && a <= kPi) return a;
  return wrap_pi(std::remainder(a, 2.0 * kPi));
}

double clamp_time(double t_s, double total_s) {
  if (!(t_s >= 0.0)) return 0.0;  // also catches NaN
  return t_s > total_s ? total_s : t_s;
}

std::string num(double x) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.17g", x);
  return buf;
}

}  // namespace

TrajVector piece_derivative(const PieceCoeffs& coeffs, double tau_s, int order) {
  TrajVector out = TrajVector::Zero();
  if (order < 0) order = 0;
  if (order > kTrajDegree) return out;
  for (int k = kTrajDegree; k >= order; --k) {
    out = out * tau_s + kFalling.v[k][order] * coeffs.row(k).transpose();
  }
  return out;
}

WheelRates wheel_rates(const BaseMotion& base, double track_width_m, double wheel_radius_m) {
  const double inv = 1.0 / (2.0 * wheel_radius_m);
  const double lin_v = 2.0 * base.eta * base.speed_mps;
  const double lin_a = 2.0 * base.eta * base.accel_mps2;
  const double ang_v = track_width_m * base.yaw_rate_radps;
  const double ang_a = track_width_m * base.yaw_accel_radps2;
  WheelRates w;
  w.left_radps = (lin_v - ang_v) * inv;
  w.right_radps = (lin_v + ang_v) * inv;
  w.left_radps2 = (lin_a - ang_a) * inv;
  w.right_radps2 = (lin_a + ang_a) * inv;
  return w;
}

PieceCoeffs quintic_hermite(const TrajVector& p0, const TrajVector& v0, const TrajVector& a0,
                            const TrajVector& p1, const TrajVector& v1, const TrajVector& a1,
                            double duration_s) {
  const double T = duration_s;
  const double T2 = T * T;
  const double T3 = T2 * T;
  // Residual of the end state w.r.t. the Taylor polynomial of the start state.
  const TrajVector h = p1 - p0 - v0 * T - 0.5 * a0 * T2;
  const TrajVector g = v1 - v0 - a0 * T;
  const TrajVector f = a1 - a0;
  PieceCoeffs c;
  c.row(0) = p0.transpose();
  c.row(1) = v0.transpose();
  c.row(2) = 0.5 * a0.transpose();
  c.row(3) = ((10.0 * h - 4.0 * T * g + 0.5 * T2 * f) / T3).transpose();
  c.row(4) = ((-15.0 * h + 7.0 * T * g - T2 * f) / (T3 * T)).transpose();
  c.row(5) = ((6.0 * h - 3.0 * T * g + 0.5 * T2 * f) / (T3 * T2)).transpose();
  return c;
}

TrajectoryResult Trajectory::create(std::vector<TrajectoryPiece> pieces, double start_yaw_rad) {
  TrajectoryResult r;
  if (pieces.empty()) {
    r.error = "pieces: a trajectory needs at least one piece";
    return r;
  }
  if (!std::isfinite(start_yaw_rad) || std::abs(start_yaw_rad) > kTrajMaxReach) {
    r.error = "start_yaw_rad: must be finite and within +-" + num(kTrajMaxReach) + " (got " +
              num(start_yaw_rad) + ")";
    return r;
  }
  double total = 0.0;
  for (size_t i = 0; i < pieces.size(); ++i) {
    const TrajectoryPiece& p = pieces[i];
    const std::string where = "pieces[" + std::to_string(i) + "]";
    if (!std::isfinite(p.duration_s) || !(p.duration_s > 0.0)) {
      r.error = where + ".duration_s: must be finite and > 0 (got " + num(p.duration_s) + ")";
      return r;
    }
    if (p.duration_s < kTrajMinPieceDuration_s || p.duration_s > kTrajMaxPieceDuration_s) {
      r.error = where + ".duration_s: must be within [" + num(kTrajMinPieceDuration_s) + ", " +
                num(kTrajMaxPieceDuration_s) + "] s (got " + num(p.duration_s) + ")";
      return r;
    }
    if (p.eta != 1 && p.eta != -1) {
      r.error = where + ".eta: must be +1 or -1 (got " + std::to_string(p.eta) + ")";
      return r;
    }
    for (int k = 0; k < kTrajNumCoeffs; ++k) {
      for (int d = 0; d < kTrajDim; ++d) {
        if (!std::isfinite(p.coeffs(k, d))) {
          r.error = where + ".coeffs[" + std::to_string(k) + "][" + std::to_string(d) +
                    "]: must be finite (got " + num(p.coeffs(k, d)) + ")";
          return r;
        }
        const double reach = std::abs(p.coeffs(k, d)) * std::pow(p.duration_s, k);
        if (!(reach <= kTrajMaxReach)) {
          r.error = where + ".coeffs[" + std::to_string(k) + "][" + std::to_string(d) + "]: |c| T^" +
                    std::to_string(k) + " = " + num(reach) + " exceeds " + num(kTrajMaxReach) +
                    " (got " + num(p.coeffs(k, d)) + " over " + num(p.duration_s) + " s)";
          return r;
        }
      }
    }
    total += p.duration_s;
  }
  if (!(total <= kTrajMaxTotalDuration_s)) {
    r.error = "pieces: total duration " + num(total) + " s exceeds " + num(kTrajMaxTotalDuration_s) + " s";
    return r;
  }
  r.trajectory.emplace(Trajectory(std::move(pieces), start_yaw_rad));
  return r;
}

Trajectory::Trajectory(std::vector<TrajectoryPiece> pieces, double start_yaw_rad)
    : pieces_(std::move(pieces)), start_yaw_rad_(start_yaw_rad) {
  const size_t n = pieces_.size();
  start_times_s_.resize(n + 1);
  start_times_s_[0] = 0.0;
  for (size_t i = 0; i < n; ++i) start_times_s_[i + 1] = start_times_s_[i] + pieces_[i].duration_s;
  // held_yaw_rad_[i] is needed by base_motion_at(i, ...), so fill it in piece order: the heading
  // held in piece i is the left-limit heading at the end of piece i - 1 (itself a held heading
  // when piece i - 1 does not move the base).
  held_yaw_rad_.assign(n, normalize_angle(start_yaw_rad));
  for (size_t i = 1; i < n; ++i) {
    const int prev = static_cast<int>(i) - 1;
    held_yaw_rad_[i] = base_motion_at(prev, pieces_[i - 1].duration_s, /*at_end=*/true).yaw_rad;
  }
}

Trajectory Trajectory::concatenate(const Trajectory& first, const Trajectory& second) {
  std::vector<TrajectoryPiece> pieces = first.pieces_;
  pieces.insert(pieces.end(), second.pieces_.begin(), second.pieces_.end());
  return Trajectory(std::move(pieces), first.start_yaw_rad_);
}

int Trajectory::locate(double t_s, double* tau_s) const {
  const double t = clamp_time(t_s, total_duration_s());
  // Piece i is the number of interior knots Tbar_1..Tbar_{N-1} that are <= t.
  const auto first = start_times_s_.begin() + 1;
  const auto last = start_times_s_.end() - 1;
  const int i = static_cast<int>(std::upper_bound(first, last, t) - first);
  double tau = t - start_times_s_[static_cast<size_t>(i)];
  tau = std::min(std::max(tau, 0.0), pieces_[static_cast<size_t>(i)].duration_s);
  if (tau_s != nullptr) *tau_s = tau;
  return i;
}

TrajVector Trajectory::derivative(double t_s, int order) const {
  double tau = 0.0;
  const int i = locate(t_s, &tau);
  return piece_derivative(pieces_[static_cast<size_t>(i)].coeffs, tau, order);
}

BaseMotion Trajectory::base_motion(double t_s) const {
  double tau = 0.0;
  const int i = locate(t_s, &tau);
  const bool at_end = clamp_time(t_s, total_duration_s()) >= total_duration_s();
  return base_motion_at(i, tau, at_end);
}

namespace {

// Base rates from the factorization pd(t0 + h) = h^(k-1) W(h) around a rest instant t0 of the
// piece (d[r] = p_xy^(r)(t0), k >= 2 the order of the first derivative that does not vanish
// there, h != 0). W(h) = sum_{m=k-1..4} d[m+1] h^(m-k+1) / m! is evaluated term by term. The
// terms below order k are dropped: they are the rounding residuals of pd, pdd at t0 (~1e-15),
// which divided by h^(k-1) would swamp the rates a few microseconds from rest (alpha_b grows like
// residual / h^4); the rest is taken as exact. Then
//   omega = (W x W') / |W|^2,  alpha = (W x W'') / |W|^2 - 2 (W x W')(W . W') / |W|^4,
//   v_b = |h|^(k-1) |W|,       a_b = d v_b / dt,        direction of motion sgn(h)^(k-1) W.
// Unlike the same quotients in pd, pdd, pddd, these contain no terms of order 1/h that cancel.
struct Expansion {
  Eigen::Vector2d dir;
  double speed, accel, omega, alpha;
};

Expansion rest_expansion(const Eigen::Vector2d* d, int k, double h) {
  Eigen::Vector2d w = Eigen::Vector2d::Zero(), w1 = Eigen::Vector2d::Zero(),
                  w2 = Eigen::Vector2d::Zero();
  for (int m = k - 1; m <= kTrajDegree - 1; ++m) {
    const int e = m - (k - 1);  // power of h in W, >= 0
    const Eigen::Vector2d c = d[m + 1] / factorial(m);
    if (c.isZero(0.0)) continue;
    const double pe = std::pow(h, e);
    w += c * pe;
    if (e != 0) w1 += c * (e * pe / h);
    if (e != 0 && e != 1) w2 += c * (e * (e - 1) * pe / (h * h));
  }
  Expansion x;
  const double n2 = w.squaredNorm();
  const double n = std::sqrt(n2);
  const double c1 = cross2(w, w1), dot1 = w.dot(w1);
  const double hk = std::pow(std::abs(h), k - 1);
  const double sign = (k % 2 == 0 && h < 0.0) ? -1.0 : 1.0;  // sgn(h)^(k-1)
  x.dir = sign * w / n;
  x.speed = hk * n;
  // d/dh (|h|^(k-1) |W|) = (k-1) |h|^(k-2) sgn(h) |W| + |h|^(k-1) (W . W') / |W|
  x.accel = (k - 1) * std::pow(std::abs(h), k - 2) * (h < 0.0 ? -1.0 : 1.0) * n + hk * dot1 / n;
  x.omega = c1 / n2;
  x.alpha = cross2(w, w2) / n2 - 2.0 * c1 * dot1 / (n2 * n2);
  return x;
}

}  // namespace

BaseMotion Trajectory::base_motion_at(int piece, double tau_s, bool at_end) const {
  const TrajectoryPiece& p = pieces_[static_cast<size_t>(piece)];
  Eigen::Vector2d d[kMaxXyOrder + 1];
  for (int r = 0; r <= kMaxXyOrder; ++r) d[r] = xy_derivative(p.coeffs, tau_s, r);

  BaseMotion m;
  m.eta = p.eta;
  const Eigen::Vector2d& v = d[1];
  m.speed_mps = v.norm();
  m.signed_speed_mps = p.eta * m.speed_mps;

  if (m.speed_mps < kSlowSpeed_mps) {
    // Next to a rest instant at the nearer end t0 of the piece: expand around it (see
    // rest_expansion). At t0 itself the limit rule below applies.
    const double t0 = tau_s <= 0.5 * p.duration_s ? 0.0 : p.duration_s;
    const double h = tau_s - t0;
    Eigen::Vector2d e[kMaxXyOrder + 1];
    for (int r = 0; r <= kMaxXyOrder; ++r) e[r] = xy_derivative(p.coeffs, t0, r);
    int k = 0;
    for (int r = 2; r <= kTrajDegree && h != 0.0 && e[1].norm() < kRestSpeed_mps; ++r) {
      if (e[r].norm() >= kVanishing) {
        k = r;
        break;
      }
    }
    if (k != 0) {
      const Expansion x = rest_expansion(e, k, h);
      if (std::isfinite(x.alpha) && std::isfinite(x.dir.x()) && std::isfinite(x.dir.y())) {
        m.yaw_rad = wrap_pi(std::atan2(p.eta * x.dir.y(), p.eta * x.dir.x()));
        m.speed_mps = x.speed;
        m.signed_speed_mps = p.eta * x.speed;
        m.accel_mps2 = x.accel;
        m.yaw_rate_radps = x.omega;
        m.yaw_accel_radps2 = x.alpha;
        return m;
      }
    }
  }

  // u: unit direction of motion; V0..V2: the series of pd / (t - t0)^(k-1) (see the header).
  Eigen::Vector2d u, V0, V1, V2;
  if (m.speed_mps >= kRestSpeed_mps) {
    u = v / m.speed_mps;
    V0 = v;
    V1 = d[2];
    V2 = d[3];
  } else {
    int k = 0;
    for (int r = 2; r <= kTrajDegree; ++r) {
      if (d[r].norm() >= kVanishing) {
        k = r;
        break;
      }
    }
    if (k == 0) {
      m.yaw_rad = held_yaw_rad_[static_cast<size_t>(piece)];
      m.held = true;
      return m;
    }
    const double along = v.dot(d[k]);
    const bool odd = (k % 2) == 1;
    // Before a rest instant (even k) the residual velocity points against p^(k).
    const bool positive = odd || (at_end ? along > 0.0 : along >= 0.0);
    u = (positive ? 1.0 : -1.0) * d[k].normalized();
    V0 = d[k] / factorial(k - 1);
    V1 = d[k + 1] / factorial(k);
    V2 = 2.0 * d[k + 2] / factorial(k + 1);
  }
  m.yaw_rad = wrap_pi(std::atan2(p.eta * u.y(), p.eta * u.x()));
  m.accel_mps2 = u.dot(d[2]);
  const double n2 = V0.squaredNorm();
  const double c1 = cross2(V0, V1);
  m.yaw_rate_radps = c1 / n2;
  m.yaw_accel_radps2 = cross2(V0, V2) / n2 - 2.0 * c1 * V0.dot(V1) / (n2 * n2);
  return m;
}

WheelRates Trajectory::wheel_rates(double t_s, double track_width_m, double wheel_radius_m) const {
  return porter::wheel_rates(base_motion(t_s), track_width_m, wheel_radius_m);
}

TrajectoryState Trajectory::sample(double t_s, double track_width_m, double wheel_radius_m) const {
  TrajectoryState s;
  double tau = 0.0;
  s.piece = locate(t_s, &tau);
  s.t_s = clamp_time(t_s, total_duration_s());
  const PieceCoeffs& c = pieces_[static_cast<size_t>(s.piece)].coeffs;
  s.z = piece_derivative(c, tau, 0);
  s.z_dot = piece_derivative(c, tau, 1);
  s.z_ddot = piece_derivative(c, tau, 2);
  s.base = base_motion_at(s.piece, tau, /*at_end=*/s.t_s >= total_duration_s());
  s.wheels = porter::wheel_rates(s.base, track_width_m, wheel_radius_m);
  return s;
}

TrajectoryState Trajectory::sample(double t_s, const BaseLimits& base) const {
  return sample(t_s, base.track_width_m, base.wheel_radius_m);
}

}  // namespace porter
