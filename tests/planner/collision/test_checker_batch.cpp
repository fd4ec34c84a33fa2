#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <vector>

#include "collision_test_utils.hpp"
#include "porter/core/scene_voxelizer.hpp"
#include "porter/planner/collision/kernel_collision_checker.hpp"

namespace porter::planner {
namespace {

// The batch path shares the tree walks with check() but computes forward kinematics, the
// links' root spheres and the self-collision sphere tests in lanes: its answers must be check()'s,
// field by field, for every kind of outcome (free, each link in collision, self-collision, joint
// limits, NaN, base off the map) and for batch sizes that do not fill the last eight lanes.
std::vector<RobotConfiguration> mixed_configurations(const RobotModel& model, const Scene& scene,
                                                     const KernelCollisionChecker& near, int count,
                                                     std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<RobotConfiguration> out;
  while (static_cast<int>(out.size()) < count) {
    RobotConfiguration c = test::random_configuration(model, scene, rng, 0.1);
    switch (rng() % 16) {
      case 0:  // a joint beyond its limit by a radian
        c.q_rad[static_cast<int>(rng() % kNumArmJoints)] += (rng() % 2 ? 1.0 : -1.0) * 3.0;
        break;
      case 1:  // NaN somewhere
        if (rng() % 2)
          c.base.yaw_rad = std::nan("");
        else
          c.q_rad[static_cast<int>(rng() % kNumArmJoints)] = std::nan("");
        break;
      case 2:  // base off the map
        c.base.x_m = scene.bounds_W.max().x() + 1.0;
        break;
      case 3:
      case 4:  // an arm in self-collision (the environment may still be hit first)
        while (!near.check_self(c.q_rad).in_collision) c.q_rad = test::random_joints(model, rng);
        break;
      default:  // mostly near obstacles, where the walks run
        if (!near.check_environment(c).in_collision && rng() % 4 != 0) continue;
        break;
    }
    out.push_back(c);
  }
  return out;
}

void expect_batch_matches_single(const KernelCollisionChecker& checker, const std::vector<RobotConfiguration>& configs,
                                 std::map<int, int>* outcomes) {
  std::vector<CollisionResult> batch(configs.size());
  checker.check_batch(configs.data(), configs.size(), batch.data());
  for (std::size_t i = 0; i < configs.size(); ++i) {
    const CollisionResult one = checker.check(configs[i]);
    ASSERT_EQ(batch[i].in_collision, one.in_collision) << "configuration " << i;
    ASSERT_EQ(batch[i].link, one.link) << "configuration " << i;
    ASSERT_EQ(batch[i].other_link, one.other_link) << "configuration " << i;
    if (outcomes) ++(*outcomes)[one.in_collision ? (one.other_link >= 0 ? 100 : one.link) : -1];
  }
}

class CheckerBatch : public ::testing::TestWithParam<std::string> {};

TEST_P(CheckerBatch, AnswersAsCheckDoesForEveryOutcome) {
  const RobotModel model = test::shipped_robot_with("t_bar");
  const Scene scene = test::shipped_scene(GetParam());
  const OccupancyGrid grid = voxelize(scene);
  KernelCollisionChecker checker(model);
  checker.set_map(grid);
  KernelCheckerSettings wide;
  wide.map.safety_margin_m = 0.3;
  KernelCollisionChecker near(model, wide);
  near.set_map(grid);
  const std::vector<RobotConfiguration> configs = mixed_configurations(model, scene, near, 6003, 77);
  std::map<int, int> outcomes;  // -1 free, 0..7 link, 100 self-collision
  expect_batch_matches_single(checker, configs, &outcomes);
  EXPECT_GT(outcomes[-1], 500);   // free
  EXPECT_GT(outcomes[0], 200);    // base, limits of the map, NaN
  EXPECT_GT(outcomes[7], 500);    // payload
  EXPECT_GT(outcomes[100], 20);   // self-collision
  int arm_links = 0;
  for (int link = 1; link <= 6; ++link) arm_links += outcomes[link];
  EXPECT_GT(arm_links, 200);  // links 1..6, including joints beyond their limits
  // Every batch size from 1 to 17 (partial last group) and an empty batch.
  for (std::size_t n = 0; n <= 17; ++n)
    expect_batch_matches_single(checker, std::vector<RobotConfiguration>(configs.begin() + 100, configs.begin() + 100 + n),
                                nullptr);
}

INSTANTIATE_TEST_SUITE_P(ShippedScenes, CheckerBatch, ::testing::Values("tunnel", "forest"));

TEST(CheckerBatchCases, NoMapAndSelfCollisionSwitchedOff) {
  const RobotModel model = test::shipped_robot_with("t_bar");
  const Scene scene = test::shipped_scene("tunnel");
  std::mt19937_64 rng(3);
  std::vector<RobotConfiguration> configs;
  for (int i = 0; i < 37; ++i) configs.push_back(test::random_configuration(model, scene, rng, 0.1));
  const KernelCollisionChecker fresh(model);
  std::vector<CollisionResult> out(configs.size());
  fresh.check_batch(configs.data(), configs.size(), out.data());
  for (const CollisionResult& r : out) {
    EXPECT_TRUE(r.in_collision);
    EXPECT_EQ(r.link, 0);
  }
  KernelCheckerSettings no_self;
  no_self.check_self_collision = false;
  KernelCollisionChecker checker(model, no_self);
  checker.set_map(voxelize(scene));
  KernelCheckerSettings wide = no_self;
  wide.map.safety_margin_m = 0.3;
  KernelCollisionChecker near(model, wide);
  near.set_map(voxelize(scene));
  std::map<int, int> outcomes;
  expect_batch_matches_single(checker, mixed_configurations(model, scene, near, 803, 5), &outcomes);
  EXPECT_EQ(outcomes[100], 0);
  EXPECT_GT(outcomes[-1], 50);
}

// The self-collision part on its own: only the lanes asked for are written, each with check()'s
// answer for that lane's configuration.
TEST(CheckerBatchCases, SelfCollisionLanesWriteOnlyTheLanesAskedFor) {
  const RobotModel model = test::shipped_robot_with("t_bar");
  const KernelCollisionChecker checker(model);
  const SelfCollisionChecker& self = checker.self_collision();
  std::mt19937_64 rng(21);
  int hits = 0;
  for (int trial = 0; trial < 600; ++trial) {
    std::array<JointVector, 8> q;
    std::array<const JointVector*, 8> qp{};
    for (std::size_t i = 0; i < 8; ++i) {
      q[i] = test::random_joints(model, rng);
      qp[i] = &q[i];
    }
    ArmPoseLanes lanes;
    checker.kinematics().compute_lanes(qp, lanes);
    const auto asked = static_cast<std::uint32_t>(rng() & 0xffu);
    std::array<CollisionResult, 8> out;
    for (CollisionResult& r : out) r.link = 42;  // marks an untouched result
    self.check_lanes(lanes, asked, out.data());
    for (int i = 0; i < 8; ++i) {
      if (!((asked >> i) & 1u)) {
        EXPECT_EQ(out[static_cast<std::size_t>(i)].link, 42);
        continue;
      }
      ArmPoses poses;
      checker.kinematics().compute(q[static_cast<std::size_t>(i)], poses);
      const CollisionResult one = self.check(poses);
      ASSERT_EQ(out[static_cast<std::size_t>(i)].in_collision, one.in_collision) << "trial " << trial << " lane " << i;
      ASSERT_EQ(out[static_cast<std::size_t>(i)].link, one.link);
      ASSERT_EQ(out[static_cast<std::size_t>(i)].other_link, one.other_link);
      hits += one.in_collision;
    }
  }
  EXPECT_GT(hits, 50);
}

}  // namespace
}  // namespace porter::planner

