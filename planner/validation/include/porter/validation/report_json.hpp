#pragma once
// The validator's report as one summary line and as JSON (porter-validate's outputs).
//
// JSON layout ("format": "porter-validate/1"):
//   {"format", "valid": bool, "failures": [text], "plan": {file, has_trajectory, exit_code,
//    status, collision_free (kernel check; null when absent), answer_stage},
//    "samples", "duration_s", "max_step_m", "time_ms",
//    "collision": {found, t_s, body, shape, obstacle, depth_m, samples},
//    "self_collision": {found, t_s, body_a, body_b, depth_m, samples},
//    "clearance": [{obstacle, min_m (signed, m; null if never measured), t_s, body}],
//    "min_clearance_m": least over the obstacles (null without obstacles),
//    "limits": [{quantity, worst_ratio, t_s, where, value, limit, kept}],
//    "start": {ok, position_error_m, yaw_error_rad, joint_error_rad}, "goal": {...}}
// A result without a trajectory gives valid = false, has_trajectory = false and no checks.
//
// Thread-safety: reentrant.

#include <string>

#include "porter/validation/plan_file.hpp"
#include "porter/validation/validator.hpp"

namespace porter::validation {

/// report may be null when the plan has no trajectory.
std::string report_to_json(const PlanFile& plan, const ValidationReport* report, int indent = 2);

/// One line: "valid: ..." or "INVALID: <failures>; ..." with the key figures.
std::string report_line(const PlanFile& plan, const ValidationReport* report);

}  // namespace porter::validation
