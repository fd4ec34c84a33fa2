// End to end on the ablation scene through the planning pipeline: bridge at h_b = 0.9 m with the T
// payload, seed 4, budgets large enough that no stage stops on time (the same run on any machine),
// the mid-end retry off so that the back-end starts from the mid-end's first trajectory, which the
// kernel check rejects; the back-end must come out collision-free under the same check, reaching
// the same goal.

#include <gtest/gtest.h>

#include "backend_fixtures.hpp"
#include "porter/core/scene_loader.hpp"
#include "porter/core/scene_voxelizer.hpp"
#include "porter/pipeline/planner.hpp"

namespace porter::backend {
namespace {

TEST(BackendBridge, MidendCollisionComesOutCollisionFreeAtHb09) {
  SceneLoadOptions options;
  options.parameter_overrides["h_b"] = 0.9;
  options.seed = 4;
  const Scene scene = load_scene(testing::source_dir() + "/config/scenes/bridge.yaml", options);
  pipeline::PlannerSettings settings;
  settings.kernels.kernels.resolution_m = scene.resolution_m;
  settings.pipeline.frontend_budget_s = 20.0;
  settings.pipeline.midend_budget_s = 2.0;
  settings.pipeline.backend_budget_s = 20.0;
  settings.pipeline.retry_arm_residual_scale = 1.0;  // no retry: the back-end gets the first solve
  pipeline::Planner planner(testing::robot("t_bar"), settings);  // the scene's payload
  ASSERT_TRUE(planner.set_map(voxelize(scene)).ok);
  pipeline::PlanRequest req;
  req.start = pipeline::StartState::at_rest(scene.start);
  req.goal = pipeline::GoalSpec::exact(scene.goal);
  req.seed = scene.seed;
  const pipeline::PlanResult p = planner.plan(req);
  ASSERT_TRUE(p.midend.has_value()) << p.message;
  ASSERT_TRUE(p.midend->result.ok()) << p.midend->result.message;
  ASSERT_FALSE(p.midend->acceptance.accepted) << "the fixture must need the back-end";
  ASSERT_TRUE(p.midend->retry.empty());
  ASSERT_TRUE(p.backend.has_value());
  const BackendResult& r = p.backend->result;
  ASSERT_TRUE(r.ok()) << to_string(r.status) << ": " << r.message;
  EXPECT_EQ(r.check, SafetyCheck::kCollisionFree) << "link " << r.collision_link << " Js " << r.initial_cost.safety << " -> " << r.final_cost.safety << " min d " << r.final_cost.safety_stats.min_distance_m << " it " << r.iterations << " " << r.message;
  EXPECT_EQ(r.safety_term, "kc_svsdf");
  EXPECT_EQ(p.status, planner::Status::kSuccess) << p.message;
  // The penalty drops and no obstacle point is left inside a link. (The solve stops at the first
  // iterate the kernel check passes, so how far J_s falls depends on the path: no ratio here.)
  EXPECT_LT(r.final_cost.safety, r.initial_cost.safety);
  EXPECT_EQ(r.final_cost.safety_stats.inside, 0);
  EXPECT_GT(r.iterations, 0);
  // Same start and goal as the mid-end's trajectory.
  const Trajectory& t = *r.trajectory;
  const Trajectory& m = *p.midend->result.trajectory;
  EXPECT_LT((t.position(0.0) - m.position(0.0)).norm(), 1e-6);
  EXPECT_LT((t.position(t.total_duration_s()) - m.position(m.total_duration_s())).norm(), 1e-6);
}

}  // namespace
}  // namespace porter::backend
