#pragma once
// Test fixture: the shipped robot carrying the T bar and its kernel checker, built once per test
// suite (the kernels take a few hundred milliseconds), plus the carrying pose the scenes use.

#include <gtest/gtest.h>

#include "collision_test_utils.hpp"
#include "porter/planner/collision/kernel_collision_checker.hpp"

namespace porter::test {

/// Base at (x, y, yaw), arm in the scenes' carrying configuration with joint 1 at q1.
inline RobotConfiguration carrying(double x, double y, double yaw, double q1 = 0.0) {
  RobotConfiguration c;
  c.base = {x, y, yaw};
  c.q_rad << q1, 0.6, -0.9, 0.0, 0.5, 0.0;
  return c;
}

class TBarCheckerSuite : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    model_ = new RobotModel(shipped_robot_with("t_bar"));
    checker_ = new planner::KernelCollisionChecker(*model_);
  }
  static void TearDownTestSuite() {
    delete checker_;
    delete model_;
    checker_ = nullptr;
    model_ = nullptr;
  }
  static inline RobotModel* model_ = nullptr;
  static inline planner::KernelCollisionChecker* checker_ = nullptr;
};

}  // namespace porter::test
