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

struct SolveContext {
  MidendProblem* problem = nullptr;
  double scale = 1.0;          ///< x = scale * y, y being liblbfgs' variables
  Eigen::VectorXd x;           ///< workspace: the unscaled point

  Clock::time_point start;
  double budget_s = 0.0;
  int iterations = 0;
  int evaluations = 0;
  bool budget_hit = false;
};

lbfgsfloatval_t evaluate_cb(void* instance, const lbfgsfloatval_t* y, lbfgsfloatval_t* g,
                            const int n, const lbfgsfloatval_t /*step*/) {
  auto* ctx = static_cast<SolveContext*>(instance);
  ++ctx->evaluations;
  ctx->x = ctx->scale * Eigen::Map<const Eigen::VectorXd>(y, n);
  const double f = ctx->problem->evaluate(ctx->x.data(), g, nullptr);
  Eigen::Map<Eigen::VectorXd>(g, n) *= ctx->scale;
  return f;
}

int progress_cb(void* instance, const lbfgsfloatval_t* /*x*/, const lbfgsfloatval_t* /*g*/,
                const lbfgsfloatval_t /*fx*/, const lbfgsfloatval_t /*xnorm*/,
                const lbfgsfloatval_t /*gnorm*/, const lbfgsfloatval_t /*step*/, int /*n*/, int k,
                int /*ls*/) {
  auto* ctx = static_cast<SolveContext*>(instance);
  ctx->iterations = k;
  if (seconds_since(ctx->start) >= ctx->budget_s) {
    ctx->budget_hit = true;
    return LBFGSERR_CANCELED;  // any non-zero value is returned verbatim by lbfgs()
  }
  return 0;
}

void finish(MidendResult& r, const TrajectoryValidator& validator, Clock::time_point start) {
  if (r.ok() && validator) {
    const auto t0 = Clock::now();
    r.execution = validator(*r.trajectory) ? Execution::kDirect : Execution::kNeedsBackend;
    r.validate_s = seconds_since(t0);
  }
  r.elapsed_s = seconds_since(start);
}

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
  if (!(s.rest_densify_factor == 0.0 || (s.rest_densify_factor > 0.0 && s.rest_densify_factor <= s.densify_factor))) {
    return fail("rest_densify_factor must be 0 (off) or in (0, densify_factor]");
  }
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
  if (!pos(s.default_time_budget_s)) return fail("default_time_budget_s must be > 0");
  if (!nonneg(s.verify_tolerance) || !std::isfinite(s.verify_step_s)) {
    return fail("verify_tolerance must be >= 0 and verify_step_s finite");
  }
  return true;
}

MidEnd::MidEnd(const RobotModel& robot, MidendSettings settings)
    : MidEnd(MidendLimits::from_robot(robot), std::move(settings)) {}

MidEnd::MidEnd(const MidendLimits& limits, MidendSettings settings)
    : limits_(limits), settings_(std::move(settings)) {}

