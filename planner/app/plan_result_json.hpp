#pragma once
// The JSON result file of porter-plan (layout documented in README.md beside this file).

#include <cstdint>
#include <map>
#include <string>

#include "porter/pipeline/plan_result.hpp"
#include "porter/planner/whole_body_path.hpp"

namespace porter::app {

/// What porter-plan was asked and used, besides the plan itself.
struct PlanRunInfo {
  std::string scene_file;
  std::string scene_name;
  std::uint64_t seed = 0;
  std::map<std::string, double> parameters;
  std::string robot_file;
  std::string payload_file;
  std::string planner_config;         ///< the settings directory
  std::string checker;                ///< the front-end's checker name
  std::string stages;
  std::string collision;              ///< the front-end's collision model
  std::string safety;                 ///< the back-end's term ("spheres" with collision spheres)
  double frontend_budget_ms = 0.0;
  double midend_budget_ms = 0.0;
  double backend_budget_ms = 0.0;
  std::string acceptance;             ///< the final acceptance test's name (exact | kernels)
  double clearance_margin_m = -1.0;   ///< its exact clearance margin, m (negative: none stated)
};

/// Total base path length (sum of chord lengths between consecutive nodes), m.
double path_length_m(const planner::WholeBodyPath& path);

/// The result document (pretty-printed). `result` is null when the run stopped before planning
/// (bad input); `status` is the last stage's status token (or "bad_input"); `error` is "" unless
/// the run failed.
std::string plan_result_json(const PlanRunInfo& info, const pipeline::PlanResult* result, const std::string& status,
                             int exit_code, const std::string& error);

}  // namespace porter::app
