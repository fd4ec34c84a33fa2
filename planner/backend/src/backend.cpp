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
#include "porter/backend/piece_window.hpp"

namespace porter::backend {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

/// What the objective and the monitor share during one solve.
struct SolveContext {
  BackendProblem* problem = nullptr;
  int evaluations = 0;
  double safety_s = 0.0;
  double prefilter_s = 0.0;
  double self_s = 0.0;
  bool have_initial = false;
  BackendCost initial;          ///< at the first evaluation (the warm start)
  double best_f = std::numeric_limits<double>::infinity();
  BackendCost best;             ///< at the lowest cost evaluated (the returned iterate's, usually)
  BackendCost cost;
  // In-loop re-check (BackendSettings::recheck_every_iterations).
  const planner::TrajectoryAcceptance* acceptance = nullptr;
  int recheck_every = 0;
  int rechecks = 0;
  double check_s = 0.0;
  bool found_free = false;      ///< an accepted iterate passed the re-check: stopped there
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

/// One evaluation of the problem, counted in ctx: evaluations, J_s skips and the terms' times.
double counted_evaluate(SolveContext& ctx, const double* x, double* g, BackendCost* cost,
                        double cutoff = std::numeric_limits<double>::infinity()) {
  ++ctx.evaluations;
  const double f = ctx.problem->evaluate(x, g, cost, cutoff);
  if (cost->safety_skipped) ++ctx.skipped;
  ctx.safety_s += cost->safety_stats.time_s;
  ctx.prefilter_s += cost->safety_stats.prefilter_s;
  ctx.self_s += cost->self_stats.time_s;
  return f;
}

/// The driver's objective: the problem's cost, the probe's cached evaluation reused, the lowest
/// cost seen kept with its split.
double objective(SolveContext& ctx, const double* x, double* g, int n) {
  double f = 0.0;
  const Eigen::Map<const Eigen::VectorXd> xv(x, n);
  if (ctx.have_cached && g && (xv - ctx.cached_x).norm() <= 1e-12 * (1.0 + ctx.cached_x.norm())) {
    // Already evaluated (and counted) by the first-step probe.
    ctx.have_cached = false;
    f = ctx.cached_f;
    ctx.cost = ctx.cached_cost;
    for (int k = 0; k < n; ++k) g[k] = ctx.cached_g[k];
  } else {
    f = counted_evaluate(ctx, x, g, &ctx.cost,
                         ctx.use_cutoff ? ctx.current_f : std::numeric_limits<double>::infinity());
  }
  if (!std::isfinite(ctx.current_f)) ctx.current_f = f;  // the round's starting point
  if (!ctx.have_initial) {
    ctx.have_initial = true;
    ctx.initial = ctx.cost;
  }
  if (f < ctx.best_f) {
    ctx.best_f = f;
    ctx.best = ctx.cost;
  }
  return f;
}

/// The driver's monitor: the re-check at a low rate, stopping at the first accepted iterate that
/// passes. Not where the safety term proves a collision (SafetyStats::certain_collision; ctx.cost
/// is the accepted iterate's, the line search's last evaluation): the check could only fail there.
bool monitor(SolveContext& ctx, const double* x, double fx, int k) {
  ctx.current_f = fx;
  if (ctx.acceptance && ctx.recheck_every > 0 && k % ctx.recheck_every == 0 &&
      !ctx.cost.safety_stats.certain_collision) {
    const auto t0 = Clock::now();
    const std::optional<Trajectory> traj = ctx.problem->trajectory(x);
    ++ctx.rechecks;
    const bool free = traj && ctx.acceptance->check(*traj).accepted;
    ctx.check_s += seconds_since(t0);
    if (free) {
      ctx.found_free = true;
      return false;
    }
  }
  return true;
}

/// Chooses the solver's variable scale for the next L-BFGS round (BackendSettings::
/// probe_first_step): liblbfgs's first trial step moves x by exactly the scale along -g, so the
/// scale is set to the length of the Newton step along -g, |g| / c, with c the curvature of the
/// cost along -g from a gradient difference over kProbeStep (at most max_scale; max_scale when c is
/// not positive). The point is kept. The evaluation at x is cached for L-BFGS's first one.
void first_step_scale(SolveContext& ctx, midend::LbfgsDriver& driver, double max_scale) {
  constexpr double kProbeStep = 1e-6;   // x units; the cost's curvature is steady below ~1e-5
  constexpr double kMinScale = 1e-9;
  const int n = driver.size();
  const Eigen::VectorXd x0 = driver.x();
  Eigen::VectorXd g0(n), x1(n), g1(n);
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
  driver.set_x(x0, new_scale);
  ctx.have_cached = std::isfinite(f0);
  ctx.cached_x = x0;
  ctx.cached_g = g0;
  ctx.cached_f = f0;
  ctx.cached_cost = c0;
}

void finish(BackendResult& r, const planner::TrajectoryAcceptance* acceptance, Clock::time_point start) {
  if (r.ok() && acceptance) {
    const auto t0 = Clock::now();
    const planner::AcceptanceResult c = acceptance->check(*r.trajectory);
    r.check = c.accepted ? SafetyCheck::kCollisionFree : SafetyCheck::kInCollision;
    r.collision_link = c.link;
    r.check_s = seconds_since(t0);
  }
  r.elapsed_s = seconds_since(start);
}

bool is_stop_code(int code) {
  return code == LBFGS_SUCCESS || code == LBFGS_STOP || code == LBFGS_ALREADY_MINIMIZED;
}

/// How a sequence of L-BFGS rounds on one problem ended.
struct Rounds {
  midend::LbfgsDriver::Run run;
  int iterations = 0;
  int rounds = 0;
  int escalations = 0;
  double weight_scale = 1.0;
  bool escalation_cut = false;  ///< the budget ended before an escalation the re-check called for
};

/// Rounds: L-BFGS from the driver's point; when it stops short of the budget with the re-check
/// still failing, the safety weight is raised and it continues (see BackendSettings). Each round
/// starts with the safety term's decisions refreshed (its cost is continuous within a round).
/// `max_iterations` caps the iterations over all rounds.
Rounds run_rounds(const BackendSettings& settings, BackendProblem& problem, SafetyTerm& safety,
                  midend::LbfgsDriver& driver, SolveContext& ctx, const planner::Deadline& deadline,
                  const planner::TrajectoryAcceptance* acceptance, int max_iterations) {
  const int n = problem.num_variables();
  const double scale = settings.variable_scale;
  lbfgs_parameter_t param = midend::lbfgs_parameters(settings);
  const midend::LbfgsDriver::Objective objective = [&ctx, n](const double* x, double* g) {
    return backend::objective(ctx, x, g, n);
  };
  const midend::LbfgsDriver::Monitor watch = [&ctx](const double* x, double fx, int k) {
    return monitor(ctx, x, fx, k);
  };
  Rounds out;
  for (;;) {
    problem.set_safety_scale(out.weight_scale);
    safety.refresh_decisions();
    if (settings.probe_first_step) first_step_scale(ctx, driver, scale);
    ctx.best_f = std::numeric_limits<double>::infinity();
    ctx.current_f = std::numeric_limits<double>::infinity();
    param.max_iterations = max_iterations - out.iterations;
    out.run = driver.run(param, objective, watch, deadline);
    out.iterations += out.run.iterations;
    ++out.rounds;
    if (ctx.found_free || out.run.stop == midend::LbfgsStop::kDeadline || out.run.stop == midend::LbfgsStop::kCanceled ||
        driver.expired_in_line_search())
      break;
    if (!acceptance) break;
    if (out.escalations >= settings.max_weight_escalations || !std::isfinite(out.run.f)) break;
    if (deadline.expired()) {
      out.escalation_cut = true;  // the round ended just as the budget did
      break;
    }
    if (out.iterations >= max_iterations) break;
    const bool stopped = is_stop_code(out.run.code) || out.run.code == LBFGSERR_MAXIMUMITERATION ||
                         midend::lbfgs_code_is_stall(out.run.code);
    if (!stopped) break;
    const Eigen::VectorXd x_round = driver.x();
    const auto t_check = Clock::now();
    const std::optional<Trajectory> traj = problem.trajectory(x_round.data());
    ++ctx.rechecks;
    const bool free = traj && acceptance->check(*traj).accepted;
    ctx.check_s += seconds_since(t_check);
    if (free) {
      ctx.found_free = true;
      break;
    }
    out.weight_scale *= settings.weight_escalation_factor;
    ++out.escalations;
  }
  return out;
}

/// Adds one solve's counters to the result.
void add_counters(BackendResult& r, const SolveContext& ctx) {
  r.evaluations += ctx.evaluations;
  r.safety_s += ctx.safety_s;
  r.safety_prefilter_s += ctx.prefilter_s;
  r.self_collision_s += ctx.self_s;
  r.rechecks += ctx.rechecks;
  r.probe_evaluations += ctx.probes;
  r.safety_skips += ctx.skipped;
  r.recheck_s += ctx.check_s;
}

}  // namespace

bool validate_settings(const BackendSettings& s, std::string* why) {
  auto fail = [why](const char* m) {
    if (why) *why = m;
    return false;
  };
  if (s.max_iterations < 1) return fail("max_iterations must be >= 1");
  if (!(s.relative_cost_tolerance > 0.0) || s.relative_cost_past < 1) return fail("relative cost test needs tolerance > 0 and past >= 1");
  if (s.memory_size < 3 || s.memory_size > 64) return fail("memory_size not in [3, 64]");
  if (s.max_line_search < 1) return fail("max_line_search must be >= 1");
  if (!(s.variable_scale > 0.0) || !std::isfinite(s.variable_scale)) return fail("variable_scale must be > 0");
  if (s.recheck_every_iterations < 0) return fail("recheck_every_iterations must be >= 0");
  if (!(s.weight_escalation_factor >= 1.0) || !std::isfinite(s.weight_escalation_factor)) return fail("weight_escalation_factor must be >= 1");
  if (s.max_weight_escalations < 0) return fail("max_weight_escalations must be >= 0");
  if (s.window_grow_pieces < 0) return fail("window_grow_pieces must be >= 0");
  if (!(s.window_max_fraction > 0.0 && s.window_max_fraction <= 1.0)) return fail("window_max_fraction not in (0, 1]");
  if (!(s.window_cut_jerk_weight >= 0.0) || !std::isfinite(s.window_cut_jerk_weight)) return fail("window_cut_jerk_weight must be >= 0");
  return true;
}

BackEnd::BackEnd(const RobotModel& robot, BackendSettings settings)
    : BackEnd(midend::MidendLimits::from_robot(robot), std::move(settings)) {}

BackEnd::BackEnd(const midend::MidendLimits& limits, BackendSettings settings)
    : limits_(limits), settings_(std::move(settings)) {}

BackendResult BackEnd::solve(const midend::MidendSolution& warm_start, const OccupancyGrid& map_W, SafetyTerm& safety,
                             const planner::Deadline& deadline, const planner::TrajectoryAcceptance* acceptance,
                             SelfCollisionTerm* self_collision) const {
  const auto start = Clock::now();
  BackendResult r;
  r.safety_term = safety.name();
  std::string why;
  if (!limits_.valid(&why)) {
    r.message = "robot limits: " + why;
    finish(r, acceptance, start);
    return r;
  }
  if (!validate_settings(settings_, &why)) {
    r.message = "settings: " + why;
    finish(r, acceptance, start);
    return r;
  }
  if (!midend::validate_settings(warm_start.settings, &why)) {
    r.message = "the warm start's mid-end settings: " + why;
    finish(r, acceptance, start);
    return r;
  }
  BackendProblem problem(warm_start.reference, limits_, warm_start.settings, safety, self_collision);
  r.num_pieces = problem.num_pieces();
  r.num_variables = problem.num_variables();
  const std::optional<Trajectory> initial =
      warm_start.x.size() == problem.num_variables() ? problem.trajectory(warm_start.x.data()) : std::nullopt;
  if (!initial) {
    r.status = planner::Status::kWarmStartMismatch;
    r.message = "the warm start's decision vector has " + std::to_string(warm_start.x.size()) +
                " entries, the problem " + std::to_string(problem.num_variables()) + " (or it describes no trajectory)";
    finish(r, acceptance, start);
    return r;
  }

  r.rounds = 0;
  // Piece windows (piece_window.hpp, BackendSettings::window_grow_pieces): the pieces around the
  // places the acceptance test rejects are optimized with the rest held; the whole problem follows
  // only when a window cannot be solved on its own.
  std::optional<Trajectory> current = initial;
  Eigen::VectorXd x_full = warm_start.x;
  bool windows_done = false;  ///< every window passed: the spliced trajectory is the answer
  bool stop = false;          ///< budget or cancellation ended the windows
  bool capped = false;        ///< the iteration cap (over every window) ended them
  if (settings_.window_grow_pieces > 0 && acceptance) {
    const auto t_loc = Clock::now();
    const std::vector<bool> flagged = flag_pieces(*initial, *acceptance);
    std::vector<PieceWindow> windows = windows_around(flagged, warm_start.reference, settings_.window_grow_pieces);
    int covered = 0;
    for (const PieceWindow& w : windows) covered += w.size();
    r.window_localise_s = seconds_since(t_loc);
    r.window_flagged = static_cast<int>(std::count(flagged.begin(), flagged.end(), true));
    const bool use = !windows.empty() && covered <= settings_.window_max_fraction * problem.num_pieces();
    bool fallback = !use;
    for (std::size_t k = 0; use && k < windows.size() && !stop && !fallback; ++k) {
      PieceWindow w = windows[k];
      int grow = settings_.window_grow_pieces;
      for (;;) {
        if (r.iterations >= settings_.max_iterations) {
          capped = stop = true;
          break;
        }
        const auto t_prep = Clock::now();
        const std::optional<midend::ReferencePath> ref = window_reference(warm_start.reference, *current, w, settings_.window_cut_jerk_weight);
        const std::optional<Trajectory> cut = cut_window(*current, w);
        if (!ref || !cut) {
          fallback = true;
          break;
        }
        BackendProblem sub(*ref, limits_, warm_start.settings, safety, self_collision);
        Eigen::VectorXd xs;
        midend::LbfgsDriver driver(sub.num_variables());
        // A grown window may hold an earlier window's cuts, where the spliced trajectory is only
        // C^2: its problem then starts from the quintics through the same waypoints and times.
        if (!driver.ok() || !sub.midend().decision_from_trajectory(*cut, xs, false)) {
          fallback = true;
          break;
        }
        safety.prepare(map_W, *cut);
        if (self_collision) self_collision->prepare(*cut);
        r.prepare_s += seconds_since(t_prep);
        driver.set_x(xs, settings_.variable_scale);
        driver.set_stop_in_line_search(true);
        SolveContext ctx;
        ctx.problem = &sub;
        ctx.acceptance = acceptance;
        ctx.recheck_every = settings_.recheck_every_iterations;
        ctx.use_cutoff = settings_.skip_safety_above_current && settings_.line_search != midend::LineSearch::kMoreThuente;
        const auto t_opt = Clock::now();
        const Rounds rounds = run_rounds(settings_, sub, safety, driver, ctx, deadline, acceptance,
                                         settings_.max_iterations - r.iterations);
        r.optimize_s += seconds_since(t_opt);
        add_counters(r, ctx);
        r.iterations += rounds.iterations;
        r.rounds += rounds.rounds;
        r.lbfgs_code = rounds.run.code;
        r.safety_weight_scale = rounds.weight_scale;
        if (r.window_solves == 0 && ctx.have_initial) r.initial_cost = ctx.initial;
        ++r.window_solves;
        r.window_pieces += w.size();
        r.final_cost = ctx.best;
        // The window's last iterate is kept even when it does not pass yet (its cost is lower).
        const Eigen::VectorXd xw = driver.x();
        if (const std::optional<Trajectory> tw = sub.trajectory(xw.data())) {
          if (std::optional<Trajectory> spliced = splice(*current, w, *tw)) current = std::move(spliced);
        }
        if (ctx.found_free) break;  // this window passes: the next one
        if (rounds.run.stop == midend::LbfgsStop::kCanceled || deadline.canceled()) {
          r.status = planner::Status::kCanceled;
          r.message = "canceled";
          finish(r, acceptance, start);
          return r;
        }
        if (deadline.expired() || rounds.run.stop == midend::LbfgsStop::kDeadline || driver.expired_in_line_search()) {
          stop = true;
          break;
        }
        if (r.iterations >= settings_.max_iterations) {
          capped = stop = true;
          break;
        }
        // Not solvable with these pieces: more room on each side, up to the whole segment.
        const PieceWindow wider = grow_window(w, warm_start.reference, grow);
        if (wider == w) {
          fallback = true;
          break;
        }
        w = wider;
        grow *= 2;
      }
    }
    double done_check_s = 0.0;
    if (use && !stop && !fallback) {
      // Every window passed on its own and every other piece did at the start: the whole.
      const auto t_check = Clock::now();
      windows_done = acceptance->check(*current).accepted;
      done_check_s = seconds_since(t_check);
      fallback = !windows_done;
    }
    if (use && fallback && !stop && !deadline.expired()) {
      // The whole problem from the spliced trajectory.
      Eigen::VectorXd x;
      if (problem.midend().decision_from_trajectory(*current, x, false)) {
        x_full = x;
        r.window_fallback = true;
      } else {
        current = initial;  // cannot be expressed in the whole problem: its own warm start
      }
    }
    if (use && (stop || windows_done)) {
      r.status = windows_done ? planner::Status::kConverged
                 : capped     ? planner::Status::kIterationLimit
                              : planner::Status::kTimeout;
      r.message = std::string("piece windows: ") + std::to_string(r.window_solves) + " solve(s) over " +
                  std::to_string(r.window_pieces) + " pieces" +
                  (windows_done ? ", all accepted" : capped ? ", iteration cap reached" : ", budget ended");
      r.trajectory = current;
      if (windows_done) {  // checked just above
        r.check = SafetyCheck::kCollisionFree;
        r.check_s = done_check_s;
        r.elapsed_s = seconds_since(start);
        return r;
      }
      finish(r, acceptance, start);
      return r;
    }
  }

  const auto t_prep = Clock::now();
  const std::optional<Trajectory> whole = problem.trajectory(x_full.data());
  if (!whole) {
    r.status = planner::Status::kNumericalFailure;
    r.message = "the spliced trajectory describes no trajectory of the whole problem";
    finish(r, acceptance, start);
    return r;
  }
  safety.prepare(map_W, *whole);
  if (self_collision) self_collision->prepare(*whole);
  r.prepare_s += r.window_solves > 0 ? seconds_since(t_prep) : seconds_since(start);
  const int n = problem.num_variables();
  midend::LbfgsDriver driver(n);
  if (!driver.ok()) {
    r.status = planner::Status::kOptimizerFailed;
    r.message = "lbfgs_malloc failed";
    finish(r, acceptance, start);
    return r;
  }
  driver.set_x(x_full, settings_.variable_scale);
  driver.set_stop_in_line_search(true);

  SolveContext ctx;
  ctx.problem = &problem;
  ctx.acceptance = acceptance;
  ctx.recheck_every = settings_.recheck_every_iterations;
  ctx.use_cutoff = settings_.skip_safety_above_current && settings_.line_search != midend::LineSearch::kMoreThuente;
  const auto t_opt = Clock::now();
  const Rounds rounds = run_rounds(settings_, problem, safety, driver, ctx, deadline, acceptance,
                                   std::max(1, settings_.max_iterations - r.iterations));
  const midend::LbfgsDriver::Run& run = rounds.run;
  const int code = run.code;
  const double fx = run.f;
  r.optimize_s += seconds_since(t_opt);
  r.lbfgs_code = code;
  r.iterations += rounds.iterations;
  add_counters(r, ctx);
  r.rounds += rounds.rounds;
  r.safety_weight_scale = rounds.weight_scale;
  if (r.window_solves == 0) r.initial_cost = ctx.initial;
  const bool canceled = run.stop == midend::LbfgsStop::kCanceled || deadline.canceled();
  const double f0 = ctx.initial.total();
  if (canceled) {
    r.status = planner::Status::kCanceled;
    r.message = "canceled";
    finish(r, acceptance, start);
    return r;
  }
  if (!ctx.have_initial || !std::isfinite(f0)) {
    r.status = planner::Status::kNumericalFailure;
    r.message = "the warm start has a non-finite cost";
    finish(r, acceptance, start);
    return r;
  }

  const Eigen::VectorXd x1 = driver.x();
  // liblbfgs returns its last accepted iterate; its cost was evaluated already unless it is not
  // the lowest one seen (then evaluate it again).
  double f1 = fx;
  if (fx == ctx.best_f) {
    r.final_cost = ctx.best;
  } else {
    f1 = problem.evaluate(x1.data(), nullptr, &r.final_cost);
  }
  std::string detail = std::string("lbfgs: ") + midend::lbfgs_code_to_string(code);
  if (r.window_fallback) detail = "whole problem after " + std::to_string(r.window_solves) + " piece-window solve(s); " + detail;
  if (!std::isfinite(f1)) {
    r.status = planner::Status::kNumericalFailure;
    r.message = detail + "; final cost is not finite";
  } else if (rounds.escalation_cut) {
    // L-BFGS converged at this weight, but the solve would have raised it had the budget allowed:
    // report the budget, not convergence (the re-check below decides success either way).
    r.status = planner::Status::kTimeout;
    r.message = detail + "; the budget ended before the safety weight could be raised";
    if (rounds.escalations > 0) r.message += " (weight x" + std::to_string(static_cast<int>(rounds.weight_scale)) + ")";
  } else if (is_stop_code(code) || (code == LBFGSERR_CANCELED && ctx.found_free)) {
    r.status = planner::Status::kConverged;
  } else if ((code == LBFGSERR_CANCELED && run.stop == midend::LbfgsStop::kDeadline) || driver.expired_in_line_search()) {
    r.status = planner::Status::kTimeout;
  } else if (code == LBFGSERR_MAXIMUMITERATION) {
    r.status = planner::Status::kIterationLimit;
  } else if (midend::lbfgs_code_is_stall(code) && (f1 < f0 || rounds.rounds > 1 || r.window_solves > 0)) {
    r.status = planner::Status::kConvergedWithWarning;
  } else {
    r.status = planner::Status::kOptimizerFailed;
  }
  if (r.message.empty()) {
    r.message = detail;
    if (ctx.found_free) r.message += " (kernel re-check passed: stopped there)";
    if (rounds.escalations > 0) r.message += "; safety weight x" + std::to_string(static_cast<int>(rounds.weight_scale));
  }
  if (has_trajectory(r.status)) {
    std::optional<Trajectory> traj = problem.trajectory(x1.data());
    if (traj) {
      r.trajectory = std::move(traj);
    } else {
      r.status = planner::Status::kNumericalFailure;
      r.message = detail + "; trajectory rejected";
    }
  }
  finish(r, acceptance, start);
  return r;
}

}  // namespace porter::backend
