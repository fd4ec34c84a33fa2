// porter-plan --stages full end to end: the back-end flags (--safety, --collision and the budgets)
// are validated with exit code 2, and on the ablation scene (bridge, h_b = 0.9 m) a mid-end
// trajectory in collision goes to the back-end, whose section, final re-check and trajectory are
// in the JSON result; the same seed gives the same result. The --self-collision-term flag, and a
// mid-end trajectory in collision solved again with both solves offered to the back-end.

#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "plan_cli_test.hpp"

namespace {

namespace fs = std::filesystem;

class PorterPlanFull : public porter::test::PlanCliTest {
 protected:
  static std::string scene(const std::string& name) {
    return std::string(PORTER_SOURCE_DIR) + "/config/scenes/" + name + ".yaml";
  }
  /// Bridge at h_b = 0.9 with budgets large enough that no stage stops on time: the front-end and
  /// mid-end converge, and the back-end stops at its iteration cap. Accepted by the kernel check
  /// (whose inflation makes the mid-end's trajectory collide here, so the back-end runs).
  std::string bridge_full(const std::string& out, const std::string& extra = "") const {
    return "--scene " + scene("bridge") + " --set h_b=0.9 --seed 4 --stages full --acceptance kernels" +
           " --frontend-budget-ms 20000" +
           " --midend-budget-ms 20000 --backend-budget-ms 120000 --backend-iterations 3 --out " +
           (dir_ / out).string() + " " + extra;
  }
};

TEST_F(PorterPlanFull, BadBackendFlagsAreExitCode2) {
  const std::string base = "--scene " + scene("empty") + " --stages full ";
  EXPECT_EQ(run(base + "--safety spheres"), 2);
  EXPECT_NE(file("stderr.txt").find("--safety: expected kc_svsdf or svsdf_per_link, got 'spheres'"), std::string::npos)
      << file("stderr.txt");
  EXPECT_EQ(run(base + "--collision octomap"), 2);
  EXPECT_NE(file("stderr.txt").find("--collision: expected kernels or spheres, got 'octomap'"), std::string::npos)
      << file("stderr.txt");
  EXPECT_EQ(run(base + "--safety"), 2);
  EXPECT_NE(file("stderr.txt").find("--safety needs a value"), std::string::npos);
  EXPECT_EQ(run(base + "--backend-budget-ms -1"), 2);
  EXPECT_NE(file("stderr.txt").find("--backend-budget-ms must be in (0, 3600000] ms"), std::string::npos);
  EXPECT_EQ(run(base + "--frontend-budget-ms 1e12"), 2);
  EXPECT_NE(file("stderr.txt").find("--frontend-budget-ms must be in (0, 3600000] ms"), std::string::npos);
  EXPECT_EQ(run(base + "--midend-budget-ms abc"), 2);
  EXPECT_EQ(run(base + "--backend-iterations 0"), 2);
  EXPECT_EQ(run(base + "--acceptance fcl"), 2);
  EXPECT_NE(file("stderr.txt").find("--acceptance: expected exact or kernels, got 'fcl'"), std::string::npos);
  EXPECT_EQ(run(base + "--clearance-margin-m -0.01"), 2);
  EXPECT_NE(file("stderr.txt").find("--clearance-margin-m must be >= 0"), std::string::npos);
  // The sphere baseline brings its own back-end term: an explicit --safety contradicts it.
  EXPECT_EQ(run(base + "--collision spheres --safety kc_svsdf"), 2);
  EXPECT_NE(file("stderr.txt").find("--safety does not apply with --collision spheres"), std::string::npos);
  // Valid values parse (nothing collides in the empty scene: no back-end, exit 0).
  EXPECT_EQ(run(base + "--safety svsdf_per_link --out " + (dir_ / "e.json").string()), 0) << file("stderr.txt");
  const auto doc = nlohmann::json::parse(file("e.json"));
  EXPECT_EQ(doc["format"], "porter-plan-result/4");
  EXPECT_EQ(doc["safety"], "svsdf_per_link");
  EXPECT_TRUE(doc["backend"].is_null());
  // The default acceptance is the kernel check (no margin stated); --acceptance exact with its
  // margin is recorded in the result and names the final check.
  EXPECT_EQ(doc["acceptance"], "kernels");
  EXPECT_TRUE(doc["clearance_margin_m"].is_null());
  EXPECT_EQ(run(base + "--acceptance exact --clearance-margin-m 0.03 --out " + (dir_ / "x.json").string()), 0)
      << file("stderr.txt");
  const auto exact = nlohmann::json::parse(file("x.json"));
  EXPECT_EQ(exact["acceptance"], "exact");
  EXPECT_DOUBLE_EQ(exact["clearance_margin_m"].get<double>(), 0.03);
  EXPECT_EQ(exact["final_check"]["checker"], "exact");
  EXPECT_TRUE(exact["final_check"]["collision_free"].get<bool>());
  EXPECT_EQ(doc["final_check"]["stage"], "midend");
  EXPECT_TRUE(doc["final_check"]["collision_free"].get<bool>());
}

TEST_F(PorterPlanFull, BridgeRunsTheBackendAndRecordsIt) {
  const int code = run(bridge_full("a.json"), "a");
  ASSERT_TRUE(code == 0 || code == 1) << code << file("stderra.txt");
  const auto doc = nlohmann::json::parse(file("a.json"));
  ASSERT_EQ(doc["frontend"]["status"], "success") << "the fixture needs a front-end path";
  ASSERT_EQ(doc["midend"]["direct_execution"], false) << "the fixture needs a mid-end trajectory in collision";
  const auto& be = doc["backend"];
  ASSERT_TRUE(be.is_object());
  EXPECT_EQ(be["safety_model"], "kc_svsdf");
  EXPECT_EQ(be["status"], "iteration_limit");
  EXPECT_EQ(be["iterations"], 3);
  EXPECT_GT(be["evaluations"].get<int>(), 3);
  EXPECT_GT(be["time_ms"].get<double>(), 0.0);
  EXPECT_EQ(be["budget_ms"], 120000.0);
  // The warm start collides: J_s > 0, and the optimizer lowered it.
  EXPECT_GT(be["initial_cost"]["safety"].get<double>(), 0.0);
  EXPECT_LT(be["final_cost"]["safety"].get<double>(), be["initial_cost"]["safety"].get<double>());
  // The answer is the back-end's, re-checked by the kernels; the exit code follows the re-check.
  ASSERT_TRUE(be["final_check"].is_object());
  EXPECT_EQ(be["final_check"]["checker"], "kernels");
  EXPECT_EQ(doc["final_check"]["stage"], "backend");
  const bool free = doc["final_check"]["collision_free"].get<bool>();
  EXPECT_EQ(be["final_check"]["collision_free"].get<bool>(), free);
  EXPECT_EQ(be["success"].get<bool>(), free);
  EXPECT_EQ(code, free ? 0 : 1);
  EXPECT_EQ(doc["exit_code"], code);
  ASSERT_TRUE(doc["trajectory"].is_object());
  EXPECT_EQ(doc["trajectory"]["pieces"].size(), be["num_pieces"].get<std::size_t>());
  // One summary line per stage.
  const std::string out = file("stdouta.txt");
  EXPECT_EQ(out.rfind("front-end: success", 0), 0u) << out;
  EXPECT_NE(out.find("\nmid-end: "), std::string::npos) << out;
  EXPECT_NE(out.find("\nback-end: iteration_limit"), std::string::npos) << out;
  EXPECT_NE(out.find("safety kc_svsdf"), std::string::npos) << out;

  // Same seed, same result (the back-end merges its threads' sums in a fixed order).
  ASSERT_EQ(run(bridge_full("b.json"), "b"), code);
  const auto again = nlohmann::json::parse(file("b.json"));
  EXPECT_EQ(again["path"], doc["path"]);
  EXPECT_EQ(again["trajectory"], doc["trajectory"]);
  EXPECT_EQ(again["backend"]["evaluations"], be["evaluations"]);
  EXPECT_EQ(again["backend"]["final_cost"], be["final_cost"]);
  EXPECT_EQ(again["final_check"]["collision_free"], doc["final_check"]["collision_free"]);

  // The ablation baseline on the same warm start: same flags, another term.
  const int per_link = run(bridge_full("c.json", "--safety svsdf_per_link"), "c");
  ASSERT_TRUE(per_link == 0 || per_link == 1) << file("stderrc.txt");
  const auto ablation = nlohmann::json::parse(file("c.json"));
  EXPECT_EQ(ablation["backend"]["safety_model"], "svsdf_per_link");
  EXPECT_EQ(ablation["midend"]["evaluations"], doc["midend"]["evaluations"]);
  EXPECT_EQ(ablation["backend"]["initial_cost"]["total"].is_number(), true);
}

TEST_F(PorterPlanFull, SelfCollisionTermFlag) {
  // Budgets large enough that only the iteration cap can stop a stage: the same result anywhere.
  // (Whether the term matters is tested on a frozen warm start: warm_start_gradient_test.cpp.)
  auto args = [&](const std::string& out, const std::string& term) {
    return "--scene " + scene("bridge") + " --set h_b=1.1 --seed 12 --stages full --frontend-budget-ms 20000" +
           " --midend-budget-ms 20000 --backend-budget-ms 120000 --backend-iterations 300 --self-collision-term " +
           term + " --out " + (dir_ / out).string();
  };
  EXPECT_EQ(run(args("bad.json", "maybe"), "x"), 2);
  EXPECT_NE(file("stderrx.txt").find("--self-collision-term: expected on or off"), std::string::npos);

  const int with = run(args("on.json", "on"), "on");
  const auto on = nlohmann::json::parse(file("on.json"));
  ASSERT_EQ(on["midend"]["direct_execution"], false) << "the fixture needs the back-end";
  EXPECT_EQ(on["backend"]["self_collision_term"], true);
  EXPECT_EQ(with, 0) << file("stdouton.txt");
  EXPECT_EQ(on["final_check"]["collision_free"], true);
  EXPECT_TRUE(on["backend"]["final_cost"]["self_collision"].is_number());
  EXPECT_GE(on["backend"]["self_collision_ms"].get<double>(), 0.0);

  const int without = run(args("off.json", "off"), "off");
  ASSERT_TRUE(without == 0 || without == 1) << file("stderroff.txt");
  const auto off = nlohmann::json::parse(file("off.json"));
  EXPECT_EQ(off["backend"]["self_collision_term"], false);
  EXPECT_EQ(off["backend"]["self_collision_ms"].get<double>(), 0.0);
}

TEST_F(PorterPlanFull, MidendInCollisionIsSolvedAgainAndTheBackendStartsFromTheShallowerOne) {
  // bridge h_b = 1.1 m seed 20: the first mid-end solve cuts through the deck; the retry with half
  // the arm residual bound stays closer to the front-end path but still collides, so both go to
  // the back-end, which (with --warm-start lowest-js) starts from the one with the lower J_s.
  const std::string args = "--scene " + scene("bridge") +
                           " --set h_b=1.1 --seed 20 --stages full --warm-start lowest-js"
                           " --frontend-budget-ms 20000 --midend-budget-ms 20000"
                           " --backend-budget-ms 120000 --backend-iterations 300 --out " + (dir_ / "r.json").string();
  const int code = run(args, "r");
  ASSERT_TRUE(code == 0 || code == 1) << file("stderrr.txt");
  const auto doc = nlohmann::json::parse(file("r.json"));
  ASSERT_TRUE(doc["midend"]["retry"].is_string());
  EXPECT_EQ(doc["midend"]["retry"].get<std::string>().rfind("in collision (link", 0), 0u) << doc["midend"]["retry"];
  EXPECT_EQ(doc["midend"]["residual_arm_bound_rad"], 0.175);
  const auto& be = doc["backend"];
  ASSERT_TRUE(be.is_object());
  const auto js = be["warm_start_safety"].get<std::vector<double>>();
  ASSERT_EQ(js.size(), 2u);
  const int chosen = be["warm_start"].get<int>();
  EXPECT_EQ(chosen, js[0] <= js[1] ? 0 : 1);
  const double chosen_js = js[static_cast<std::size_t>(chosen)];
  EXPECT_NEAR(be["initial_cost"]["safety"].get<double>(), chosen_js, 1e-9 * chosen_js);
  EXPECT_GE(be["selection_ms"].get<double>(), 0.0);
  EXPECT_EQ(code, 0) << file("stdoutr.txt");
  // With --stages mid the same collision is not retried (only a self-collision would be).
  const std::string mid = "--scene " + scene("bridge") + " --set h_b=1.1 --seed 20 --stages mid --frontend-budget-ms 20000"
                          " --midend-budget-ms 20000 --out " + (dir_ / "m.json").string();
  const int mid_code = run(mid, "m");
  ASSERT_TRUE(mid_code == 0 || mid_code == 1) << file("stderrm.txt");
  EXPECT_EQ(nlohmann::json::parse(file("m.json"))["midend"]["direct_execution"], false);
  EXPECT_TRUE(nlohmann::json::parse(file("m.json"))["midend"]["retry"].is_null());
}

}  // namespace
