// Motion and trajectory checks of KernelCollisionChecker (sampling bounds in its header).
#include <algorithm>
#include <array>
#include <cmath>

#include "porter/core/trajectory.hpp"
#include "porter/planner/angle.hpp"
#include "porter/planner/collision/kernel_collision_checker.hpp"

namespace porter::planner {

namespace {

using planner::wrap_angle_rad;

RobotConfiguration interpolate(const RobotConfiguration& a, const RobotConfiguration& b, double dyaw, double s) {
  RobotConfiguration c;
  c.base.x_m = a.base.x_m + s * (b.base.x_m - a.base.x_m);
  c.base.y_m = a.base.y_m + s * (b.base.y_m - a.base.y_m);
  c.base.yaw_rad = a.base.yaw_rad + s * dyaw;
  c.q_rad = a.q_rad + s * (b.q_rad - a.q_rad);
  return c;
}

/// Bound on how far any robot point moves for a change (dxy, dyaw, dq).
double displacement_bound(const ChainRadii& radii, double dxy, double dyaw, const JointVector& dq) {
  double d = dxy + radii.reach_m * std::abs(dyaw);
  for (int j = 0; j < kNumArmJoints; ++j) d += radii.sweep_radius_m[static_cast<std::size_t>(j)] * std::abs(dq[j]);
  return d;
}

/// |dz_d/dt| <= sum_k k |c_kd| T^(k-1) over the piece, per coordinate d.
TrajVector rate_bound(const TrajectoryPiece& piece) {
  TrajVector vmax = TrajVector::Zero();
  double tk = 1.0;
  for (int k = 1; k < kTrajNumCoeffs; ++k) {
    vmax += (k * tk) * piece.coeffs.row(k).transpose().cwiseAbs();
    tk *= piece.duration_s;
  }
  return vmax;
}

/// Intervals of a piece of duration T over which a point moving at most `speed` advances at most
/// half_step each.
int piece_intervals(double speed, double T, double half_step) {
  const double n = speed > 0.0 ? std::ceil(speed * T / half_step) : 1.0;
  return static_cast<int>(std::min(std::max(n, 1.0), 1e7));
}

/// Checks configurations in the order they are added, eight at a time with check_batch(), and
/// keeps the first hit in that order: the same answer as checking them one by one and stopping
/// at the first hit, for at most seven extra checks.
class BatchedChecks {
 public:
  explicit BatchedChecks(const KernelCollisionChecker& checker) : checker_(checker) {}
  /// Queues c; false once a hit is known (the caller stops adding and reads result()).
  bool add(const RobotConfiguration& c) {
    queue_[static_cast<std::size_t>(queued_++)] = c;
    return queued_ < kLanes || flush();
  }
  /// Checks what is queued; false once a hit is known.
  bool flush() {
    if (queued_ > 0 && !result_.in_collision) {
      std::array<CollisionResult, kLanes> results;
      checker_.check_batch(queue_.data(), static_cast<std::size_t>(queued_), results.data());
      for (int i = 0; i < queued_ && !result_.in_collision; ++i) result_ = results[static_cast<std::size_t>(i)];
    }
    queued_ = 0;
    return !result_.in_collision;
  }
  const CollisionResult& result() const { return result_; }

