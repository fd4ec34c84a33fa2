// End to end on the ablation scene: bridge at h_b = 0.9 m with the T payload. The front-end plans
// with seed 4 and a generous budget (it finishes on its iteration counts, so the path is the same
// on any machine); the mid-end follows the path and is left in collision (kernel check); the
// back-end, warm started from it, must come out collision-free under the same kernel check,
// reaching the same goal. (A hand-made path used to serve here; since the kernels' inflation
// dropped to ~6 cm the mid-end got it through the hole on its own.)

#include <gtest/gtest.h>

#include "backend_fixtures.hpp"
#include "porter/backend/backend.hpp"
#include "porter/backend/svsdf_safety_term.hpp"
#include "porter/core/scene_loader.hpp"
#include "porter/core/scene_voxelizer.hpp"
#include "porter/frontend/frontend.hpp"
#include "porter/midend/midend.hpp"
#include "porter/pipeline/kernel_acceptance.hpp"
#include "porter/planner/collision/kernel_collision_checker.hpp"

namespace porter::backend {
namespace {

TEST(BackendBridge, MidendCollisionComesOutCollisionFreeAtHb09) {
  SceneLoadOptions options;
  options.parameter_overrides["h_b"] = 0.9;
  options.seed = 4;
  const Scene scene = load_scene(testing::source_dir() + "/config/scenes/bridge.yaml", options);
  const OccupancyGrid grid = voxelize(scene);
  const RobotModel& model = testing::robot("t_bar");  // the scene's payload
  planner::KernelCollisionChecker checker(model);
  checker.set_map(grid);

  frontend::FrontEnd fe(model, checker);
  fe.set_map(grid);
  const frontend::FrontendResult f = fe.plan(scene.start, scene.goal, 20.0, scene.seed);
  ASSERT_EQ(f.status, planner::Status::kSuccess) << f.message;
  const planner::WholeBodyPath& path = f.path;

  const midend::MidEnd mid(model);
  const midend::MidendResult m = mid.solve(path, 2.0);
  ASSERT_TRUE(m.ok()) << m.message;
  ASSERT_TRUE(checker.check_trajectory(*m.trajectory).in_collision) << "the fixture must need the back-end";

  const BackEnd backend(model, BackendSettings{});
  SvsdfSafetyTerm safety(model, testing::robot_sdf("t_bar"), SvsdfSafetySettings{});
  // A generous budget: the outcome must not depend on the machine's speed.
  ASSERT_TRUE(m.solution.has_value());
  const pipeline::KernelAcceptance acceptance(checker);
  const BackendResult r = backend.solve(*m.solution, grid, safety, planner::Deadline(20.0), &acceptance);
  ASSERT_TRUE(r.ok()) << to_string(r.status) << ": " << r.message;
  EXPECT_EQ(r.check, SafetyCheck::kCollisionFree) << "link " << r.collision_link << " Js " << r.initial_cost.safety << " -> " << r.final_cost.safety << " min d " << r.final_cost.safety_stats.min_distance_m << " it " << r.iterations << " " << r.message;
  EXPECT_EQ(r.safety_term, "kc_svsdf");
  // The penalty drops and no obstacle point is left inside a link. (The solve stops at the first
  // iterate the kernel check passes, so how far J_s falls depends on the path: no ratio here.)
  EXPECT_LT(r.final_cost.safety, r.initial_cost.safety);
  EXPECT_EQ(r.final_cost.safety_stats.inside, 0);
  EXPECT_GT(r.iterations, 0);
  // Same start and goal as the mid-end's trajectory.
  const Trajectory& t = *r.trajectory;
  EXPECT_LT((t.position(0.0) - m.trajectory->position(0.0)).norm(), 1e-6);
  EXPECT_LT((t.position(t.total_duration_s()) - m.trajectory->position(m.trajectory->total_duration_s())).norm(), 1e-6);
}

}  // namespace
}  // namespace porter::backend
