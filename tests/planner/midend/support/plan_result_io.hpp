#pragma once
// Reads the parts of a porter-plan result file (planner/app/plan_result_json.*, format
// "porter-plan-result/2" and /3) that the mid-end tools need: the front-end path ("path") and the
// final trajectory ("trajectory"), plus the recorded mid-end status and timings.
//
// Throws porter::LoadError naming the file and the key when the file is unreadable or a
// present key is malformed; a missing path or trajectory (null) is reported as nullopt.
// Not a product API: test and benchmark support only. Thread-safe (no shared state).

#include <optional>
#include <string>

#include "porter/core/trajectory.hpp"
#include "porter/planner/whole_body_path.hpp"

namespace porter::midend::testing {

struct PlanResultFile {
  std::string file;
  std::string scene_name;
  long long seed = 0;
  std::optional<planner::WholeBodyPath> path;  ///< null when the front-end failed
  std::optional<Trajectory> trajectory;        ///< the final trajectory, if any
  bool has_midend = false;
  std::string midend_status;
  double midend_optimize_ms = 0.0;
  double midend_time_ms = 0.0;
  /// rho_m the reported mid-end solve used (porter-plan's self-collision retry halves it); 0 when
  /// the file does not say.
  double midend_arm_residual_bound_rad = 0.0;
};

PlanResultFile read_plan_result(const std::string& file);

}  // namespace porter::midend::testing
