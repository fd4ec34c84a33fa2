#include <gtest/gtest.h>

#include <random>

#include "collision_test_utils.hpp"
#include "porter/planner/collision/self_collision.hpp"
#include "reference_collision.hpp"

namespace porter::planner {
namespace {

class SelfCollisionSweep : public ::testing::TestWithParam<std::string> {};

// Random joint configurations (the arm folds into itself, the base and the mast often):
// every overlap FCL finds is reported (no false negative), and every reported pair is within the
// stated inflation of each other. Pairs proven free at build time never overlap.
TEST_P(SelfCollisionSweep, NoFalseNegativeAndBoundedFalsePositives) {
  const RobotModel model = test::shipped_robot_with(GetParam());
  const SelfCollisionChecker checker(model, SelfCollisionSettings{});
  const test::ReferenceSelfCollision reference(model);
  const KernelKinematics kin(model);
  std::mt19937_64 rng(31);
  int ref_hits = 0, kernel_hits = 0, false_positives = 0;
  for (int i = 0; i < 3000; ++i) {
    const JointVector q = test::random_joints(model, rng);
    ArmPoses poses;
    kin.compute(q, poses);
    const CollisionResult r = checker.check(poses);
    bool any_ref = false;
    for (int a = 0; a < kNumLinks; ++a)
      for (int b = a + 1; b < kNumLinks; ++b) {
        const PairStatus st = checker.pair_status(a, b);
        if (st == PairStatus::kAllowed) continue;
        const bool hit = reference.pair_collides(q, a, b);
        if (st == PairStatus::kProvenFree) {
          ASSERT_FALSE(hit) << "proven pair " << a << "," << b;
        }
        any_ref = any_ref || hit;
      }
    ref_hits += any_ref;
    kernel_hits += r.in_collision;
    if (any_ref) {
      ASSERT_TRUE(r.in_collision) << "missed self-collision at q = " << q.transpose();
    }
    if (r.in_collision) {
      ASSERT_LT(r.link, r.other_link);
      EXPECT_EQ(checker.pair_status(r.link, r.other_link), PairStatus::kChecked);
      if (!any_ref) {
        ++false_positives;
        EXPECT_LE(reference.pair_distance(q, r.link, r.other_link), checker.inflation_bound_m() + 1e-6)
            << r.link << "," << r.other_link << " at q = " << q.transpose();
      }
    }
  }
  EXPECT_GT(ref_hits, 100);  // the sweep does exercise self-collisions
  EXPECT_LE(false_positives, kernel_hits);
  RecordProperty("reference_hits", ref_hits);
  RecordProperty("false_positives", false_positives);
}

INSTANTIATE_TEST_SUITE_P(Payloads, SelfCollisionSweep, ::testing::Values("t_bar", "long_bar", "arc"));

TEST(SelfCollision, AllowedAndProvenPairsAreNotChecked) {
  const RobotModel model = test::shipped_robot_with("t_bar");
  const SelfCollisionChecker checker(model, SelfCollisionSettings{});
  for (int a = 0; a < kNumLinks; ++a) {
    EXPECT_EQ(checker.pair_status(a, a), PairStatus::kAllowed);
    for (int b = 0; b < kNumLinks; ++b) {
      EXPECT_EQ(checker.pair_status(a, b), checker.pair_status(b, a));
      if (model.allowed_collisions[static_cast<std::size_t>(a)][static_cast<std::size_t>(b)]) {
        EXPECT_EQ(checker.pair_status(a, b), PairStatus::kAllowed);
      }
    }
  }
  // The payload against the base and the mast is always checked at run time.
  EXPECT_EQ(checker.pair_status(0, kEndEffectorLink), PairStatus::kChecked);
  SelfCollisionSettings no_proofs;
  no_proofs.prove_pairs = false;
  const SelfCollisionChecker unproven(model, no_proofs);
  EXPECT_GE(unproven.num_checked_pairs(), checker.num_checked_pairs());
  EXPECT_NEAR(checker.inflation_bound_m(), 0.01 * std::sqrt(3.0), 2e-4);
}

TEST(SelfCollision, HandPickedPoses) {
  const RobotModel model = test::shipped_robot_with("t_bar");
  const SelfCollisionChecker checker(model, SelfCollisionSettings{});
  const test::ReferenceSelfCollision reference(model);
  const KernelKinematics kin(model);
  auto check = [&](const JointVector& q) {
    ArmPoses poses;
    kin.compute(q, poses);
    return checker.check(poses);
  };
  JointVector carry;  // the scenes' carrying pose: clear of itself
  carry << 0.0, 0.6, -0.9, 0.0, 0.5, 0.0;
  EXPECT_FALSE(check(carry).in_collision);
  EXPECT_EQ(reference.first_colliding_pair(carry)[0], -1);
  // Shoulder laid back and elbow folded: the T bar swings down through the base and the mast.
  JointVector down;
  down << 3.0, 2.8, -0.3, 0.0, 0.0, 0.0;
  const auto ref = reference.first_colliding_pair(down);
  ASSERT_NE(ref[0], -1) << "pose expected to collide";
  EXPECT_TRUE(check(down).in_collision);
}

}  // namespace
}  // namespace porter::planner
