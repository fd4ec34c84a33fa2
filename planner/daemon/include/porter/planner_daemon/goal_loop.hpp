#pragma once
// What porter-planner does with its inputs, without LCM or threads: one GoalLoop owns the
// Planner (built once per robot + payload), the latest map, the goal being served and the
// trajectory last published, and answers each event with what to publish.
//
//   GoalLoop s(std::move(planner), params, wall_clock);
//   Outcome o = s.on_goal(goal, state, now);         // plan from the state (or a hand-off)
//   o = s.on_map(grid, map_utime, now);              // new map: check the rest, re-plan or brake
//   o = s.on_tick(state, now);                       // arrival, retries after a brake
//   if (o.publication) publish(o.publication->trajectory, o.publication->start_utime, ...);
//   for (auto& r : o.reports) publish_status(r);
//
// Rules:
//   - A goal is planned only on a map no older than max_map_age_s (else refused: kNoMap with
//     the age) and from a state no older than max_state_age_s (else kNoState). While a
//     published trajectory is still executing, the plan starts from its state at now +
//     handoff.lead_s (continuous command); otherwise from the measured configuration at rest.
//   - Every new map is checked against the rest of the executing trajectory
//     (first_collision_s). A collision ahead leads to choose_handoff(): a re-plan from the
//     hand-off state to the same goal, or an immediate brake. A re-plan that fails, or finishes
//     after its hand-off time minus latency_s, is replaced by a brake (braking_trajectory) from
//     the current time plus latency_s.
//   - After a brake the goal stays: once the robot has stopped (the brake's end has passed) the
//     next on_tick() plans again from rest, up to max_attempts plans per goal.
//   - A plan from rest that fails with a status another seed or a newer map may change
//     (retryable(): timeout, no path, rejected by the acceptance test, optimizer failures) is
//     reported as kReplanning and tried again from rest on the next on_tick() with the next
//     seed, within the same max_attempts. Invalid goals, starts and inputs end the goal.
//   - The goal is done when a (non-brake) trajectory to it has been executed to its end with the
//     measured base within arrival_tolerance_m of the goal; farther away (the tracker stopped on a
//     fault, the base was held), the next on_tick() plans again from rest while attempts remain.
//   - A goal in collision, an invalid start and every other pipeline failure are reported with
//     the pipeline's message.
// Times: *_utime are µs on the messages' clock; `clock` returns that clock's now (plans take
// real time, so the loop reads it after each plan).
// Thread-safety: not thread-safe; one thread calls every member. A CancelFlag given in
// GoalLoopParams may be set from another thread to end a running plan.

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "porter/core/occupancy_grid.hpp"
#include "porter/core/trajectory.hpp"
#include "porter/pipeline/planner.hpp"
#include "porter/planner_daemon/replan.hpp"

namespace porter::planner_daemon {

struct GoalLoopParams {
  double max_map_age_s = 2.0;     ///< refuse to plan on an older map, s (> 0)
  double max_state_age_s = 0.5;   ///< refuse to plan from an older ROBOT_STATE, s (> 0)
  HandoffParams handoff;          ///< lead (>= the pipeline's worst-case plan time), latency, braking
  double collision_step_s = 0.02; ///< resolution of the first-collision time, s (> 0)
  int max_attempts = 3;           ///< plans per goal (the first + re-plans from rest after brakes)
  /// A trajectory that ended with the measured base farther than this from the goal is followed
  /// by a plan from rest (while attempts remain), m (> 0).
  double arrival_tolerance_m = 0.3;
  std::uint64_t seed = 1;         ///< seed of the first plan; later plans use seed + n
  /// A plan for a hand-off may run until the hand-off minus handoff.latency_s and this reserve
  /// (the back-end's final check, a loaded computer), s (>= 0): its back-end takes that time when
  /// it is longer than the back-end's budget. Plans from rest keep the settings' budgets.
  double handoff_reserve_s = 0.3;
  const planner::CancelFlag* cancel = nullptr;  ///< ends a running plan when set (optional)

