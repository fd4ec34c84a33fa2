#include "porter/planner_daemon/goal_loop.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <utility>

namespace porter::planner_daemon {
namespace {

std::string fmt(const char* f, double a, double b = 0.0, double c = 0.0) {
  char buf[200];
  std::snprintf(buf, sizeof buf, f, a, b, c);
  return buf;
}

std::vector<StageTiming> stage_timings(const pipeline::PlanResult& r) {
  std::vector<StageTiming> s;
  s.push_back({"goal", planner::to_string(r.goal.status), r.goal.time_s, r.goal.candidates});
  if (r.frontend) {
    const auto& f = *r.frontend;
    s.push_back({"front_end", planner::to_string(f.status), f.elapsed_s,
                 static_cast<int>(f.hybrid_astar.iterations + f.layered_arm.iterations + f.whole_body_rrt.iterations)});
  }
  if (r.midend) {
    s.push_back({"mid_end", planner::to_string(r.midend->result.status), r.midend->time_s, r.midend->result.iterations});
  }
  if (r.backend) {
    s.push_back({"back_end", planner::to_string(r.backend->result.status), r.backend->result.elapsed_s,
                 r.backend->result.iterations});
  }
  return s;
}

}  // namespace

bool retryable(planner::Status s) {
  switch (s) {
    case planner::Status::kTimeout:
    case planner::Status::kNoPath:
    case planner::Status::kInCollision:
    case planner::Status::kIterationLimit:
    case planner::Status::kConvergedWithWarning:
    case planner::Status::kNumericalFailure:
    case planner::Status::kOptimizerFailed:
    case planner::Status::kConstraintViolation:
      return true;
    default:
      return false;
  }
}

void GoalLoopParams::validate() const {
  auto positive = [](double v, const char* name) {
    if (!(v > 0.0) || !std::isfinite(v)) throw std::invalid_argument(std::string(name) + " must be > 0");
  };
  positive(max_map_age_s, "max_map_age_s");
  positive(max_state_age_s, "max_state_age_s");
  positive(handoff.lead_s, "handoff.lead_s");
  positive(handoff.latency_s, "handoff.latency_s");
  positive(handoff.braking.base_decel_mps2, "handoff.braking.base_decel_mps2");
  positive(handoff.braking.joint_decel_radps2, "handoff.braking.joint_decel_radps2");
  positive(handoff.braking.min_duration_s, "handoff.braking.min_duration_s");
  positive(collision_step_s, "collision_step_s");
  positive(arrival_tolerance_m, "arrival_tolerance_m");
  if (handoff.latency_s >= handoff.lead_s) throw std::invalid_argument("handoff.latency_s must be < handoff.lead_s");
  if (max_attempts < 1) throw std::invalid_argument("max_attempts must be >= 1");
  if (!(handoff_reserve_s >= 0.0) || !std::isfinite(handoff_reserve_s))
    throw std::invalid_argument("handoff_reserve_s must be >= 0");
}

const char* to_string(GoalLoopState s) {
  switch (s) {
    case GoalLoopState::kIdle: return "IDLE";
    case GoalLoopState::kPlanning: return "PLANNING";
    case GoalLoopState::kSucceeded: return "SUCCEEDED";
    case GoalLoopState::kFailed: return "FAILED";
    case GoalLoopState::kReplanning: return "REPLANNING";
    case GoalLoopState::kNoMap: return "NO_MAP";
    case GoalLoopState::kNoState: return "NO_STATE";
  }
  return "?";
}

GoalLoop::GoalLoop(std::unique_ptr<pipeline::Planner> planner, GoalLoopParams params, std::function<std::int64_t()> clock)
    : planner_(std::move(planner)), params_(params), clock_(std::move(clock)) {
  if (!planner_) throw std::invalid_argument("GoalLoop: no planner");
  if (!clock_) throw std::invalid_argument("GoalLoop: no clock");
  params_.validate();
}

void GoalLoop::replace_planner(std::unique_ptr<pipeline::Planner> planner) {
  if (!planner) return;
  planner_ = std::move(planner);
  if (map_W_) planner_->set_map(*map_W_);
}

Report GoalLoop::report(GoalLoopState state, std::string reason) const {
  Report r;
  r.state = state;
  r.goal_id = goal_ ? goal_->goal_id : -1;
  r.plan_id = active_ ? active_->plan_id : -1;
  r.reason = std::move(reason);
  return r;
}

double GoalLoop::active_time_s(std::int64_t now_utime) const {
  return active_ ? static_cast<double>(now_utime - active_->start_utime) * 1e-6 : 0.0;
}

bool GoalLoop::active_executing(std::int64_t now_utime) const {
  return active_ && active_time_s(now_utime) < active_->trajectory.total_duration_s();
}

std::string GoalLoop::state_problem(const std::optional<MeasuredState>& state, std::int64_t now) const {
  if (!state) return "no ROBOT_STATE received";
  if (!state->valid) return "ROBOT_STATE has no fresh pose or arm";
  const double age = static_cast<double>(now - state->utime) * 1e-6;
  if (age > params_.max_state_age_s) return fmt("ROBOT_STATE is %.2f s old, limit %.2f s", age, params_.max_state_age_s);
  return "";
}

Outcome GoalLoop::on_map(const OccupancyGrid& map_W, std::int64_t map_utime) {
  Outcome out;
  ++stats_.maps;
  const pipeline::MapUpdate u = planner_->set_map(map_W);
  if (!u.ok) {
    ++stats_.maps_refused;
    out.reports.push_back(report(GoalLoopState::kFailed, "map refused: " + u.message));
    out.log.push_back("map refused: " + u.message);
    return out;
  }
  map_W_ = map_W;
  map_utime_ = map_utime;
  out.log.push_back(fmt("map set in %.1f ms", u.time_s * 1e3) + (u.incremental ? " (incremental, " : " (full, ") +
                    std::to_string(u.changed_voxels) + " voxels changed)");
  const std::int64_t now = clock_();
  if (!goal_ || !active_executing(now) || active_->braking) return out;

  const double t_now = std::max(0.0, active_time_s(now));
  const std::optional<double> hit = first_collision_s(planner_->kernel_checker(), active_->trajectory, t_now,
                                                      params_.collision_step_s);
  if (!hit) return out;
  ++stats_.blocked_checks;
  const HandoffChoice choice = choose_handoff(active_->trajectory, t_now, hit, params_.handoff);
  out.log.push_back("plan " + std::to_string(active_->plan_id) + ": " + choice.reason);
  if (choice.action == HandoffAction::kBrake) return brake(choice.handoff_s, choice.reason, std::move(out));
  ++stats_.replans;
  Attempt a;
  a.start = pipeline::StartState::on_trajectory(active_->trajectory, choice.handoff_s);
  a.start_utime = active_->start_utime + static_cast<std::int64_t>(std::llround(choice.handoff_s * 1e6));
  a.replan = true;
  a.handoff_s = choice.handoff_s;
  out.reports.push_back(report(GoalLoopState::kReplanning, choice.reason));
  return plan(a, std::move(out));
}

Outcome GoalLoop::on_goal(const Goal& goal, const std::optional<MeasuredState>& state) {
  Outcome out;
  goal_ = goal;
  attempts_ = 0;
  retry_from_rest_ = false;
  const std::int64_t now = clock_();
  auto refuse = [&](GoalLoopState s, const std::string& why) {
    out.reports.push_back(report(s, why));
    out.log.push_back("goal " + std::to_string(goal.goal_id) + " refused: " + why);
    goal_.reset();
    return std::move(out);
  };
  if (!map_W_) return refuse(GoalLoopState::kNoMap, "no map received yet");
  const std::string old = map_age_problem(map_utime_, now, params_.max_map_age_s);
  if (!old.empty()) return refuse(GoalLoopState::kNoMap, old);

  Attempt a;
  if (active_executing(now)) {
    const double t = std::min(std::max(0.0, active_time_s(now)) + params_.handoff.lead_s,
                              active_->trajectory.total_duration_s());
    a.start = pipeline::StartState::on_trajectory(active_->trajectory, t);
    a.start_utime = active_->start_utime + static_cast<std::int64_t>(std::llround(t * 1e6));
    a.handoff_s = t;
  } else {
    const std::string bad = state_problem(state, now);
    if (!bad.empty()) return refuse(GoalLoopState::kNoState, bad);
    a.start = pipeline::StartState::at_rest(state->config);
  }
  out.reports.push_back(report(GoalLoopState::kPlanning, ""));
  return plan(a, std::move(out));
}

Outcome GoalLoop::on_tick(const std::optional<MeasuredState>& state) {
  Outcome out;
  const std::int64_t now = clock_();
  if (retry_from_rest_ && goal_ && !active_executing(now)) {
    const std::string old = map_age_problem(map_utime_, now, params_.max_map_age_s);
    const std::string bad = state_problem(state, now);
    if (!old.empty() || !bad.empty()) return out;  // wait for a fresh map and state
    retry_from_rest_ = false;
    Attempt a;
    a.start = pipeline::StartState::at_rest(state->config);
    out.reports.push_back(report(GoalLoopState::kPlanning, "re-plan from rest after a failed plan"));
    return plan(a, std::move(out));
  }
  if (!active_ || active_executing(now) || !goal_) return out;
  if (!active_->braking) {
    // The trajectory has ended; a robot left short of the goal (the tracker stopped on a fault,
    // the base was held) is planned again from where it stands.
    const double off_m = state && state->valid ? std::hypot(state->config.base.x_m - goal_->spec.base.x_m,
                                                            state->config.base.y_m - goal_->spec.base.y_m)
                                               : 0.0;
    if (off_m > params_.arrival_tolerance_m && attempts_ < params_.max_attempts) {
      const std::string old = map_age_problem(map_utime_, now, params_.max_map_age_s);
      if (!old.empty() || !state_problem(state, now).empty()) return out;  // wait for a fresh map and state
      Attempt a;
      a.start = pipeline::StartState::at_rest(state->config);
      out.reports.push_back(report(GoalLoopState::kPlanning, fmt("re-plan from rest: the trajectory ended with the "
                                                                 "robot %.2f m from the goal", off_m)));
      out.log.push_back(out.reports.back().reason);
      return plan(a, std::move(out));
    }
    out.reports.push_back(report(GoalLoopState::kIdle, "goal " + std::to_string(goal_->goal_id) +
                                                          ": trajectory executed to its end"));
    out.log.push_back(out.reports.back().reason);
    goal_.reset();
    return out;
  }
  // Stopped by a brake with the goal still set: plan again from rest.
  if (attempts_ >= params_.max_attempts) {
    out.reports.push_back(report(GoalLoopState::kFailed, "goal " + std::to_string(goal_->goal_id) + ": gave up after " +
                                                            std::to_string(attempts_) + " plans"));
    out.log.push_back(out.reports.back().reason);
    goal_.reset();
    return out;
  }
  const std::string old = map_age_problem(map_utime_, now, params_.max_map_age_s);
  const std::string bad = state_problem(state, now);
  if (!old.empty() || !bad.empty()) return out;  // wait for a fresh map and state
  Attempt a;
  a.start = pipeline::StartState::at_rest(state->config);
  out.reports.push_back(report(GoalLoopState::kPlanning, "re-plan from rest after braking"));
  return plan(a, std::move(out));
}

Outcome GoalLoop::plan(const Attempt& attempt, Outcome out) {
  ++attempts_;
  ++stats_.plans;
  pipeline::PlanRequest request;
  request.start = attempt.start;
  request.goal = goal_->spec;
  request.seed = params_.seed + static_cast<std::uint64_t>(stats_.plans - 1);
  request.stages = pipeline::Stages::kFull;
  request.cancel = params_.cancel;
  if (attempt.start_utime != 0) {
    const double until_s = static_cast<double>(attempt.start_utime - clock_()) * 1e-6 - params_.handoff.latency_s -
                           params_.handoff_reserve_s;
    request.time_available_s = std::max(0.0, until_s);
  }
  const pipeline::PlanResult r = planner_->plan(request);
  const std::int64_t now = clock_();

  Report rep = report(GoalLoopState::kSucceeded, attempt.replan ? "re-planned around a collision ahead" : "");
  rep.stages = stage_timings(r);
  rep.total_s = r.total_s;
  rep.time_available_s = request.time_available_s;
  std::string failure;
  if (!r.success() || !r.trajectory) {
    failure = std::string(planner::to_string(r.status)) + (r.message.empty() ? "" : ": " + r.message);
  } else if (attempt.start_utime != 0 && now > attempt.start_utime - static_cast<std::int64_t>(params_.handoff.latency_s * 1e6)) {
    failure = fmt("plan finished %.3f s after its hand-off time minus latency (total %.3f s)",
                  static_cast<double>(now - attempt.start_utime) * 1e-6 + params_.handoff.latency_s, r.total_s);
  }
  std::string timing;
  for (const auto& s : rep.stages) timing += " " + s.name + " " + fmt("%.1f ms", s.time_s * 1e3) + " (" + s.status + ")";
  if (request.time_available_s > 0.0) timing += fmt("; given %.2f s until the hand-off", request.time_available_s);
  if (!failure.empty()) {
    rep.state = GoalLoopState::kFailed;
    rep.reason = failure;
    out.reports.push_back(rep);
    out.log.push_back("goal " + std::to_string(goal_->goal_id) + ": plan failed in " + fmt("%.1f ms", r.total_s * 1e3) +
                      ": " + failure + ";" + timing);
    if (attempt.handoff_s && active_executing(now)) {
      const double t_brake = std::max(0.0, active_time_s(now)) + params_.handoff.latency_s;
      return brake(t_brake, "the plan from the hand-off failed", std::move(out));
    }
    // A plan from rest that the search or the optimizers did not finish (a randomized front-end,
    // budgets) is tried again with the next seed on the next tick, while attempts remain.
    if (!attempt.handoff_s && retryable(r.status) && attempts_ < params_.max_attempts) {
      rep.state = GoalLoopState::kReplanning;
      rep.reason = "plan failed: " + failure + "; planning again from rest (attempt " + std::to_string(attempts_ + 1) +
                   " of " + std::to_string(params_.max_attempts) + ")";
      out.reports.back() = rep;
      retry_from_rest_ = true;
      return out;
    }
    goal_.reset();
    return out;
  }
  Publication p{*r.trajectory,
                attempt.start_utime != 0 ? attempt.start_utime
                                         : now + static_cast<std::int64_t>(params_.handoff.latency_s * 1e6),
                next_plan_id_++, false};
  active_ = p;
  state_ = GoalLoopState::kSucceeded;
  rep.plan_id = p.plan_id;
  rep.duration_s = p.trajectory.total_duration_s();
  out.reports.push_back(rep);
  out.log.push_back("goal " + std::to_string(goal_->goal_id) + ": plan " + std::to_string(p.plan_id) + " in " +
                    fmt("%.1f ms, %.2f s long", r.total_s * 1e3, rep.duration_s) +
                    (attempt.handoff_s ? fmt(", hand-off at t = %.2f s of the previous", *attempt.handoff_s) : "") +
                    ";" + timing);
  out.publication = std::move(p);
  return out;
}

Outcome GoalLoop::brake(double from_s, const std::string& why, Outcome out) {
  ++stats_.brakes;
  const double t = std::min(from_s, active_->trajectory.total_duration_s());
  Publication p{braking_trajectory(active_->trajectory, t, params_.handoff.braking),
                active_->start_utime + static_cast<std::int64_t>(std::llround(t * 1e6)), next_plan_id_++, true};
  active_ = p;
  const bool retry = goal_ && attempts_ < params_.max_attempts;
  Report rep = report(retry ? GoalLoopState::kReplanning : GoalLoopState::kFailed,
                      "braking: " + why + (retry ? "; the goal is planned again once stopped" : ""));
  rep.duration_s = p.trajectory.total_duration_s();
  out.reports.push_back(rep);
  out.log.push_back("plan " + std::to_string(p.plan_id) + ": braking trajectory, " +
                    fmt("%.2f s from t = %.2f s of the previous: ", rep.duration_s, t) + why);
  if (!retry) goal_.reset();
  out.publication = std::move(p);
  return out;
}

}  // namespace porter::planner_daemon
