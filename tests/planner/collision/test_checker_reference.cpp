#include <gtest/gtest.h>

#include <cmath>
#include <ostream>
#include <random>

#include "collision_test_utils.hpp"
#include "porter/core/kinematics.hpp"
#include "porter/core/scene_voxelizer.hpp"
#include "porter/planner/collision/kernel_collision_checker.hpp"
#include "reference_collision.hpp"

namespace porter::planner {
namespace {

struct SweepCase {
  std::string scene;
  std::string payload;
  double margin_m;
  int configurations;
};

void PrintTo(const SweepCase& c, std::ostream* os) {
  *os << c.scene << "/" << c.payload << " margin " << c.margin_m << " m, " << c.configurations << " configurations";
}

std::string case_name(const ::testing::TestParamInfo<SweepCase>& info) {
  return info.param.scene + "_" + info.param.payload + "_margin" +
         std::to_string(static_cast<int>(info.param.margin_m * 100));
}

class CheckerReferenceSweep : public ::testing::TestWithParam<SweepCase> {};

// Random whole-body configurations near obstacles (the environment check with a 0.3 m larger
// margin flags them; three in four that the kernel check rejects are dropped to enrich the
// sample in free configurations close to obstacles): the kernel check misses no collision of the exact geometry at
// voxel level (reference), and every collision it reports that the reference does not have lies within the documented
// inflation of the flagged voxels.
TEST_P(CheckerReferenceSweep, EnvironmentHasNoFalseNegativesAndBoundedFalsePositives) {
  const SweepCase& p = GetParam();
  const RobotModel model = test::shipped_robot_with(p.payload);
  const Scene scene = test::shipped_scene(p.scene);
  const OccupancyGrid grid = voxelize(scene);
  KernelCheckerSettings s;
  s.map.safety_margin_m = p.margin_m;
  s.self.prove_pairs = false;  // self-collision is not exercised here
  KernelCollisionChecker checker(model, s);
  checker.set_map(grid);
  KernelCheckerSettings wide = s;
  wide.map.safety_margin_m = p.margin_m + 0.3;
  KernelCollisionChecker near(model, wide);
  near.set_map(grid);
  const test::ReferenceEnvironment reference(grid, p.margin_m);
  const double h = grid.resolution_m();

  std::mt19937_64 rng(1000 + static_cast<std::uint64_t>(p.configurations));
  int tested = 0, ref_hits = 0, kernel_hits = 0, false_positives = 0;
  while (tested < p.configurations) {
    const RobotConfiguration c = test::random_configuration(model, scene, rng, 0.1);
    if (!near.check_environment(c).in_collision) continue;  // not near anything
    const CollisionResult k = checker.check_environment(c);
    // Random arms mostly end in a wall or the ground; keep a quarter of those so that free
    // configurations close to obstacles (the hard case) make up a good part of the sweep.
    if (k.in_collision && rng() % 4 != 0) continue;
    ++tested;
    const int r = reference.first_colliding_link(model, c);
    ref_hits += r >= 0;
    kernel_hits += k.in_collision;
    if (r >= 0) {
      ASSERT_TRUE(k.in_collision) << "false negative: link " << r << " at base (" << c.base.x_m << ", " << c.base.y_m
                                  << ", " << c.base.yaw_rad << ") q = " << c.q_rad.transpose();
    } else if (k.in_collision) {
      ++false_positives;
      KinematicsWorkspace ws;
      forward_kinematics(model, c, ws);
      const double bound = checker.kernels().inflation_bound_m(k.link) + 0.5 * std::sqrt(3.0) * h + 1e-6;
      ASSERT_TRUE(reference.link_within(model, ws, k.link, bound))
          << "false positive beyond the inflation bound: link " << k.link << " at base (" << c.base.x_m << ", "
          << c.base.y_m << ", " << c.base.yaw_rad << ") q = " << c.q_rad.transpose();
    }
  }
  // Both outcomes must be well represented for the sweep to mean anything.
  EXPECT_GT(ref_hits, p.configurations / 10);
  EXPECT_GT(tested - kernel_hits, p.configurations / 10);
  RecordProperty("reference_collisions", ref_hits);
  RecordProperty("kernel_collisions", kernel_hits);
  RecordProperty("false_positives", false_positives);
}

INSTANTIATE_TEST_SUITE_P(
    ShippedScenes, CheckerReferenceSweep,
    ::testing::Values(SweepCase{"tunnel", "t_bar", 0.0, 10000}, SweepCase{"tunnel", "long_bar", 0.0, 10000},
                      SweepCase{"tunnel", "arc", 0.0, 10000}, SweepCase{"forest", "t_bar", 0.0, 10000},
                      SweepCase{"forest", "long_bar", 0.0, 10000}, SweepCase{"forest", "arc", 0.0, 10000},
                      SweepCase{"tunnel", "t_bar", 0.12, 2000}),
    case_name);

}  // namespace
}  // namespace porter::planner
