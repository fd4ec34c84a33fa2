#pragma once
// The JSON result file of porter-plan (layout documented in README.md beside this file).

#include <cstdint>
#include <map>
#include <optional>
#include <string>

#include "backend_stage.hpp"
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
  std::string collision;              ///< --collision (the front-end's checker)
  std::string safety;                 ///< --safety (the SVSDF term when collision = kernels)
  double frontend_budget_ms = 0.0;
  double midend_budget_ms = 0.0;
  double backend_budget_ms = 0.0;
  /// Why the mid-end was solved a second time with a tighter arm residual ("" when it was not).
  std::string midend_retry;
  /// rho_m of the mid-end solve whose result is reported (rad; 0: no mid-end).
  double midend_arm_residual_bound_rad = 0.0;
};

/// The kernel trajectory check of the answer (mid-end's, or back-end's when it ran).
struct FinalCheck {
  std::string stage;                  ///< "midend" or "backend": whose trajectory is the answer
  bool collision_free = false;
  int collision_link = -1;            ///< first link in collision (-1: none / unknown)
  double check_ms = 0.0;
};

/// Total base path length (sum of chord lengths between consecutive nodes), m.
double path_length_m(const planner::WholeBodyPath& path);

/// The result document (pretty-printed). `frontend` is absent when planning did not start
/// (error before it); `error` is "" unless the run failed before or outside planning.
/// `midend` is absent when the mid-end did not run (--stages front, or the front-end failed);
/// `backend` when the back-end did not run; `final_check` when there is no trajectory to check.
/// "trajectory" is the back-end's when it returned one, else the mid-end's.
std::string plan_result_json(const PlanRunInfo& info, const frontend::FrontendResult* frontend,
                             const std::string& status, int exit_code, const std::string& error,
                             const midend::MidendResult* midend = nullptr, const BackendRun* backend = nullptr,
                             const FinalCheck* final_check = nullptr);

}  // namespace porter::app
