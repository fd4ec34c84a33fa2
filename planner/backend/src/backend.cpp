#include "porter/backend/backend.hpp"

#include <lbfgs.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <string>

#include "porter/midend/lbfgs_codes.hpp"
#include "porter/midend/lbfgs_driver.hpp"
#include "porter/midend/midend.hpp"
#include "porter/midend/reference_path.hpp"

namespace porter::backend {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

struct SolveContext {
  BackendProblem* problem = nullptr;
  double scale = 1.0;              ///< x = scale * y (y: the solver's variables)
  Eigen::VectorXd x;               ///< scratch
  Clock::time_point start;
  double budget_s = 0.0;
  int iterations = 0;
  int evaluations = 0;
  double safety_s = 0.0;
  double self_s = 0.0;
  bool budget_hit = false;
  int safe_streak = 0;          ///< consecutive iterations with zero collision cost
  int stop_after_safe = 0;
  bool stopped_safe = false;
  double last_safety = 0.0;     ///< J_s at the last evaluation
  bool expired = false;         ///< the budget ran out inside a line search
  bool have_initial = false;
  BackendCost initial;          ///< at the first evaluation (the warm start)
  double best_f = std::numeric_limits<double>::infinity();
  BackendCost best;             ///< at the lowest cost evaluated (the returned iterate's, usually)
  BackendCost cost;
  // In-loop kernel re-check (BackendSettings::recheck_every_iterations).
  const planner::CollisionChecker* checker = nullptr;
  int recheck_every = 0;
  int round_iterations = 0;     ///< iterations of the current L-BFGS round
  int rechecks = 0;
  double check_s = 0.0;
  bool found_free = false;      ///< an accepted iterate passed the re-check: stopped there
  int refresh_every = 0;        ///< BackendSettings::refresh_every_iterations
  bool refresh_requested = false;  ///< the round ended to refresh the safety term's decisions
  // The first-step probe's evaluation at the round's start (first_step_scale), handed to L-BFGS's
  // own first evaluation of the same point instead of computing it again.
  bool have_cached = false;
  Eigen::VectorXd cached_x, cached_g;
  double cached_f = 0.0;
  BackendCost cached_cost;
  int probes = 0;
  // Cost of the round's current iterate (+infinity before its first evaluation): the cutoff of
  // BackendSettings::skip_safety_above_current.
  double current_f = std::numeric_limits<double>::infinity();
  bool use_cutoff = false;  ///< backtracking line searches only (More-Thuente interpolates f)
  int skipped = 0;
};

/// What an evaluation reports once the budget is gone: the line search cannot accept a step, so
/// liblbfgs reverts to the last accepted iterate and stops (an iteration can be long: each
/// evaluation costs milliseconds and a line search may need several).
constexpr double kExpiredCost = 1e300;

/// One evaluation of the problem, counted in ctx: evaluations, J_s skips and the terms' times.
double counted_evaluate(SolveContext& ctx, const double* x, double* g, BackendCost* cost,
                        double cutoff = std::numeric_limits<double>::infinity()) {
  ++ctx.evaluations;
  const double f = ctx.problem->evaluate(x, g, cost, cutoff);
  if (cost->safety_skipped) ++ctx.skipped;
  ctx.safety_s += cost->safety_stats.time_s;
  ctx.self_s += cost->self_stats.time_s;
  return f;
}

lbfgsfloatval_t evaluate_cb(void* instance, const lbfgsfloatval_t* y, lbfgsfloatval_t* g,
                            const int n, const lbfgsfloatval_t /*step*/) {
  auto* ctx = static_cast<SolveContext*>(instance);
  if (ctx->have_initial && !ctx->expired && seconds_since(ctx->start) >= ctx->budget_s) ctx->expired = true;
  if (ctx->expired) {
    if (g) std::fill(g, g + n, 0.0);
    return kExpiredCost;
  }
  for (int k = 0; k < n; ++k) ctx->x[k] = ctx->scale * y[k];
  double f = 0.0;
  if (ctx->have_cached && g && (ctx->x - ctx->cached_x).norm() <= 1e-12 * (1.0 + ctx->cached_x.norm())) {
    // Already evaluated (and counted) by the first-step probe.
    ctx->have_cached = false;
    f = ctx->cached_f;
    ctx->cost = ctx->cached_cost;
    for (int k = 0; k < n; ++k) g[k] = ctx->cached_g[k] * ctx->scale;
  } else {
    f = counted_evaluate(*ctx, ctx->x.data(), g, &ctx->cost,
                         ctx->use_cutoff ? ctx->current_f : std::numeric_limits<double>::infinity());
    if (g) {
      for (int k = 0; k < n; ++k) g[k] *= ctx->scale;
    }
  }
  ctx->last_safety = ctx->cost.safety;
  if (!std::isfinite(ctx->current_f)) ctx->current_f = f;  // the round's starting point
  if (!ctx->have_initial) {
    ctx->have_initial = true;
    ctx->initial = ctx->cost;
  }
  if (f < ctx->best_f) {
    ctx->best_f = f;
    ctx->best = ctx->cost;
  }
  return f;
}

/// What progress_cb returns to stop L-BFGS; lbfgs() returns it verbatim. Not 1: that is
/// LBFGS_STOP, the relative-cost test's own code, and a stop at the budget was reported as
/// convergence ("stopped by the relative cost decrease test") before.
constexpr int kStop = LBFGSERR_CANCELED;

int progress_cb(void* instance, const lbfgsfloatval_t* y, const lbfgsfloatval_t* /*g*/,
                const lbfgsfloatval_t fx, const lbfgsfloatval_t /*xnorm*/,
                const lbfgsfloatval_t /*gnorm*/, const lbfgsfloatval_t /*step*/, int n, int k,
                int /*ls*/) {
  auto* ctx = static_cast<SolveContext*>(instance);
  ctx->round_iterations = k;
  ctx->current_f = fx;
  // The re-check at a low rate: stop at the first accepted iterate the kernel check passes. Not
  // where the safety term proves a collision (SafetyStats::certain_collision; ctx->cost is the
  // accepted iterate's, the line search's last evaluation): the check could only fail there.
  if (ctx->checker && ctx->recheck_every > 0 && k % ctx->recheck_every == 0 &&
      !ctx->cost.safety_stats.certain_collision) {
    const auto t0 = Clock::now();
    for (int i = 0; i < n; ++i) ctx->x[i] = ctx->scale * y[i];
    const std::optional<Trajectory> traj = ctx->problem->trajectory(ctx->x.data());
    ++ctx->rechecks;
    const bool free = traj && !ctx->checker->check_trajectory(*traj).in_collision;
    ctx->check_s += seconds_since(t0);
    if (free) {
      ctx->found_free = true;
      return kStop;
    }
  }
  // The last evaluation of an iteration is the accepted point's.
  ctx->safe_streak = ctx->last_safety == 0.0 ? ctx->safe_streak + 1 : 0;
  if (ctx->stop_after_safe > 0 && ctx->safe_streak >= ctx->stop_after_safe) {
    ctx->stopped_safe = true;
    return kStop;
  }
  if (seconds_since(ctx->start) >= ctx->budget_s) {
    ctx->budget_hit = true;
    return kStop;
  }
  if (ctx->refresh_every > 0 && k >= ctx->refresh_every) {
    ctx->refresh_requested = true;
    return kStop;
  }
  return 0;
}

/// Chooses the solver's variable scale for the next L-BFGS round (BackendSettings::
/// probe_first_step): liblbfgs's first trial step moves x by exactly ctx.scale along -g, so the
/// scale is set to the length of the Newton step along -g, |g| / c, with c the curvature of the
/// cost along -g from a gradient difference over kProbeStep (at most max_scale; max_scale when c is
/// not positive). y is rescaled to keep x. The evaluation at x is cached for L-BFGS's first one.
void first_step_scale(SolveContext& ctx, double* y, int n, double max_scale) {
  constexpr double kProbeStep = 1e-6;   // x units; the cost's curvature is steady below ~1e-5
  constexpr double kMinScale = 1e-9;
  Eigen::VectorXd x0(n), g0(n), x1(n), g1(n);
  for (int k = 0; k < n; ++k) x0[k] = ctx.scale * y[k];
  BackendCost c0, c1;
  const double f0 = counted_evaluate(ctx, x0.data(), g0.data(), &c0);
  double new_scale = max_scale;
  const double gn = g0.norm();
  if (std::isfinite(f0) && gn > 0.0) {
    x1 = x0 - (kProbeStep / gn) * g0;
    ++ctx.probes;
    const double f1 = counted_evaluate(ctx, x1.data(), g1.data(), &c1);
    const double c = std::isfinite(f1) ? -(g1 - g0).dot(g0) / (gn * kProbeStep) : 0.0;
    if (c > 0.0) new_scale = std::clamp(gn / c, kMinScale, max_scale);
  }
  for (int k = 0; k < n; ++k) y[k] = x0[k] / new_scale;
  ctx.scale = new_scale;
  ctx.have_cached = std::isfinite(f0);
  ctx.cached_x = x0;
  ctx.cached_g = g0;
  ctx.cached_f = f0;
  ctx.cached_cost = c0;
}

void finish(BackendResult& r, const planner::CollisionChecker* checker, Clock::time_point start) {
  if (r.ok() && checker) {
    const auto t0 = Clock::now();
    const planner::CollisionResult c = checker->check_trajectory(*r.trajectory);
    r.check = c.in_collision ? SafetyCheck::kInCollision : SafetyCheck::kCollisionFree;
    r.collision_link = c.link;
    r.check_s = seconds_since(t0);
  }
  r.elapsed_s = seconds_since(start);
}

}  // namespace

