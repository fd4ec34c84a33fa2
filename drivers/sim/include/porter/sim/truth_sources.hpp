#pragma once
// Where the simulated world takes the robot's ground truth from: the base pose from the device
// that moves the base (the Scout Mini firmware model integrates it), the arm's joint angles from
// the device that moves the arm (the Piper firmware model), or fixed values when no such device
// is hosted. porter-sim reads both after every step.
//
//   sim.set_base_source(std::make_unique<FunctionBaseSource>([&fw] { ... fw.pose() ... }));
//   sim.set_joint_source(std::make_unique<FixedJointSource>(scene.start.q_rad));
//
// A device model does not need to know these interfaces: wrap its accessors in the Function*
// adapters (a few lines where porter-sim builds its devices).
//
// Frames and units: the base pose is B in W (x, y of B's origin, heading of x_B), velocities of
// B in B; joint angles in the robot model's convention (URDF joint1..joint6), rad and rad/s.
// Thread-safety: called from the simulation thread only.

#include <functional>
#include <utility>

#include "porter/core/types.hpp"

namespace porter::sim {

struct BaseTruth {
  BasePose pose_W;            ///< B in W
  double v_mps = 0.0;         ///< forward speed of B along x_B
  double omega_radps = 0.0;   ///< yaw rate about z
};

struct JointTruth {
  JointVector q_rad = JointVector::Zero();
  JointVector qd_radps = JointVector::Zero();
};

class BaseSource {
 public:
  virtual ~BaseSource() = default;
  virtual BaseTruth base_truth() const = 0;
};

class JointSource {
 public:
  virtual ~JointSource() = default;
  virtual JointTruth joint_truth() const = 0;
};

/// A base that never moves (no base device hosted).
class FixedBaseSource final : public BaseSource {
 public:
  explicit FixedBaseSource(const BasePose& pose_W) { truth_.pose_W = pose_W; }
  BaseTruth base_truth() const override { return truth_; }

 private:
  BaseTruth truth_;
};

/// An arm held at fixed angles (no arm device hosted).
class FixedJointSource final : public JointSource {
 public:
  explicit FixedJointSource(const JointVector& q_rad) { truth_.q_rad = q_rad; }
  JointTruth joint_truth() const override { return truth_; }

 private:
  JointTruth truth_;
};

class FunctionBaseSource final : public BaseSource {
 public:
  explicit FunctionBaseSource(std::function<BaseTruth()> fn) : fn_(std::move(fn)) {}
  BaseTruth base_truth() const override { return fn_(); }

 private:
  std::function<BaseTruth()> fn_;
};

class FunctionJointSource final : public JointSource {
 public:
  explicit FunctionJointSource(std::function<JointTruth()> fn) : fn_(std::move(fn)) {}
  JointTruth joint_truth() const override { return fn_(); }

 private:
  std::function<JointTruth()> fn_;
};

}  // namespace porter::sim
