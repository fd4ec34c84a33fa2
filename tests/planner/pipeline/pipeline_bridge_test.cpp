// The same plans as before the pipeline became a library: bridge ablation seeds through
// porter::pipeline::Planner give the statuses porter-plan recorded for them (--stages full,
// budgets large enough that no stage stops on time, back-end capped at 200 iterations: the
// outcome does not depend on the machine). A few seeds, one per kind of run: accepted directly,
// a self-colliding mid-end solve retried, a retry accepted directly, the back-end from the
// retry and from the first solve. One Planner for all of them, the map set once per h_b.
#include <optional>
#include <string>

#include <gtest/gtest.h>

#include "pipeline_fixtures.hpp"

namespace porter::pipeline {
namespace {

struct Recorded {
  double h_b;
  int seed;
  const char* retry;         ///< prefix of MidendReport::retry ("" none)
  bool direct;               ///< the mid-end's trajectory was accepted
  int warm_start;            ///< the back-end's warm start (-1: no back-end)
};

// From porter-plan --scene config/scenes/bridge.yaml --set h_b=H --seed S --stages full
// --frontend-budget-ms 20000 --midend-budget-ms 20000 --backend-budget-ms 120000
// --backend-iterations 200, before the pipeline library: every run below had front-end success,
// mid-end converged, a back-end (when it ran) converged and a final trajectory the kernel check
// accepted (exit 0). The warm starts of h_b 1.1 seeds 4 and 6 were recorded again (1 -> 0 and
// 0 -> 1) when the mid-end's rest-boundary heading term became exact: both solves' J_s changed
// and the lower is now the other one; every status is as recorded.
const Recorded kRecorded[] = {
    {1.1, 2, "", true, -1},
    {1.1, 17, "self-collision (links 1-4)", true, -1},
    {1.1, 4, "in collision (link 7)", false, 0},
    {1.1, 6, "in collision (link 7)", false, 1},
    {1.0, 5, "in collision (link 7)", true, -1},
    {0.8, 1, "self-collision (links 1-7)", true, -1},
    {0.8, 12, "in collision (link 7)", false, 0},
};

TEST(PipelineBridge, AblationSeedsGiveTheRecordedStatuses) {
  const Scene first = testing::scene("bridge", 1.1);
  PlannerSettings settings = testing::shipped_settings(first);
  testing::generous_budgets(settings);
  settings.pipeline.choose_warm_start_by_safety = true;  // as recorded (the warm-start column)
  Planner planner(testing::robot_for(first), settings);
  double h_b = -1.0;
  for (const Recorded& rec : kRecorded) {
    const std::string label = "h_b " + std::to_string(rec.h_b) + " seed " + std::to_string(rec.seed);
    const Scene scene = testing::scene("bridge", rec.h_b, static_cast<std::uint64_t>(rec.seed));
    if (rec.h_b != h_b) {
      ASSERT_TRUE(planner.set_map(voxelize(scene)).ok) << label;
      h_b = rec.h_b;
    }
    const PlanResult r = planner.plan(testing::request(scene));
    ASSERT_TRUE(r.frontend.has_value()) << label << ": " << r.message;
    EXPECT_EQ(r.frontend->status, planner::Status::kSuccess) << label;
    ASSERT_TRUE(r.midend.has_value()) << label << ": " << r.message;
    EXPECT_EQ(r.midend->result.status, planner::Status::kConverged) << label << ": " << r.midend->result.message;
    EXPECT_EQ(r.midend->retry.rfind(rec.retry, 0), 0u) << label << ": " << r.midend->retry;
    EXPECT_EQ(r.midend->retry.empty(), std::string(rec.retry).empty()) << label << ": " << r.midend->retry;
    EXPECT_EQ(r.midend->acceptance.accepted, rec.direct) << label;
    EXPECT_EQ(r.backend.has_value(), rec.warm_start >= 0) << label;
    if (r.backend && rec.warm_start >= 0) {
      EXPECT_EQ(r.backend->result.status, planner::Status::kConverged) << label << ": " << r.backend->result.message;
      EXPECT_EQ(r.backend->warm_start, rec.warm_start) << label;
      EXPECT_EQ(r.final_check->stage, "backend") << label;
    }
    EXPECT_EQ(r.status, planner::Status::kSuccess) << label << ": " << r.message;
    ASSERT_TRUE(r.final_check.has_value()) << label;
    EXPECT_TRUE(r.final_check->result.accepted) << label;
    ASSERT_TRUE(r.trajectory.has_value()) << label;
    // The answer is accepted by an independent run of the same test.
    EXPECT_FALSE(planner.kernel_checker().check_trajectory(*r.trajectory).in_collision) << label;
  }
}

}  // namespace
}  // namespace porter::pipeline
