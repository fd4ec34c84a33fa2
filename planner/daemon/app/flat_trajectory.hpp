#pragma once
// A core Trajectory as the validator's own flat form (planner/validation keeps its polynomial
// type apart from core so that it checks trajectories independently): the tools that judge a
// run against the scene's exact geometry (porter-mission, porter-run-audit) convert through this.

#include <vector>

#include "porter/core/trajectory.hpp"
#include "porter/validation/validator.hpp"

namespace porter::planner_app {

inline validation::FlatTrajectory to_flat(const Trajectory& t) {
  std::vector<validation::PolyPiece> pieces;
  pieces.reserve(t.pieces().size());
  for (const auto& p : t.pieces()) {
    validation::PolyPiece q;
    q.duration_s = p.duration_s;
    q.eta = p.eta;
    q.coeffs = p.coeffs;
    pieces.push_back(q);
  }
  return validation::FlatTrajectory(pieces, t.start_yaw_rad());
}

}  // namespace porter::planner_app
