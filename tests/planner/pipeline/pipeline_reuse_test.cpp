// One Planner for many plans and maps: the robot side (kernels and self-collision proofs, per-link
// SDFs) is built once and never again for a new map (counted, not timed); the same request on the
// same map gives the same plan again; a refused map and a missing map are statuses; a canceled
// request returns before planning; another acceptance test can replace the kernel check.
#include <chrono>
#include <memory>
#include <thread>

#include <gtest/gtest.h>

#include "pipeline_fixtures.hpp"
#include "porter/backend/robot_sdf.hpp"
#include "porter/planner/collision/kernel_robot.hpp"

namespace porter::pipeline {
namespace {

TEST(PipelineReuse, ANewMapDoesNotRebuildTheRobotSide) {
  // Bridge h_b 1.1 m seed 4 and h_b 1.0 m seed 1 both need the back-end (recorded statuses:
  // pipeline_bridge_test.cpp), so both plans use every robot-side part.
  const Scene a = testing::scene("bridge", 1.1, 4);
  const Scene b = testing::scene("bridge", 1.0, 1);
  PlannerSettings settings = testing::shipped_settings(a);
  testing::generous_budgets(settings);
  const std::int64_t kernels0 = planner::KernelRobot::build_count();
  const std::int64_t sdf0 = backend::RobotSdf::build_count();
  Planner planner(testing::robot_for(a), settings);
  EXPECT_EQ(planner::KernelRobot::build_count(), kernels0 + 1);
  EXPECT_EQ(backend::RobotSdf::build_count(), sdf0);  // the back-end's side waits for a back-end

  ASSERT_TRUE(planner.set_map(voxelize(a)).ok);
  const PlanResult first = planner.plan(testing::request(a));
  ASSERT_TRUE(first.backend.has_value()) << "the fixture needs the back-end";
  EXPECT_GT(first.setup_s, 0.0);
  EXPECT_GT(first.backend->setup_s, 0.0);
  EXPECT_EQ(backend::RobotSdf::build_count(), sdf0 + 1);

  const MapUpdate update = planner.set_map(voxelize(b));
  ASSERT_TRUE(update.ok) << update.message;
  EXPECT_TRUE(update.incremental);  // same grid geometry, another deck height
  EXPECT_GT(update.changed_voxels, 0);
  const PlanResult second = planner.plan(testing::request(b));
  ASSERT_TRUE(second.backend.has_value()) << "the fixture needs the back-end";
  EXPECT_EQ(second.status, planner::Status::kSuccess) << second.message;
  EXPECT_EQ(second.setup_s, 0.0);
  EXPECT_EQ(second.backend->setup_s, 0.0);
  EXPECT_EQ(planner::KernelRobot::build_count(), kernels0 + 1);
  EXPECT_EQ(backend::RobotSdf::build_count(), sdf0 + 1);
  EXPECT_TRUE(planner.setup().backend_ready);
}

TEST(PipelineReuse, TheSameRequestOnTheSameMapGivesTheSamePlan) {
  const Scene s = testing::scene("bridge", 1.1, 6);  // retry, then the back-end
  PlannerSettings settings = testing::shipped_settings(s);
  testing::generous_budgets(settings);
  Planner planner(testing::robot_for(s), settings);
  ASSERT_TRUE(planner.set_map(voxelize(s)).ok);
  const PlanResult a = planner.plan(testing::request(s));
  const PlanResult b = planner.plan(testing::request(s));
  ASSERT_TRUE(a.trajectory && b.trajectory);
  ASSERT_TRUE(a.backend && b.backend) << "the fixture needs the back-end";
  EXPECT_EQ(a.backend->result.evaluations, b.backend->result.evaluations);
  ASSERT_EQ(a.trajectory->num_pieces(), b.trajectory->num_pieces());
  for (int i = 0; i < a.trajectory->num_pieces(); ++i) {
    EXPECT_EQ(a.trajectory->piece(i).duration_s, b.trajectory->piece(i).duration_s) << i;
    EXPECT_EQ(a.trajectory->piece(i).coeffs, b.trajectory->piece(i).coeffs) << i;
  }
}

TEST(PipelineReuse, MapsAndCancellationAreStatuses) {
  const Scene s = testing::scene("empty");
  Planner planner(testing::robot_for(s), testing::shipped_settings(s));
  EXPECT_EQ(planner.plan(testing::request(s)).status, planner::Status::kNoMap);
  // A map at another resolution than the kernels' is refused (and leaves no map).
  const OccupancyGrid coarse(Eigen::Vector3d(-1.0, -3.0, 0.0), 0.1, Eigen::Vector3i(110, 60, 25));
  const MapUpdate refused = planner.set_map(coarse);
  EXPECT_FALSE(refused.ok);
  EXPECT_NE(refused.message.find("resolution"), std::string::npos) << refused.message;
  EXPECT_EQ(planner.plan(testing::request(s)).status, planner::Status::kNoMap);
  ASSERT_TRUE(planner.set_map(voxelize(s)).ok);
  planner::CancelFlag cancel;
  cancel.request();
  PlanRequest req = testing::request(s);
  req.cancel = &cancel;
  const PlanResult canceled = planner.plan(req);
  EXPECT_EQ(canceled.status, planner::Status::kCanceled);
  EXPECT_FALSE(canceled.frontend.has_value());
  cancel.reset();
  EXPECT_EQ(planner.plan(req).status, planner::Status::kSuccess);
}

TEST(PipelineReuse, AnotherThreadCancelsARunningPlan) {
  // Forest, budgets that no stage reaches: the back-end alone runs for seconds (200 iterations),
  // so the plan is still running when the flag is set 50 ms in.
  const Scene s = testing::scene("forest", -1.0, 2);
  PlannerSettings settings = testing::shipped_settings(s);
  testing::generous_budgets(settings);
  Planner planner(testing::robot_for(s), settings);
  ASSERT_TRUE(planner.set_map(voxelize(s)).ok);
  planner.prepare_backend();
  planner::CancelFlag cancel;
  PlanRequest req = testing::request(s);
  req.cancel = &cancel;
  std::thread canceller([&cancel] {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    cancel.request();
  });
  const PlanResult r = planner.plan(req);
  canceller.join();
  EXPECT_EQ(r.status, planner::Status::kCanceled) << r.message;
  // The stage that saw it says so.
  const bool stage_canceled = (r.frontend && r.frontend->status == planner::Status::kCanceled) ||
                              (r.midend && r.midend->result.status == planner::Status::kCanceled) ||
                              (r.backend && r.backend->result.status == planner::Status::kCanceled);
  EXPECT_TRUE(stage_canceled || r.message == "canceled") << r.message;
}

/// An acceptance test that refuses everything: the pipeline must consult it for the mid-end's
/// trajectory and report the refusal.
class RefuseAll final : public planner::TrajectoryAcceptance {
 public:
  planner::AcceptanceResult check(const Trajectory&) const override {
    ++calls;
    return planner::AcceptanceResult{false, 3, -1};
  }
  std::string name() const override { return "refuse-all"; }
  mutable int calls = 0;
};

TEST(PipelineReuse, TheAcceptanceTestIsOneReplaceableStep) {
  const Scene s = testing::scene("empty");
  PlannerSettings settings = testing::shipped_settings(s);
  settings.pipeline.retry_arm_residual_scale = 1.0;  // no retry: one acceptance test per mid-end
  Planner planner(testing::robot_for(s), settings);
  ASSERT_TRUE(planner.set_map(voxelize(s)).ok);
  auto refuse = std::make_shared<RefuseAll>();
  planner.set_acceptance(refuse);
  const PlanResult r = planner.plan(testing::request(s, Stages::kMid));
  EXPECT_EQ(r.status, planner::Status::kInCollision) << r.message;
  EXPECT_EQ(refuse->calls, 1);
  ASSERT_TRUE(r.final_check.has_value());
  EXPECT_EQ(r.final_check->checker, "refuse-all");
  EXPECT_EQ(r.final_check->result.link, 3);
  planner.set_acceptance(nullptr);  // back to the kernel check: the empty scene's plan is accepted
  EXPECT_EQ(planner.plan(testing::request(s, Stages::kMid)).status, planner::Status::kSuccess);
}

}  // namespace
}  // namespace porter::pipeline