  /// Throws std::invalid_argument naming the first invalid field.
  void validate() const;
};

/// PLANNER_STATUS states (planner_status_t.STATE_*).
enum class GoalLoopState : std::int8_t {
  kIdle = 0, kPlanning = 1, kSucceeded = 2, kFailed = 3, kReplanning = 4, kNoMap = 5, kNoState = 6,
};
const char* to_string(GoalLoopState s);

/// Whether a plan that failed with this status is worth another attempt (a new seed, a newer
/// map): kTimeout, kNoPath, kInCollision and the optimizers' failures; not the invalid inputs.
bool retryable(planner::Status s);

/// The measured state the planner starts from.
struct MeasuredState {
  std::int64_t utime = 0;   ///< when it was received (receiver's clock), µs
  RobotConfiguration config;
  bool valid = false;       ///< pose and arm are fresh (ROBOT_STATE's flags)
};

struct Goal {
  std::int64_t goal_id = 0;
  pipeline::GoalSpec spec;
};

struct StageTiming {
  std::string name;     ///< "goal", "front_end", "mid_end", "back_end"
  std::string status;   ///< planner::to_string of the stage's status
  double time_s = 0.0;
  int iterations = 0;
};

/// One PLANNER_STATUS.
struct Report {
  GoalLoopState state = GoalLoopState::kIdle;
  std::int64_t goal_id = -1;
  std::int64_t plan_id = -1;
  std::string reason;   ///< failure or refusal cause; for successes a note (re-plan, brake)
  std::vector<StageTiming> stages;
  double total_s = 0.0;
  double duration_s = 0.0;  ///< of the published trajectory (0 when none)
  /// The time a plan for a hand-off was given (PlanRequest::time_available_s), s; 0 for a plan
  /// from rest (the settings' budgets).
  double time_available_s = 0.0;
};

/// A trajectory to publish on TRAJECTORY.
struct Publication {
  Trajectory trajectory;
  std::int64_t start_utime = 0;  ///< absolute time of its t = 0 (the hand-off time)
  std::int64_t plan_id = 0;
  bool braking = false;
};

struct Outcome {
  std::optional<Publication> publication;
  std::vector<Report> reports;
  std::vector<std::string> log;  ///< lines for the process log, with timings
};

/// Counters for logs and tests.
struct GoalLoopStats {
  int plans = 0;
  int replans = 0;          ///< plans started because of a collision ahead
  int brakes = 0;
  int maps = 0;
  int maps_refused = 0;
  int blocked_checks = 0;   ///< maps on which the rest of the trajectory collided
};

class GoalLoop {
 public:
  /// Throws std::invalid_argument when params are invalid or planner is null.
  GoalLoop(std::unique_ptr<pipeline::Planner> planner, GoalLoopParams params,
          std::function<std::int64_t()> clock);

  /// Adopts a map (stamped map_utime). A map the planner refuses is reported (kFailed, the
  /// pipeline's message) and the previous one is kept.
  Outcome on_map(const OccupancyGrid& map_W, std::int64_t map_utime);
  /// A new goal replaces the current one.
  Outcome on_goal(const Goal& goal, const std::optional<MeasuredState>& state);
  /// Periodic: arrival, and the re-plan from rest after a brake.
  Outcome on_tick(const std::optional<MeasuredState>& state);
  /// Replaces the planner (another payload); the current map is given to it, the goal and the
  /// executing trajectory are kept.
  void replace_planner(std::unique_ptr<pipeline::Planner> planner);

  const pipeline::Planner& planner() const { return *planner_; }
  bool has_goal() const { return goal_.has_value(); }
  const std::optional<Publication>& active() const { return active_; }
  const GoalLoopStats& stats() const { return stats_; }
  GoalLoopState state() const { return state_; }

 private:
  struct Attempt {
    pipeline::StartState start;
    std::int64_t start_utime = 0;  ///< t = 0 of the plan to publish
    bool replan = false;           ///< because of a collision ahead
    std::optional<double> handoff_s;  ///< on the active trajectory (when moving)
  };
  Outcome plan(const Attempt& attempt, Outcome out);
  Outcome brake(double from_s, const std::string& why, Outcome out);
  std::string state_problem(const std::optional<MeasuredState>& state, std::int64_t now) const;
  double active_time_s(std::int64_t now_utime) const;
  bool active_executing(std::int64_t now_utime) const;
  Report report(GoalLoopState state, std::string reason) const;

  std::unique_ptr<pipeline::Planner> planner_;
  GoalLoopParams params_;
  std::function<std::int64_t()> clock_;
  std::optional<OccupancyGrid> map_W_;
  std::int64_t map_utime_ = 0;
  std::optional<Goal> goal_;
  int attempts_ = 0;
  bool retry_from_rest_ = false;  ///< a failed plan from rest is tried again on the next tick
  std::optional<Publication> active_;
  std::int64_t next_plan_id_ = 1;
  GoalLoopState state_ = GoalLoopState::kIdle;
  GoalLoopStats stats_;
};

}  // namespace porter::planner_daemon
