#pragma once
// Outcome of a front-end stage (OMPL PlannerStatus style) and the timing/iteration record every
// stage returns. Pure, thread-safe.

#include <cstdint>
#include <string>

namespace porter::frontend {

enum class PlannerStatus {
  kSuccess,       ///< a path was found (it may be refined further within the budget)
  kTimeout,       ///< the time budget (or iteration cap) ran out before a path was found
  kNoPath,        ///< the search space was exhausted or the goal is provably unreachable
  kInvalidStart,  ///< start outside the map/joint limits or in collision
  kInvalidGoal,   ///< goal outside the map/joint limits or in collision
};

/// Short, stable names used in logs and result files: "success", "timeout", "no_path",
/// "invalid_start", "invalid_goal".
inline const char* to_string(PlannerStatus s) {
  switch (s) {
    case PlannerStatus::kSuccess: return "success";
    case PlannerStatus::kTimeout: return "timeout";
    case PlannerStatus::kNoPath: return "no_path";
    case PlannerStatus::kInvalidStart: return "invalid_start";
    case PlannerStatus::kInvalidGoal: return "invalid_goal";
  }
  return "unknown";
}

/// What one stage did. `ran` is false when the pipeline did not need the stage.
struct StageReport {
  bool ran = false;
  PlannerStatus status = PlannerStatus::kNoPath;
  double elapsed_s = 0.0;
  std::int64_t iterations = 0;        ///< expansions (Hybrid A*) or sampling iterations (RRT*)
  std::int64_t collision_checks = 0;  ///< calls into the CollisionChecker
  std::string message;                ///< detail for a failure ("" on success)
};

}  // namespace porter::frontend