MidendResult MidEnd::solve(const planner::WholeBodyPath& path, double time_budget_s,
                           const TrajectoryValidator& validator) const {
  const auto start = Clock::now();
  MidendResult r;
  std::string why;
  if (!limits_.valid(&why)) {
    r.status = MidendStatus::kInvalidRobotLimits;
    r.message = why;
    finish(r, validator, start);
    return r;
  }
  if (!validate_settings(settings_, &why)) {
    r.status = MidendStatus::kInvalidInput;
    r.message = "settings: " + why;
    finish(r, validator, start);
    return r;
  }
  const double budget_s = time_budget_s > 0.0 ? time_budget_s : settings_.default_time_budget_s;

  ReferenceBuild ref = build_reference_path(path, limits_, settings_);
  if (ref.outcome == ReferenceOutcome::kEmpty || ref.outcome == ReferenceOutcome::kMalformed) {
    r.status = MidendStatus::kInvalidInput;
    r.message = ref.message;
    finish(r, validator, start);
    return r;
  }
  if (ref.outcome == ReferenceOutcome::kNoMotion) {
    TrajectoryPiece hold;
    hold.duration_s = settings_.min_initial_piece_duration_s;
    hold.coeffs.row(0) << ref.single.base.x_m, ref.single.base.y_m, ref.single.q_rad.transpose();
    TrajectoryResult tr = Trajectory::create({hold}, ref.single.base.yaw_rad);
    r.status = tr.ok() ? MidendStatus::kTrivialPath : MidendStatus::kNumericalFailure;
    r.message = tr.ok() ? ref.message + ": stationary trajectory" : tr.error;
    r.trajectory = std::move(tr.trajectory);
    r.num_pieces = 1;
    r.num_segments = 1;
    finish(r, validator, start);
    return r;
  }

  MidendProblem problem(std::move(ref.path), limits_, settings_);
  r.num_pieces = problem.num_pieces();
  r.num_segments = problem.num_segments();
  r.num_variables = problem.num_variables();
  const Eigen::VectorXd x0 = problem.initial_guess();
  const double f0 = problem.evaluate(x0.data(), nullptr, &r.initial_cost);
  if (!std::isfinite(f0)) {
    r.status = MidendStatus::kNumericalFailure;
    r.message = "the initial guess has a non-finite cost (singular MINCO system?)";
    finish(r, validator, start);
    return r;
  }

  const int n = problem.num_variables();
  LbfgsBuffer x(n);
  if (x.data == nullptr) {
    r.status = MidendStatus::kOptimizerFailed;
    r.message = "lbfgs_malloc failed";
    finish(r, validator, start);
    return r;
  }
  const double scale = settings_.variable_scale;
  Eigen::Map<Eigen::VectorXd>(x.data, n) = x0 / scale;

  lbfgs_parameter_t param = lbfgs_parameters(settings_);

  SolveContext ctx;
  ctx.problem = &problem;
  ctx.scale = scale;
  ctx.x.resize(n);
  ctx.start = start;
  ctx.budget_s = budget_s;
  const auto t_opt = Clock::now();
  // Restarts: on these stiff costs a run often ends (relative-decrease test or a stalled line
  // search) while the curvature memory is stale, not at a minimum. Restart from the last iterate
  // with a fresh memory while the previous run still decreased the cost noticeably.
  int code = 0;
  double f_run_start = f0;
  for (int run = 0;; ++run) {
    param.max_iterations = settings_.max_iterations - r.iterations;
    ctx.iterations = 0;
    lbfgsfloatval_t fx = 0.0;
    code = lbfgs(n, x.data, &fx, evaluate_cb, progress_cb, &ctx, &param);
    r.iterations += ctx.iterations;
    const bool stopped_early = code == LBFGS_SUCCESS || code == LBFGS_STOP ||
                               code == LBFGS_ALREADY_MINIMIZED || lbfgs_code_is_stall(code);
    if (!stopped_early || run >= settings_.max_restarts || r.iterations >= settings_.max_iterations) break;
    ctx.x = scale * Eigen::Map<const Eigen::VectorXd>(x.data, n);
    const double f_run_end = problem.evaluate(ctx.x.data(), nullptr, nullptr);
    ++ctx.evaluations;
    if (!std::isfinite(f_run_end) ||
        f_run_start - f_run_end <= settings_.restart_min_decrease * std::abs(f_run_end)) {
      break;
    }
    f_run_start = f_run_end;
  }
  r.optimize_s = seconds_since(t_opt);
  r.lbfgs_code = code;
  r.evaluations = ctx.evaluations;

  const Eigen::VectorXd x1 = scale * Eigen::Map<const Eigen::VectorXd>(x.data, n);
  const double f1 = problem.evaluate(x1.data(), nullptr, &r.final_cost);
  const std::string detail = std::string("lbfgs: ") + lbfgs_code_to_string(code);
  if (!std::isfinite(f1)) {
    r.status = MidendStatus::kNumericalFailure;
    r.message = detail + "; final cost is not finite";
  } else if (code == LBFGS_SUCCESS || code == LBFGS_STOP || code == LBFGS_ALREADY_MINIMIZED) {
    r.status = MidendStatus::kConverged;
  } else if (code == LBFGSERR_CANCELED && ctx.budget_hit) {
    r.status = MidendStatus::kTimeBudgetExceeded;
  } else if (code == LBFGSERR_MAXIMUMITERATION) {
    r.status = MidendStatus::kIterationLimit;
  } else if (lbfgs_code_is_stall(code) && f1 < f0) {
    r.status = MidendStatus::kConvergedWithWarning;
  } else {
    r.status = MidendStatus::kOptimizerFailed;
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
      r.status = MidendStatus::kConstraintViolation;
    } else if (tr.ok()) {
      r.trajectory = std::move(tr.trajectory);
    } else {
      r.status = MidendStatus::kNumericalFailure;
      r.message = detail + "; trajectory rejected: " + tr.error;
    }
  }
  finish(r, validator, start);
  return r;
}

}  // namespace porter::midend
