#pragma once
// The timing and iteration record every front-end sub-stage returns (outcomes in the pipeline's
// one vocabulary, porter/planner/status.hpp). Plain data.

#include <cstdint>
#include <string>

#include "porter/planner/status.hpp"

namespace porter::frontend {

/// What one sub-stage did. `ran` is false when the front-end did not need it. Statuses used:
/// kSuccess, kTimeout, kCanceled, kNoPath, kInvalidStart, kInvalidGoal.
struct StageReport {
  bool ran = false;
  planner::Status status = planner::Status::kNoPath;
  double elapsed_s = 0.0;
  std::int64_t iterations = 0;        ///< expansions (Hybrid A*) or sampling iterations (RRT*)
  std::int64_t collision_checks = 0;  ///< calls into the CollisionChecker
  std::string message;                ///< detail for a failure ("" on success)
};

}  // namespace porter::frontend