 private:
  static constexpr int kLanes = 8;
  const KernelCollisionChecker& checker_;
  std::array<RobotConfiguration, kLanes> queue_;
  int queued_ = 0;
  CollisionResult result_;
};

}  // namespace

int KernelCollisionChecker::motion_intervals(const RobotConfiguration& from, const RobotConfiguration& to) const {
  const double dxy = std::hypot(to.base.x_m - from.base.x_m, to.base.y_m - from.base.y_m);
  const double dyaw = wrap_angle_rad(to.base.yaw_rad - from.base.yaw_rad);
  const double d = displacement_bound(kernels_.radii(), dxy, dyaw, to.q_rad - from.q_rad);
  if (!std::isfinite(d)) return -1;
  const double n = std::ceil(d / motion_step_m_);
  return static_cast<int>(std::min(std::max(n, 1.0), 1e8));
}

CollisionResult KernelCollisionChecker::check_motion(const RobotConfiguration& from,
                                                     const RobotConfiguration& to) const {
  const int n = motion_intervals(from, to);
  if (n < 0) {  // NaN or infinite input
    CollisionResult r;
    r.in_collision = true;
    r.link = 0;
    return r;
  }
  const double dyaw = wrap_angle_rad(to.base.yaw_rad - from.base.yaw_rad);
  BatchedChecks checks(*this);
  if (!checks.add(from) || !checks.add(to)) return checks.result();
  // Interior samples i = 1..n-1 in bisection order: odd multiples of the largest power of two
  // below n first, then of half that, and so on; each index is visited once.
  int stride = 1;
  while (stride * 2 < n) stride *= 2;
  for (; stride >= 1; stride /= 2)
    for (int i = stride; i < n; i += 2 * stride)
      if (!checks.add(interpolate(from, to, dyaw, static_cast<double>(i) / n))) return checks.result();
  checks.flush();
  return checks.result();
}

CollisionResult KernelCollisionChecker::check_trajectory(const Trajectory& trajectory) const {
  const ChainRadii& radii = kernels_.radii();
  const double half_step = 0.5 * motion_step_m_;
  auto config_at = [&](double t) {
    RobotConfiguration c;
    const TrajVector z = trajectory.position(t);
    c.base.x_m = z[0];
    c.base.y_m = z[1];
    c.base.yaw_rad = trajectory.yaw_rad(t);
    c.q_rad = z.tail<kNumArmJoints>();
    return c;
  };
  BatchedChecks checks(*this);
  RobotConfiguration prev = config_at(0.0);
  if (!checks.add(prev)) return checks.result();
  double t_prev = 0.0;
  for (int i = 0; i < trajectory.num_pieces(); ++i) {
    const TrajectoryPiece& piece = trajectory.piece(i);
    const double T = piece.duration_s;
    const TrajVector vmax = rate_bound(piece);
    double speed = std::hypot(vmax[0], vmax[1]);
    for (int j = 0; j < kNumArmJoints; ++j) speed += radii.sweep_radius_m[static_cast<std::size_t>(j)] * vmax[2 + j];
    const int n = piece_intervals(speed, T, half_step);
    const double t0 = trajectory.piece_start_time_s(i);
    for (int k = 1; k <= n; ++k) {
      const double t = (k == n) ? trajectory.piece_start_time_s(i + 1) : t0 + T * k / n;
      // Halve [t_prev, t] while the heading change moves a point more than half a step.
      RobotConfiguration next = config_at(t);
      double t_lo = t_prev, t_hi = t;
      RobotConfiguration lo = prev, hi = next;
      int depth = 0;
      while (true) {
        const double dyaw = std::abs(wrap_angle_rad(hi.base.yaw_rad - lo.base.yaw_rad));
        if (radii.reach_m * dyaw <= half_step || depth >= 20) {
          if (!checks.add(hi)) return checks.result();
          if (t_hi >= t) break;
          t_lo = t_hi;
          lo = hi;
          t_hi = t;
          hi = next;
          depth = 0;
          continue;
        }
        t_hi = 0.5 * (t_lo + t_hi);
        hi = config_at(t_hi);
        ++depth;
      }
      prev = next;
      t_prev = t;
    }
  }
  checks.flush();
  return checks.result();
}

CollisionResult KernelCollisionChecker::check_trajectory_self(const Trajectory& trajectory) const {
  const ChainRadii& radii = kernels_.radii();
  const double half_step = 0.5 * motion_step_m_;
  auto q_at = [&](double t) -> JointVector { return trajectory.position(t).tail<kNumArmJoints>(); };
  CollisionResult r = check_self(q_at(0.0));
  if (r) return r;
  for (int i = 0; i < trajectory.num_pieces(); ++i) {
    const TrajectoryPiece& piece = trajectory.piece(i);
    const double T = piece.duration_s;
    // Relative motion of two links comes from the joints alone: bound it by sum_j rho_j |qdot_j|.
    const TrajVector vmax = rate_bound(piece);
    double speed = 0.0;
    for (int j = 0; j < kNumArmJoints; ++j) speed += radii.sweep_radius_m[static_cast<std::size_t>(j)] * vmax[2 + j];
    const int n = piece_intervals(speed, T, half_step);
    const double t0 = trajectory.piece_start_time_s(i);
    for (int k = 1; k <= n; ++k) {
      const double t = (k == n) ? trajectory.piece_start_time_s(i + 1) : t0 + T * k / n;
      r = check_self(q_at(t));
      if (r) return r;
    }
  }
  return r;
}

}  // namespace porter::planner