bool validate_settings(const BackendSettings& s, std::string* why) {
  auto fail = [why](const char* m) {
    if (why) *why = m;
    return false;
  };
  std::string inner;
  if (!midend::validate_settings(s.problem, &inner)) {
    if (why) *why = "problem: " + inner;
    return false;
  }
  if (s.max_iterations < 1) return fail("max_iterations must be >= 1");
  if (!(s.relative_cost_tolerance > 0.0) || s.relative_cost_past < 1) return fail("relative cost test needs tolerance > 0 and past >= 1");
  if (s.memory_size < 3 || s.memory_size > 64) return fail("memory_size not in [3, 64]");
  if (s.max_line_search < 1) return fail("max_line_search must be >= 1");
  if (!(s.default_time_budget_s > 0.0) || !std::isfinite(s.default_time_budget_s)) return fail("default_time_budget_s must be > 0");
  if (s.stop_after_safe_iterations < 0) return fail("stop_after_safe_iterations must be >= 0");
  if (!(s.variable_scale > 0.0) || !std::isfinite(s.variable_scale)) return fail("variable_scale must be > 0");
  if (s.recheck_every_iterations < 0) return fail("recheck_every_iterations must be >= 0");
  if (!(s.weight_escalation_factor >= 1.0) || !std::isfinite(s.weight_escalation_factor)) return fail("weight_escalation_factor must be >= 1");
  if (s.max_weight_escalations < 0) return fail("max_weight_escalations must be >= 0");
  if (s.refresh_every_iterations < 0) return fail("refresh_every_iterations must be >= 0");
  return true;
}

