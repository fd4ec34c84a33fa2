#include "porter/midend/midend.hpp"

#include <lbfgs.h>

#include <chrono>
#include <cmath>
#include <string>

#include "porter/midend/lbfgs_codes.hpp"
#include "porter/midend/lbfgs_driver.hpp"
#include "porter/midend/midend_problem.hpp"
#include "porter/midend/reference_path.hpp"
#include "trajectory_verify.hpp"

namespace porter::midend {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

void finish(MidendResult& r, Clock::time_point start) { r.elapsed_s = seconds_since(start); }

}  // namespace

bool validate_settings(const MidendSettings& s, std::string* why) {
  auto fail = [why](const char* m) {
    if (why) *why = m;
    return false;
  };
  auto pos = [](double v) { return std::isfinite(v) && v > 0.0; };
  auto nonneg = [](double v) { return std::isfinite(v) && v >= 0.0; };
  if (s.samples_per_piece < 2 || s.samples_per_piece > 64) return fail("samples_per_piece not in [2, 64]");
  if (s.gear_sample_factor < 1 || s.gear_sample_factor > 16) return fail("gear_sample_factor not in [1, 16]");
  if (!nonneg(s.max_sample_interval_s)) return fail("max_sample_interval_s must be >= 0");
  if (!nonneg(s.weight_min_speed) || !(s.min_speed_fraction >= 0.0 && s.min_speed_fraction <= 1.0)) {
    return fail("weight_min_speed must be >= 0 and min_speed_fraction in [0, 1]");
  }
  if (!(s.slow_reference_fraction > 0.0 && s.slow_reference_fraction <= 1.0)) {
    return fail("slow_reference_fraction not in (0, 1]");
  }
  if (!pos(s.energy_weight_base) || !pos(s.energy_weight_joint)) return fail("energy weights must be > 0");
  if (!pos(s.time_weight_per_s)) return fail("time_weight_per_s must be > 0");
  if (!pos(s.penalty_smoothing) || s.penalty_smoothing > 1.0) return fail("penalty_smoothing not in (0, 1]");
  for (double w : {s.weight_wheel_velocity, s.weight_wheel_acceleration, s.weight_joint_position,
                   s.weight_joint_velocity, s.weight_joint_acceleration, s.weight_residual_base,
                   s.weight_residual_arm, s.weight_boundary_heading}) {
    if (!nonneg(w)) return fail("penalty weights must be >= 0");
  }
  if (!pos(s.residual_base_bound_m) || !pos(s.residual_arm_bound_rad)) return fail("residual bounds must be > 0");
  if (!(s.limit_penalty_fraction > 0.0 && s.limit_penalty_fraction <= 1.0)) {
    return fail("limit_penalty_fraction not in (0, 1]");
  }
  if (!(s.residual_penalty_fraction > 0.0 && s.residual_penalty_fraction <= 1.0)) {
    return fail("residual_penalty_fraction not in (0, 1]");
  }
  if (!nonneg(s.residual_yaw_weight_m2)) return fail("residual_yaw_weight_m2 must be >= 0");
  if (!pos(s.speed_guard_mps) || !pos(s.yaw_gate_speed_mps) || !pos(s.boundary_jerk_guard_mps3)) {
    return fail("singularity guards must be > 0");
  }
  if (!nonneg(s.coincident_tolerance) || !nonneg(s.min_segment_length_m)) return fail("path tolerances must be >= 0");
  if (!nonneg(s.still_max_base_m) || !nonneg(s.still_max_yaw_rad) || !nonneg(s.still_min_arm_rad)) {
    return fail("still_max_base_m, still_max_yaw_rad and still_min_arm_rad must be >= 0");
  }
  if (!(s.densify_factor >= 1.0) || s.max_pieces_per_edge < 1) return fail("densify_factor must be >= 1 and max_pieces_per_edge >= 1");
  if (!pos(s.piece_length_m) || !pos(s.piece_arm_motion_rad) || s.max_edges_per_piece < 1 ||
      !(s.piece_duration_ratio >= 1.0)) {
    return fail("piece_length_m and piece_arm_motion_rad must be > 0, max_edges_per_piece >= 1 and piece_duration_ratio >= 1");
  }
  if (s.samples_per_edge < 1 || s.samples_per_edge > 64) return fail("samples_per_edge not in [1, 64]");
  if (!pos(s.initial_speed_fraction) || s.initial_speed_fraction > 1.0) return fail("initial_speed_fraction not in (0, 1]");
  if (!pos(s.min_initial_piece_duration_s)) return fail("min_initial_piece_duration_s must be > 0");
  if (s.max_iterations < 1) return fail("max_iterations must be >= 1");
  if (!pos(s.relative_cost_tolerance) || s.relative_cost_past < 1) return fail("relative cost test needs tolerance > 0 and past >= 1");
  if (s.memory_size < 3 || s.memory_size > 64) return fail("memory_size not in [3, 64]");
  if (s.max_line_search < 1) return fail("max_line_search must be >= 1");
  if (!pos(s.variable_scale)) return fail("variable_scale must be > 0");
  if (s.max_restarts < 0 || !nonneg(s.restart_min_decrease)) return fail("max_restarts and restart_min_decrease must be >= 0");
  if (!nonneg(s.verify_tolerance) || !std::isfinite(s.verify_step_s)) {
    return fail("verify_tolerance must be >= 0 and verify_step_s finite");
  }
  return true;
}

