#include "stages.hpp"

#include <algorithm>
#include <chrono>
#include <limits>
#include <sstream>

#include "porter/backend/trajectory_gradient.hpp"

namespace porter::pipeline::detail {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

/// A solve and the acceptance test of its trajectory (time added to *check_s).
struct Solve {
  midend::MidendResult result;
  planner::AcceptanceResult acceptance;
  double check_s = 0.0;
};

Solve solve_and_check(const midend::MidEnd& midend, const planner::WholeBodyPath& path, const StartState& start,
                      double budget_s, const planner::TrajectoryAcceptance& acceptance,
                      const planner::CancelFlag* cancel) {
  Solve s;
  s.result = midend.solve(path, planner::Deadline(budget_s, cancel), midend::StartDerivatives{start.velocity, start.acceleration});
  if (s.result.trajectory) {
    const auto t0 = Clock::now();
    s.acceptance = acceptance.check(*s.result.trajectory);
    s.check_s = seconds_since(t0);
  }
  return s;
}

}  // namespace

MidendReport run_midend(const midend::MidEnd& midend, const planner::WholeBodyPath& path, const StartState& start,
                        const PipelineSettings& settings, Stages stages, const planner::TrajectoryAcceptance& acceptance,
                        const planner::CollisionChecker& self_checker, const planner::CancelFlag* cancel) {
  const auto t_stage = Clock::now();
  MidendReport rep;
  Solve first = solve_and_check(midend, path, start, settings.midend_budget_s, acceptance, cancel);
  rep.residual_arm_bound_rad = midend.settings().residual_arm_bound_rad;
  rep.acceptance_s = first.check_s;
  auto done = [&](Solve& s) {
    rep.result = std::move(s.result);
    rep.acceptance = s.acceptance;
    rep.time_s = seconds_since(t_stage);
    return std::move(rep);
  };
  const bool retry_enabled = settings.retry_arm_residual_scale < 1.0;
  if (!first.result.trajectory || first.acceptance.accepted || !retry_enabled ||
      (cancel && cancel->requested()))
    return done(first);
  const auto t_self = Clock::now();
  const planner::CollisionResult self = self_checker.check_trajectory_self(*first.result.trajectory);
  rep.self_check_s = seconds_since(t_self);
  if (!self.in_collision && stages != Stages::kFull) return done(first);

  midend::MidendSettings tight = midend.settings();
  tight.residual_arm_bound_rad *= settings.retry_arm_residual_scale;
  const midend::MidEnd retry_solver(midend.limits(), tight);
  Solve retry = solve_and_check(retry_solver, path, start, settings.midend_budget_s, acceptance, cancel);
  rep.acceptance_s += retry.check_s;
  std::ostringstream why;
  if (self.in_collision) {
    why << "self-collision (links " << self.link << "-" << self.other_link << ")";
  } else {
    why << "in collision (link " << first.acceptance.link << ")";
  }
  why << ": arm residual bound " << midend.settings().residual_arm_bound_rad << " -> " << tight.residual_arm_bound_rad
      << " rad";
  rep.retry = why.str();
  if (!retry.result.trajectory) return done(first);
  // A retry that hits itself where the first did not is no use to the back-end either.
  bool retry_self = false;
  if (!retry.acceptance.accepted && !self.in_collision) {
    const auto t0 = Clock::now();
    retry_self = self_checker.check_trajectory_self(*retry.result.trajectory).in_collision;
    rep.self_check_s += seconds_since(t0);
  }
  // The stage's cost is both solves: times, iterations and evaluations add up.
  Solve& kept = retry_self ? first : retry;
  const Solve& other = retry_self ? retry : first;
  kept.result.elapsed_s += other.result.elapsed_s;
  kept.result.prepare_s += other.result.prepare_s;
  kept.result.optimize_s += other.result.optimize_s;
  kept.result.iterations += other.result.iterations;
  kept.result.evaluations += other.result.evaluations;
  if (retry_self) {
    rep.retry += " (the retry hits itself: not used)";
    return done(first);
  }
  if (!self.in_collision && !retry.acceptance.accepted) rep.first = std::move(first.result);  // a second warm start
  rep.residual_arm_bound_rad = tight.residual_arm_bound_rad;
  return done(retry);
}

BackendReport run_backend(const backend::BackEnd& backend, const MidendReport& mid, const OccupancyGrid& map_W,
                          backend::SafetyTerm& safety, backend::SelfCollisionTerm* self_term, double budget_s,
                          bool choose_by_safety, const planner::TrajectoryAcceptance& acceptance, const planner::CancelFlag* cancel) {
  BackendReport rep;
  rep.budget_s = budget_s;
  rep.safety_model = safety.name();
  rep.self_collision_term = self_term != nullptr;
  // The warm starts: the reported solve, and (when asked for) the first one when both were
  // rejected.
  std::vector<const midend::MidendResult*> starts{&mid.result};
  if (choose_by_safety && mid.first && mid.first->solution) starts.push_back(&*mid.first);
  // With several, the one with the lowest J_s (the term's own measure of how deep the trajectory
  // is in collision), at one evaluation each, taken from the budget.
  const auto t_select = Clock::now();
  if (starts.size() > 1) {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < starts.size(); ++i) {
      const Trajectory& t = *starts[i]->trajectory;
      safety.prepare(map_W, t);
      backend::TrajectoryGradient unused;
      unused.reset(t.num_pieces());
      const double js = safety.evaluate(t, unused, nullptr);
      rep.warm_start_safety.push_back(js);
      if (js < best) {
        best = js;
        rep.warm_start = static_cast<int>(i);
      }
    }
  }
  rep.selection_s = seconds_since(t_select);
  const midend::MidendResult& chosen = *starts[static_cast<std::size_t>(rep.warm_start)];
  rep.result = backend.solve(*chosen.solution, map_W, safety,
                             planner::Deadline(std::max(1e-3, budget_s - rep.selection_s), cancel), &acceptance, self_term);
  rep.result.elapsed_s += rep.selection_s;
  return rep;
}

}  // namespace porter::pipeline::detail
