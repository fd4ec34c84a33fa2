#pragma once
// Shared fixtures of the back-end tests and benchmark: the shipped robot with a payload, its SDFs
// (built once per process), and random smooth whole-body trajectories. Frozen: the benchmark's
// numbers are only comparable while these generators are unchanged.

#include <cstdint>
#include <random>
#include <string>

#include <Eigen/Core>

#include "porter/backend/robot_sdf.hpp"
#include "porter/backend/swept_body.hpp"
#include "porter/core/robot_model.hpp"
#include "porter/core/trajectory.hpp"

namespace porter::backend::testing {

std::string source_dir();
/// The Scout Mini + Piper config with config/payloads/<payload>.yaml attached ("" for none).
/// Cached per payload name; the reference stays valid for the process.
const RobotModel& robot(const std::string& payload);
/// RobotSdf::build(robot(payload)) with default settings, cached.
const RobotSdf& robot_sdf(const std::string& payload);

struct RandomTrajectoryOptions {
  int pieces = 4;
  double piece_duration_s = 1.0;
  double base_speed_mps = 0.4;     ///< mean forward speed (the base never stops)
  double turn_rate_radps = 0.4;    ///< heading changes drawn in +- this
  double joint_amplitude_rad = 0.5;
  int eta = 1;
  static RandomTrajectoryOptions with_pieces(int n) {
    RandomTrajectoryOptions o;
    o.pieces = n;
    return o;
  }
};

/// Quintic Hermite pieces through random knot states: the base drives with non-zero speed
/// (heading always defined), joints wander around a carry pose within their limits.
Trajectory random_trajectory(const RobotModel& model, std::uint64_t seed,
                             const RandomTrajectoryOptions& options = {});

/// A copy of `traj` with one raw parameter moved: piece i's coefficient (row, col) when
/// row >= 0, else piece i's duration (by delta).
Trajectory perturbed(const Trajectory& traj, int piece, int row, int col, double delta);

/// A point near link `link` at a random instant of `body`'s trajectory: a random point of the link's
/// bounding box, moved by up to `spread` metres along each axis.
Eigen::Vector3d point_near(const SweptBody& body, int link, std::mt19937& rng, double spread);

}  // namespace porter::backend::testing