BackEnd::BackEnd(const RobotModel& robot, BackendSettings settings)
    : BackEnd(midend::MidendLimits::from_robot(robot), std::move(settings)) {}

BackEnd::BackEnd(const midend::MidendLimits& limits, BackendSettings settings)
    : limits_(limits), settings_(std::move(settings)) {}

BackendResult BackEnd::solve(const planner::WholeBodyPath& path, const Trajectory& warm_start,
                             const OccupancyGrid& map_W, SafetyTerm& safety, double time_budget_s,
                             const planner::CollisionChecker* checker, SelfCollisionTerm* self_collision) const {
  const auto start = Clock::now();
  BackendResult r;
  r.safety_term = safety.name();
  std::string why;
  if (!limits_.valid(&why)) {
    r.message = "robot limits: " + why;
    finish(r, checker, start);
    return r;
  }
  if (!validate_settings(settings_, &why)) {
    r.message = "settings: " + why;
    finish(r, checker, start);
    return r;
  }
  const double budget_s = time_budget_s > 0.0 ? time_budget_s : settings_.default_time_budget_s;
  midend::ReferenceBuild ref = midend::build_reference_path(path, limits_, settings_.problem);
  if (ref.outcome != midend::ReferenceOutcome::kOk) {
    r.message = "path: " + ref.message;
    finish(r, checker, start);
    return r;
  }
  safety.prepare(map_W, warm_start);
  if (self_collision) self_collision->prepare(warm_start);
  BackendProblem problem(std::move(ref.path), limits_, settings_.problem, safety, self_collision);
  r.num_pieces = problem.num_pieces();
  r.num_variables = problem.num_variables();
  Eigen::VectorXd x0;
  if (!problem.decision_from_trajectory(warm_start, x0)) {
    r.status = BackendStatus::kWarmStartMismatch;
    r.message = "warm start has " + std::to_string(warm_start.num_pieces()) + " pieces, the problem " +
                std::to_string(problem.num_pieces()) + " (or a piece's direction differs)";
    finish(r, checker, start);
    return r;
  }
  const int n = problem.num_variables();
  midend::LbfgsBuffer x(n);
  if (x.data == nullptr) {
    r.status = BackendStatus::kOptimizerFailed;
    r.message = "lbfgs_malloc failed";
    finish(r, checker, start);
    return r;
  }
  const double scale = settings_.variable_scale;
  for (int k = 0; k < n; ++k) x.data[k] = x0[k] / scale;  // the solver's y
  lbfgs_parameter_t param = midend::lbfgs_parameters(settings_);

  SolveContext ctx;
  ctx.problem = &problem;
  ctx.scale = scale;
  ctx.x.resize(n);
  ctx.start = start;
  ctx.budget_s = budget_s;
  ctx.stop_after_safe = settings_.stop_after_safe_iterations;
  ctx.checker = checker;
  ctx.recheck_every = settings_.recheck_every_iterations;
  ctx.refresh_every = settings_.refresh_every_iterations;
  ctx.use_cutoff = settings_.skip_safety_above_current && settings_.line_search != midend::LineSearch::kMoreThuente;
  const auto t_opt = Clock::now();
  lbfgsfloatval_t fx = 0.0;
  int code = LBFGS_SUCCESS;
  // Rounds: L-BFGS from the current iterate; when it stops short of the budget with the re-check
  // still failing, the safety weight is raised and it continues (see BackendSettings). Each round
  // starts with the safety term's decisions refreshed (its cost is continuous within a round).
  double weight_scale = 1.0;
  int rounds = 0;
  int escalations = 0;
  bool escalation_cut = false;  ///< the budget ended before an escalation the re-check called for
  for (;;) {
    problem.set_safety_scale(weight_scale);
    safety.refresh_decisions();
    if (settings_.probe_first_step) first_step_scale(ctx, x.data, n, scale);
    ctx.best_f = std::numeric_limits<double>::infinity();
    ctx.current_f = std::numeric_limits<double>::infinity();
    ctx.round_iterations = 0;
    ctx.refresh_requested = false;
    param.max_iterations = settings_.max_iterations - ctx.iterations;  // the cap is over all rounds
    code = lbfgs(n, x.data, &fx, evaluate_cb, progress_cb, &ctx, &param);
    ctx.iterations += ctx.round_iterations;
    ++rounds;
    if (ctx.found_free || ctx.stopped_safe || ctx.budget_hit || ctx.expired) break;
    if (ctx.refresh_requested) {
      // Ended only to refresh: continue from here with the same weight unless out of budget.
      if (seconds_since(start) >= budget_s) {
        ctx.budget_hit = true;
        break;
      }
      if (ctx.iterations >= settings_.max_iterations) {
        code = LBFGSERR_MAXIMUMITERATION;
        break;
      }
      continue;
    }
    if (!checker) break;
    if (escalations >= settings_.max_weight_escalations || !std::isfinite(fx)) break;
    if (seconds_since(start) >= budget_s) {
      escalation_cut = true;  // the round ended just as the budget did
      break;
    }
    if (ctx.iterations >= settings_.max_iterations) break;
    const bool stopped = code == LBFGS_SUCCESS || code == LBFGS_STOP || code == LBFGS_ALREADY_MINIMIZED ||
                         code == LBFGSERR_MAXIMUMITERATION || midend::lbfgs_code_is_stall(code);
    if (!stopped) break;
    for (int k = 0; k < n; ++k) ctx.x[k] = ctx.scale * x.data[k];
    const auto t_check = Clock::now();
    const std::optional<Trajectory> traj = problem.trajectory(ctx.x.data());
    ++ctx.rechecks;
    const bool free = traj && !checker->check_trajectory(*traj).in_collision;
    ctx.check_s += seconds_since(t_check);
    if (free) {
      ctx.found_free = true;
      break;
    }
    weight_scale *= settings_.weight_escalation_factor;
    ++escalations;
  }
  r.optimize_s = seconds_since(t_opt);
  r.lbfgs_code = code;
  r.iterations = ctx.iterations;
  r.evaluations = ctx.evaluations;
  r.safety_s = ctx.safety_s;
  r.self_collision_s = ctx.self_s;
  r.rechecks = ctx.rechecks;
  r.probe_evaluations = ctx.probes;
  r.safety_skips = ctx.skipped;
  r.recheck_s = ctx.check_s;
  r.rounds = rounds;
  r.safety_weight_scale = weight_scale;
  r.initial_cost = ctx.initial;
  const double f0 = ctx.initial.total();
  if (!ctx.have_initial || !std::isfinite(f0)) {
    r.status = BackendStatus::kNumericalFailure;
    r.message = "the warm start has a non-finite cost";
    finish(r, checker, start);
    return r;
  }

  Eigen::VectorXd x1(n);
  for (int k = 0; k < n; ++k) x1[k] = ctx.scale * x.data[k];
  // liblbfgs returns its last accepted iterate; its cost was evaluated already unless it is not
  // the lowest one seen (then evaluate it again).
  double f1 = fx;
  if (fx == ctx.best_f) {
    r.final_cost = ctx.best;
  } else {
    f1 = problem.evaluate(x1.data(), nullptr, &r.final_cost);
  }
  const std::string detail = std::string("lbfgs: ") + midend::lbfgs_code_to_string(code);
  if (!std::isfinite(f1)) {
    r.status = BackendStatus::kNumericalFailure;
    r.message = detail + "; final cost is not finite";
  } else if (escalation_cut) {
    // L-BFGS converged at this weight, but the solve would have raised it had the budget allowed:
    // report the budget, not convergence (the re-check below decides success either way).
    r.status = BackendStatus::kTimeBudgetExceeded;
    r.message = detail + "; the budget ended before the safety weight could be raised";
    if (escalations > 0) r.message += " (weight x" + std::to_string(static_cast<int>(weight_scale)) + ")";
  } else if (code == LBFGS_SUCCESS || code == LBFGS_STOP || code == LBFGS_ALREADY_MINIMIZED ||
             (code == LBFGSERR_CANCELED && (ctx.stopped_safe || ctx.found_free))) {
    r.status = BackendStatus::kConverged;
  } else if ((code == LBFGSERR_CANCELED && ctx.budget_hit) || ctx.expired) {
    r.status = BackendStatus::kTimeBudgetExceeded;
  } else if (code == LBFGSERR_MAXIMUMITERATION) {
    r.status = BackendStatus::kIterationLimit;
  } else if (midend::lbfgs_code_is_stall(code) && (f1 < f0 || rounds > 1)) {
    r.status = BackendStatus::kConvergedWithWarning;
  } else {
    r.status = BackendStatus::kOptimizerFailed;
  }
  if (r.message.empty()) {
    r.message = detail;
    if (ctx.stopped_safe) r.message += " (collision term zero: stopped early)";
    if (ctx.found_free) r.message += " (kernel re-check passed: stopped there)";
    if (escalations > 0) r.message += "; safety weight x" + std::to_string(static_cast<int>(weight_scale));
  }
  if (has_trajectory(r.status)) {
    std::optional<Trajectory> traj = problem.trajectory(x1.data());
    if (traj) {
      r.trajectory = std::move(traj);
    } else {
      r.status = BackendStatus::kNumericalFailure;
      r.message = detail + "; trajectory rejected";
    }
  }
  finish(r, checker, start);
  return r;
}

}  // namespace porter::backend
