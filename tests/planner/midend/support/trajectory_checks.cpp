#include "trajectory_checks.hpp"
#include "porter/planner/angle.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

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
    int segment = 0;
    bool still = false;
  };
  std::vector<PieceRef> refs;
  for (std::size_t si = 0; si < ref.path.segments.size(); ++si) {
    const auto& seg = ref.path.segments[si];
    for (int p = 0; p < seg.num_pieces(); ++p) {
      PieceRef pr;
      pr.segment = static_cast<int>(si);
      pr.still = seg.base_still;
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
        std::abs(planner::angle_difference_rad(traj.yaw_rad(0.0), first.base.yaw_rad));
    r.goal_heading_error_rad =
        std::abs(planner::angle_difference_rad(traj.yaw_rad(total), last.base.yaw_rad));
  }

  // Segment of every piece: from the reference when it matches, else from eta changes.
  std::vector<int> piece_segment(static_cast<std::size_t>(n), 0);
  std::vector<bool> piece_still(static_cast<std::size_t>(n), false);
  for (int i = 0; i < n; ++i) {
    if (have_edges) {
      piece_segment[static_cast<std::size_t>(i)] = refs[static_cast<std::size_t>(i)].segment;
      piece_still[static_cast<std::size_t>(i)] = refs[static_cast<std::size_t>(i)].still;
    } else if (i > 0) {
      piece_segment[static_cast<std::size_t>(i)] =
          piece_segment[static_cast<std::size_t>(i - 1)] + (traj.piece(i).eta != traj.piece(i - 1).eta);
    }
  }

  // Knots.
  for (int i = 0; i + 1 < n; ++i) {
    const TrajectoryPiece& a = traj.piece(i);
    const TrajectoryPiece& b = traj.piece(i + 1);
    const bool rest_junction = piece_segment[static_cast<std::size_t>(i)] != piece_segment[static_cast<std::size_t>(i + 1)] &&
                               (piece_still[static_cast<std::size_t>(i)] || piece_still[static_cast<std::size_t>(i + 1)]);
    if (rest_junction) {
      // The base comes to rest (or leaves it) while the arm goes on: C^2, base v = a = 0.
      ++r.rest_junctions;
      for (int k = 0; k <= 2; ++k) {
        const TrajVector l = piece_derivative(a.coeffs, a.duration_s, k);
        const TrajVector rr = piece_derivative(b.coeffs, 0.0, k);
        r.continuity_error = std::max(r.continuity_error,
                                      (l - rr).cwiseAbs().maxCoeff() / std::max(1.0, l.cwiseAbs().maxCoeff()));
        if (k > 0) {
          r.rest_junction_error = std::max({r.rest_junction_error, l.head<2>().norm(), rr.head<2>().norm()});
        }
      }
    } else if (a.eta == b.eta) {
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
          r.max_gear_yaw_jump_rad, std::abs(planner::angle_difference_rad(traj.yaw_rad(tg + 1e-6), traj.yaw_rad(tg - 1e-6))));
    }
  }

  // Dense samples.
  const int steps = static_cast<int>(std::ceil(total / dt_s));
  double prev_yaw = traj.yaw_rad(0.0);
  Eigen::Vector2d prev_v = Eigen::Vector2d::Zero();  // last base velocity above kMoving
  int prev_segment = -1;
  constexpr double kMoving_mps = 1e-6;
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
    r.max_yaw_step_rad = std::max(r.max_yaw_step_rad, std::abs(planner::angle_difference_rad(st.base.yaw_rad, prev_yaw)));
    {
      const int seg = piece_segment[static_cast<std::size_t>(st.piece)];
      const Eigen::Vector2d v = st.z_dot.head<2>();
      if (seg != prev_segment) {
        prev_segment = seg;
        prev_v.setZero();
      }
      if (piece_still[static_cast<std::size_t>(st.piece)]) {
        r.rest_junction_error = std::max(r.rest_junction_error, v.norm());
      } else if (v.norm() > kMoving_mps) {
        if (prev_v.norm() > kMoving_mps && v.dot(prev_v) < 0.0) ++r.reversals;
        prev_v = v;
      }
    }
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
        const double dyaw = planner::angle_difference_rad(st.base.yaw_rad, node->base.yaw_rad);
        const double eb = dx * dx + dy * dy + settings.residual_yaw_weight_m2 * dyaw * dyaw;
        best_b = std::min(best_b, eb);
        best_m = std::min(best_m, (st.z.tail<6>() - node->q_rad).squaredNorm());
      }
      const double ratio_b = std::sqrt(best_b / rho_b2);
      const double ratio_m = std::sqrt(best_m) / settings.residual_arm_bound_rad;
      if (ratio_b > r.residual_base_ratio) {
        r.residual_base_ratio = ratio_b;
        r.residual_base_worst_t_s = t;
      }
      if (ratio_m > r.residual_arm_ratio) {
        r.residual_arm_ratio = ratio_m;
        r.residual_arm_worst_t_s = t;
      }
    }
  }
  return r;
}

std::vector<std::string> violations(const CheckReport& r, const CheckTolerances& tol) {
  std::vector<std::string> out;
  char buf[160];
  auto above = [&](double value, double bound, const char* what) {
    if (!(value <= bound)) {
      std::snprintf(buf, sizeof buf, "%s %.4g (bound %.4g)", what, value, bound);
      out.emplace_back(buf);
    }
  };
  if (!r.finite) out.emplace_back("non-finite state");
  if (!r.have_reference) out.emplace_back("pieces do not match the reference path");
  above(r.boundary_error, tol.boundary, "boundary error");
  above(r.continuity_error, tol.continuity, "continuity error");
  above(r.gear_error, tol.continuity, "gear-switch error");
  above(r.rest_junction_error, tol.continuity, "base motion at rest junctions / still pieces");
  if (r.reversals > 0) out.emplace_back("base reverses inside a segment (" + std::to_string(r.reversals) + "x)");
  above(r.max_gear_yaw_jump_rad, tol.gear_yaw_jump_rad, "yaw jump at a gear switch, rad");
  above(r.max_yaw_step_rad, tol.yaw_step_rad, "yaw step between samples, rad");
  above(r.wheel_velocity_ratio, tol.limit_ratio, "wheel velocity / limit");
  above(r.wheel_acceleration_ratio, tol.limit_ratio, "wheel acceleration / limit");
  above(r.joint_velocity_ratio, tol.limit_ratio, "joint velocity / limit");
  above(r.joint_acceleration_ratio, tol.limit_ratio, "joint acceleration / limit");
  above(r.joint_position_excess, tol.joint_position_excess, "joint position excess / range");
  above(r.residual_base_ratio, tol.residual_ratio, "base residual / rho_b");
  above(r.residual_arm_ratio, tol.residual_ratio, "arm residual / rho_m");
  above(r.start_heading_error_rad, tol.heading_rad, "start heading error, rad");
  above(r.goal_heading_error_rad, tol.heading_rad, "goal heading error, rad");
  return out;
}

}  // namespace porter::midend::testing
