#pragma once
// The final acceptance test of a trajectory: the one step that decides whether a trajectory may
// be executed (the mid-end's directly, or the back-end's answer, which the back-end also consults
// while it optimizes). Today's implementation is the kernel collision check along the trajectory
// (planner/pipeline kernel_acceptance.hpp); another may replace it without touching the stages.
//
// Contract: check() never throws and does not modify the acceptance object; it may be called from
// the planning thread while no map update runs (implementations document more).

#include <string>

#include "porter/core/trajectory.hpp"

namespace porter::planner {

struct AcceptanceResult {
  bool accepted = false;
  int link = -1;        ///< first planning link found in collision (-1: none or unknown)
  int other_link = -1;  ///< the second link of a self-collision (-1: environment, ground, none)
};

class TrajectoryAcceptance {
 public:
  virtual ~TrajectoryAcceptance() = default;
  virtual AcceptanceResult check(const Trajectory& trajectory) const = 0;
  /// A short name for logs and result files ("kernels").
  virtual std::string name() const = 0;
  /// The least exact clearance an accepted trajectory keeps to every obstacle, m, when the test
  /// states one (the back-end then aims its safety term at it); negative when it decides on its
  /// own geometry instead (the kernel check's inflated voxels).
  virtual double clearance_margin_m() const { return -1.0; }
};

}  // namespace porter::planner