MidEnd::MidEnd(const RobotModel& robot, MidendSettings settings)
    : MidEnd(MidendLimits::from_robot(robot), std::move(settings)) {}

MidEnd::MidEnd(const MidendLimits& limits, MidendSettings settings)
    : limits_(limits), settings_(std::move(settings)) {}

MidendResult MidEnd::solve(const planner::WholeBodyPath& path, const planner::Deadline& deadline,
                           const StartDerivatives& start) const {
  const auto start_time = Clock::now();
  MidendResult r;
  std::string why;
  if (!limits_.valid(&why)) {
    r.status = planner::Status::kInvalidRobotLimits;
    r.message = why;
    finish(r, start_time);
    return r;
  }
  if (!validate_settings(settings_, &why)) {
    r.status = planner::Status::kInvalidInput;
    r.message = "settings: " + why;
    finish(r, start_time);
    return r;
  }
  if (!start.velocity.allFinite() || !start.acceleration.allFinite()) {
    r.status = planner::Status::kInvalidStart;
    r.message = "start velocity or acceleration not finite";
    finish(r, start_time);
    return r;
  }
  ReferenceBuild ref = build_reference_path(path, limits_, settings_, start);
  if (ref.outcome == ReferenceOutcome::kEmpty || ref.outcome == ReferenceOutcome::kMalformed) {
    r.status = planner::Status::kInvalidInput;
    r.message = ref.message;
    finish(r, start_time);
    return r;
  }
  if (ref.outcome == ReferenceOutcome::kNoMotion && !(start.velocity.isZero(0.0) && start.acceleration.isZero(0.0))) {
    r.status = planner::Status::kInvalidStart;
    r.message = ref.message + ", but the start moves: a path without motion cannot continue it";
    finish(r, start_time);
    return r;
  }
  if (ref.outcome == ReferenceOutcome::kNoMotion) {
    TrajectoryPiece hold;
    hold.duration_s = settings_.min_initial_piece_duration_s;
    hold.coeffs.row(0) << ref.single.base.x_m, ref.single.base.y_m, ref.single.q_rad.transpose();
    TrajectoryResult tr = Trajectory::create({hold}, ref.single.base.yaw_rad);
    r.status = tr.ok() ? planner::Status::kTrivialPath : planner::Status::kNumericalFailure;
    r.message = tr.ok() ? ref.message + ": stationary trajectory" : tr.error;
    r.trajectory = std::move(tr.trajectory);
    r.num_pieces = 1;
    r.num_segments = 1;
    finish(r, start_time);
    return r;
  }

  MidendProblem problem(std::move(ref.path), limits_, settings_);
  r.num_pieces = problem.num_pieces();
  r.num_segments = problem.num_segments();
  r.num_variables = problem.num_variables();
  const Eigen::VectorXd x0 = problem.initial_guess();
  const double f0 = problem.evaluate(x0.data(), nullptr, &r.initial_cost);
  r.prepare_s = seconds_since(start_time);
  if (!std::isfinite(f0)) {
    r.status = planner::Status::kNumericalFailure;
    r.message = "the initial guess has a non-finite cost (singular MINCO system?)";
    finish(r, start_time);
    return r;
  }

  const int n = problem.num_variables();
  LbfgsDriver driver(n);
  if (!driver.ok()) {
    r.status = planner::Status::kOptimizerFailed;
    r.message = "lbfgs_malloc failed";
    finish(r, start_time);
    return r;
  }
  const double scale = settings_.variable_scale;
  driver.set_x(x0, scale);
  lbfgs_parameter_t param = lbfgs_parameters(settings_);
  int evaluations = 0;
  const LbfgsDriver::Objective objective = [&](const double* x, double* g) {
    ++evaluations;
    return problem.evaluate(x, g, nullptr);
  };
  const auto t_opt = Clock::now();
  // Restarts: on these stiff costs a run often ends (relative-decrease test or a stalled line
  // search) while the curvature memory is stale, not at a minimum. Restart from the last iterate
  // with a fresh memory while the previous run still decreased the cost noticeably.
  LbfgsDriver::Run run;
  double f_run_start = f0;
  for (int k = 0;; ++k) {
    param.max_iterations = settings_.max_iterations - r.iterations;
    run = driver.run(param, objective, {}, deadline);
    r.iterations += run.iterations;
    const int code = run.code;
    const bool stopped_early = code == LBFGS_SUCCESS || code == LBFGS_STOP ||
                               code == LBFGS_ALREADY_MINIMIZED || lbfgs_code_is_stall(code);
    if (!stopped_early || k >= settings_.max_restarts || r.iterations >= settings_.max_iterations) break;
    const Eigen::VectorXd x_end = driver.x();
    const double f_run_end = problem.evaluate(x_end.data(), nullptr, nullptr);
    ++evaluations;
    if (!std::isfinite(f_run_end) ||
        f_run_start - f_run_end <= settings_.restart_min_decrease * std::abs(f_run_end)) {
      break;
    }
    f_run_start = f_run_end;
  }
  const int code = run.code;
  r.optimize_s = seconds_since(t_opt);
  r.lbfgs_code = code;
  r.evaluations = evaluations;

  const Eigen::VectorXd x1 = driver.x();
  const double f1 = problem.evaluate(x1.data(), nullptr, &r.final_cost);
  const std::string detail = std::string("lbfgs: ") + lbfgs_code_to_string(code);
  if (!std::isfinite(f1)) {
    r.status = planner::Status::kNumericalFailure;
    r.message = detail + "; final cost is not finite";
  } else if (code == LBFGS_SUCCESS || code == LBFGS_STOP || code == LBFGS_ALREADY_MINIMIZED) {
    r.status = planner::Status::kConverged;
  } else if (code == LBFGSERR_CANCELED && run.stop == LbfgsStop::kCanceled) {
    r.status = planner::Status::kCanceled;
  } else if (code == LBFGSERR_CANCELED && run.stop == LbfgsStop::kDeadline) {
    r.status = planner::Status::kTimeout;
  } else if (code == LBFGSERR_MAXIMUMITERATION) {
    r.status = planner::Status::kIterationLimit;
  } else if (lbfgs_code_is_stall(code) && f1 < f0) {
    r.status = planner::Status::kConvergedWithWarning;
  } else {
    r.status = planner::Status::kOptimizerFailed;
  }
  if (r.message.empty()) r.message = detail;

  if (has_trajectory(r.status)) {
    TrajectoryResult tr = Trajectory::create(problem.pieces(x1.data()), problem.start_yaw_rad());
    std::string violation;
    if (tr.ok() && settings_.verify_step_s > 0.0) {
      std::vector<int> piece_segment;
      for (int s = 0; s < problem.num_segments(); ++s) {
        piece_segment.insert(piece_segment.end(), problem.reference().segments[s].num_pieces(), s);
      }
      violation = detail::verify_trajectory(*tr.trajectory, piece_segment, limits_,
                                            settings_.verify_tolerance, settings_.verify_step_s);
    }
    if (tr.ok() && !violation.empty()) {
      r.message = std::string("optimizer: ") + to_string(r.status) + ", " + detail + "; rejected: " + violation;
      r.status = planner::Status::kConstraintViolation;
    } else if (tr.ok()) {
      r.trajectory = std::move(tr.trajectory);
      // Handed over with the time scale folded into the piece times (sigma = 0): the back-end's
      // L-BFGS starts from a neutral global time scale, whatever sigma this solve ended with.
      Eigen::VectorXd x_handed;
      if (!problem.decision_from_trajectory(*r.trajectory, x_handed)) x_handed = x1;
      r.solution = MidendSolution{problem.reference(), settings_, std::move(x_handed)};
    } else {
      r.status = planner::Status::kNumericalFailure;
      r.message = detail + "; trajectory rejected: " + tr.error;
    }
  }
  finish(r, start_time);
  return r;
}

std::optional<MidendSolution> MidEnd::solution_for(const planner::WholeBodyPath& path, const Trajectory& trajectory,
                                                   const StartDerivatives& start) const {
  ReferenceBuild ref = build_reference_path(path, limits_, settings_, start);
  if (ref.outcome != ReferenceOutcome::kOk || !limits_.valid(nullptr)) return std::nullopt;
  MidendProblem problem(std::move(ref.path), limits_, settings_);
  Eigen::VectorXd x;
  if (!problem.decision_from_trajectory(trajectory, x)) return std::nullopt;
  return MidendSolution{problem.reference(), settings_, std::move(x)};
}

}  // namespace porter::midend
