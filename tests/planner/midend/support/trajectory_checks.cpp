#include "trajectory_checks.hpp"

#include <algorithm>
#include <cmath>

#include "porter/midend/diff_drive.hpp"
#include "porter/midend/reference_path.hpp"

namespace porter::midend::testing {
namespace {

TrajVector node_vector(const RobotConfiguration& c) {
  TrajVector z;
  z << c.base.x_m, c.base.y_m, c.q_rad;
  return z;
}

}  // namespace

CheckReport check_trajectory(const Trajectory& traj, const planner::WholeBodyPath& path,
                             const MidendLimits& limits, const MidendSettings& settings,
                             double dt_s) {
  CheckReport r;
  const ReferenceBuild ref = build_reference_path(path, limits, settings);
  // Per trajectory piece: its reference nodes and their time fractions (reference_path.hpp).
  struct PieceRef {
    std::vector<const RobotConfiguration*> nodes;
    std::vector<double> fractions;
  };
  std::vector<PieceRef> refs;
  for (const auto& seg : ref.path.segments) {
    for (int p = 0; p < seg.num_pieces(); ++p) {
      PieceRef pr;
      for (int k = 0; k <= seg.edges_in_piece(p); ++k) {
        pr.nodes.push_back(&seg.nodes[static_cast<std::size_t>(seg.knots[p] + k)]);
        pr.fractions.push_back(seg.fraction_in_piece(p, k));
      }
      refs.push_back(std::move(pr));
    }
  }
  const bool have_edges = ref.outcome == ReferenceOutcome::kOk &&
                          static_cast<int>(refs.size()) == traj.num_pieces();
  r.have_reference = have_edges;
  const int n = traj.num_pieces();
  const double total = traj.total_duration_s();

  // Boundaries.
  if (have_edges) {
    const RobotConfiguration& first = ref.path.segments.front().nodes.front();
    const RobotConfiguration& last = ref.path.segments.back().nodes.back();
    const TrajVector z0 = node_vector(first);
    const TrajVector z1 = node_vector(last);
    r.boundary_error = std::max({(traj.position(0.0) - z0).cwiseAbs().maxCoeff(),
                                 traj.velocity(0.0).cwiseAbs().maxCoeff(),
                                 traj.acceleration(0.0).cwiseAbs().maxCoeff(),
                                 (traj.position(total) - z1).cwiseAbs().maxCoeff(),
                                 traj.velocity(total).cwiseAbs().maxCoeff(),
                                 traj.acceleration(total).cwiseAbs().maxCoeff()});
    r.start_heading_error_rad =
        std::abs(angle_difference(traj.yaw_rad(0.0), first.base.yaw_rad));
    r.goal_heading_error_rad =
        std::abs(angle_difference(traj.yaw_rad(total), last.base.yaw_rad));
  }

  // Knots.
  for (int i = 0; i + 1 < n; ++i) {
    const TrajectoryPiece& a = traj.piece(i);
    const TrajectoryPiece& b = traj.piece(i + 1);
    if (a.eta == b.eta) {
      for (int k = 0; k <= 4; ++k) {
        const TrajVector l = piece_derivative(a.coeffs, a.duration_s, k);
        const TrajVector rr = piece_derivative(b.coeffs, 0.0, k);
        r.continuity_error = std::max(r.continuity_error,
                                      (l - rr).cwiseAbs().maxCoeff() / std::max(1.0, l.cwiseAbs().maxCoeff()));
      }
    } else {
      ++r.gear_switches;
      const TrajVector pl = piece_derivative(a.coeffs, a.duration_s, 0);
      const TrajVector pr = piece_derivative(b.coeffs, 0.0, 0);
      const TrajVector vl = piece_derivative(a.coeffs, a.duration_s, 1);
      const TrajVector vr = piece_derivative(b.coeffs, 0.0, 1);
      const TrajVector al = piece_derivative(a.coeffs, a.duration_s, 2);
      const TrajVector ar = piece_derivative(b.coeffs, 0.0, 2);
      double e = (pl - pr).cwiseAbs().maxCoeff();
      e = std::max(e, (vl.tail<6>() - vr.tail<6>()).cwiseAbs().maxCoeff());
      e = std::max(e, (al.tail<6>() - ar.tail<6>()).cwiseAbs().maxCoeff());
      // Base: speed v_ns on both sides, opposite directions, zero acceleration.
      e = std::max(e, std::abs(vl.head<2>().norm() - limits.nonsingular_speed_mps));
      e = std::max(e, std::abs(vr.head<2>().norm() - limits.nonsingular_speed_mps));
      e = std::max(e, (vl.head<2>() + vr.head<2>()).norm());
      e = std::max({e, al.head<2>().norm(), ar.head<2>().norm()});
      r.gear_error = std::max(r.gear_error, e);
      const double tg = traj.piece_start_time_s(i + 1);
      r.max_gear_yaw_jump_rad = std::max(
          r.max_gear_yaw_jump_rad, std::abs(angle_difference(traj.yaw_rad(tg + 1e-6), traj.yaw_rad(tg - 1e-6))));
    }
  }

  // Dense samples.
  const int steps = static_cast<int>(std::ceil(total / dt_s));
  double prev_yaw = traj.yaw_rad(0.0);
  const double rho_b2 = settings.residual_base_bound_m * settings.residual_base_bound_m;
  for (int s = 0; s <= steps; ++s) {
    const double t = std::min(s * dt_s, total);
    const TrajectoryState st = traj.sample(t, limits.track_width_m, limits.wheel_radius_m);
    ++r.samples;
    if (!st.z.allFinite() || !st.z_dot.allFinite() || !st.z_ddot.allFinite() ||
        !std::isfinite(st.base.yaw_rad) || !std::isfinite(st.wheels.left_radps) ||
        !std::isfinite(st.wheels.right_radps) || !std::isfinite(st.wheels.left_radps2) ||
        !std::isfinite(st.wheels.right_radps2)) {
      r.finite = false;
      continue;
    }
    r.max_yaw_step_rad = std::max(r.max_yaw_step_rad, std::abs(angle_difference(st.base.yaw_rad, prev_yaw)));
    prev_yaw = st.base.yaw_rad;
    r.wheel_velocity_ratio = std::max({r.wheel_velocity_ratio, std::abs(st.wheels.left_radps) / limits.wheel_omega_max_radps,
                                       std::abs(st.wheels.right_radps) / limits.wheel_omega_max_radps});
    r.wheel_acceleration_ratio =
        std::max({r.wheel_acceleration_ratio, std::abs(st.wheels.left_radps2) / limits.wheel_alpha_max_radps2,
                  std::abs(st.wheels.right_radps2) / limits.wheel_alpha_max_radps2});
    for (int j = 0; j < kNumArmJoints; ++j) {
      const double q = st.z[2 + j];
      const double range = limits.joint_upper_rad[j] - limits.joint_lower_rad[j];
      const double excess = std::max({0.0, q - limits.joint_upper_rad[j], limits.joint_lower_rad[j] - q});
      r.joint_position_excess = std::max(r.joint_position_excess, excess / range);
      r.joint_velocity_ratio = std::max(r.joint_velocity_ratio, std::abs(st.z_dot[2 + j]) / limits.joint_velocity_max_radps[j]);
      r.joint_acceleration_ratio =
          std::max(r.joint_acceleration_ratio, std::abs(st.z_ddot[2 + j]) / limits.joint_acceleration_max_radps2[j]);
    }
    if (have_edges) {
      double tau = 0.0;
      const int i = traj.locate(t, &tau);
      const double frac = tau / traj.piece(i).duration_s;
      // Nearest in time (node times are fixed fractions of the piece); at an exact midpoint
      // either node is nearest: take the better one.
      const PieceRef& pr = refs[static_cast<std::size_t>(i)];
      double best_gap = 1e300;
      for (double f : pr.fractions) best_gap = std::min(best_gap, std::abs(f - frac));
      std::vector<const RobotConfiguration*> nodes;
      for (std::size_t k = 0; k < pr.nodes.size(); ++k) {
        if (std::abs(pr.fractions[k] - frac) <= best_gap + 1e-9) nodes.push_back(pr.nodes[k]);
      }
      double best_b = 1e300, best_m = 1e300;
      for (const RobotConfiguration* node : nodes) {
        const double dx = st.z[0] - node->base.x_m, dy = st.z[1] - node->base.y_m;
        const double dyaw = angle_difference(st.base.yaw_rad, node->base.yaw_rad);
        const double eb = dx * dx + dy * dy + settings.residual_yaw_weight_m2 * dyaw * dyaw;
        best_b = std::min(best_b, eb);
        best_m = std::min(best_m, (st.z.tail<6>() - node->q_rad).squaredNorm());
      }
      r.residual_base_ratio = std::max(r.residual_base_ratio, std::sqrt(best_b / rho_b2));
      r.residual_arm_ratio = std::max(r.residual_arm_ratio, std::sqrt(best_m) / settings.residual_arm_bound_rad);
    }
  }
  return r;
}

}  // namespace porter::midend::testing
