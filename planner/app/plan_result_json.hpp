#pragma once
// The JSON result file of porter-plan (layout documented in README.md beside this file).

#include <cstdint>
#include <map>
#include <optional>
#include <string>

#include "porter/frontend/frontend.hpp"
#include "porter/midend/midend_result.hpp"
#include "porter/planner/whole_body_path.hpp"

namespace porter::app {

struct PlanRunInfo {
  std::string scene_file;
  std::string scene_name;
  std::uint64_t seed = 0;
  std::map<std::string, double> parameters;
  std::string robot_file;
  std::string payload_file;
  std::string checker;
  std::string stages;
  double frontend_budget_ms = 0.0;
};

/// Total base path length (sum of chord lengths between consecutive nodes), m.
double path_length_m(const planner::WholeBodyPath& path);

/// The result document (pretty-printed). `frontend` is absent when planning did not start
/// (error before it); `error` is "" unless the run failed before or outside planning.
/// `midend` is absent when the mid-end did not run (--stages front, or the front-end failed).
std::string plan_result_json(const PlanRunInfo& info, const frontend::FrontendResult* frontend,
                             const std::string& status, int exit_code, const std::string& error,
                             const midend::MidendResult* midend = nullptr);

}  // namespace porter::app