namespace porter::planner {
namespace {

// The interface's default batch checks one configuration at a time, in order.
class CountingChecker final : public CollisionChecker {
 public:
  void set_map(const OccupancyGrid&) override {}
  CollisionResult check(const RobotConfiguration& c) const override {
    ++calls;
    CollisionResult r;
    r.in_collision = c.base.x_m > 0.0;
    r.link = r.in_collision ? static_cast<int>(c.base.x_m) : -1;
    return r;
  }
  CollisionResult check_base(const BasePose&) const override { return {}; }
  CollisionResult check_motion(const RobotConfiguration&, const RobotConfiguration&) const override { return {}; }
  CollisionResult check_trajectory(const Trajectory&) const override { return {}; }
  CollisionResult check_trajectory_self(const Trajectory&) const override { return {}; }
  double inflation_bound_m(int) const override { return 0.0; }
  std::string name() const override { return "counting"; }
  mutable int calls = 0;
};

TEST(CheckerBatchCases, InterfaceDefaultChecksEachConfiguration) {
  CountingChecker counting;
  std::vector<RobotConfiguration> configs(11);
  for (std::size_t i = 0; i < configs.size(); ++i) configs[i].base.x_m = static_cast<double>(i % 3);
  std::vector<CollisionResult> out(configs.size());
  const CollisionChecker& checker = counting;
  checker.check_batch(configs.data(), configs.size(), out.data());
  EXPECT_EQ(counting.calls, 11);
  for (std::size_t i = 0; i < configs.size(); ++i) {
    EXPECT_EQ(out[i].in_collision, i % 3 != 0);
    EXPECT_EQ(out[i].link, i % 3 != 0 ? static_cast<int>(i % 3) : -1);
  }
}

}  // namespace
}  // namespace porter::planner
