#pragma once
// Two sensors every simulated run has (sensor.hpp):
// - TruthSensor: the robot's exact ground truth at a fixed rate (porter-sim publishes it on
//   SIM_TRUTH for tests, the validator and the demo's clearance figure).
// - LioPoseSensor: the stand-in for the real robot's LiDAR-inertial odometry (FAST-LIO2 there):
//   the base pose at a fixed rate with optional zero-mean Gaussian noise on x, y and yaw
//   (independent per sample, from a seeded generator so a run is reproducible), published on
//   LIO_POSE.
// Samples fall on the grid k / rate_hz (k = 1, 2, ...) of simulated time, whatever the step.
// Both hand their samples to a callback (porter-sim's publishes them; tests collect them).
//
// Thread-safety: simulation thread only.

#include <array>
#include <cstdint>
#include <functional>
#include <random>
#include <string>

#include "porter/sim/sensor.hpp"

namespace porter::sim {

class TruthSensor final : public SimSensor {
 public:
  using Callback = std::function<void(const RobotSample&)>;
  /// rate_hz > 0.
  TruthSensor(double rate_hz, Callback callback);
  std::string name() const override { return "truth"; }
  void advance(const World& world, double t0_s, double t1_s) override;

 private:
  double period_s_;
  Callback callback_;
};

struct LioNoise {
  double position_sigma_m = 0.0;  ///< per axis (x, y)
  double yaw_sigma_rad = 0.0;
  std::uint64_t seed = 1;
};

/// One LIO pose: B in W at t_s, with its covariance (row-major 6x6 over [x, y, z, rot_x, rot_y,
/// rot_z]; all zero when there is no noise).
struct PoseSample {
  double t_s = 0.0;
  BasePose pose_W;
  std::array<double, 36> covariance{};
  bool has_covariance = false;
};

class LioPoseSensor final : public SimSensor {
 public:
  using Callback = std::function<void(const PoseSample&)>;
  /// rate_hz > 0, sigmas >= 0.
  LioPoseSensor(double rate_hz, const LioNoise& noise, Callback callback);
  std::string name() const override { return "lio_pose"; }
  void advance(const World& world, double t0_s, double t1_s) override;

 private:
  double period_s_;
  LioNoise noise_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
  Callback callback_;
};

}  // namespace porter::sim
