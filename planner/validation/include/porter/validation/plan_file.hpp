#pragma once
// The parts of a porter-plan result file (planner/app/README.md, "JSON result") the validator
// reads: the planned trajectory's polynomial pieces and the planner's own verdict.
//
// Only the keys used here are read; other keys are ignored so that newer result layouts still
// validate. The trajectory object must follow the layout of porter-plan's "trajectory" key:
//   {"dimension": 8, "degree": 5, "start_yaw_rad": y,
//    "pieces": [{"duration_s": T > 0, "eta": +1|-1, "coeffs": 6 rows of 8 numbers}, ...]}
// where row k of a piece multiplies tau^k (tau in [0, T] local to the piece, seconds) and column
// d is the flat output z_d = [p_x, p_y, q1..q6] (m, m, rad x6; world frame W).
//
// Failure: parse_plan_file throws porter::LoadError naming the label and the key path
// ("result.json: key 'trajectory.pieces[3].coeffs[2]': expected 8 finite numbers"). A result
// without a trajectory (a failed plan) is not an error: has_trajectory is false.
// Thread-safety: reentrant.

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace porter::validation {

inline constexpr int kFlatDim = 8;       ///< z = [p_x, p_y, q1..q6]
inline constexpr int kPolyCoeffs = 6;    ///< degree 5

/// Row k multiplies tau^k; column d is z_d.
using PolyCoeffs = Eigen::Matrix<double, kPolyCoeffs, kFlatDim>;

struct PolyPiece {
  double duration_s = 0.0;
  int eta = 1;
  PolyCoeffs coeffs = PolyCoeffs::Zero();
};

/// What the planner said about its own answer (absent fields stay at their defaults).
struct PlannerVerdict {
  int exit_code = -1;                    ///< porter-plan's exit code, -1 when absent
  std::string status;                    ///< status of the last stage that ran
  std::optional<bool> collision_free;    ///< final_check.collision_free (kernel check)
  std::string answer_stage;              ///< final_check.stage: "midend" or "backend"
};

struct PlanFile {
  std::string label;                     ///< file name, for messages
  bool has_trajectory = false;
  double start_yaw_rad = 0.0;
  std::vector<PolyPiece> pieces;
  PlannerVerdict verdict;
  std::string scene_name;                ///< scene.name when present
  std::optional<long long> scene_seed;   ///< scene.seed when present
};

/// Parses result JSON held in memory; `label` names it in errors.
PlanFile parse_plan_file(const std::string& json_text, const std::string& label);

/// Reads and parses a result file (LoadError when unreadable or malformed).
PlanFile load_plan_file(const std::string& path);

}  // namespace porter::validation
