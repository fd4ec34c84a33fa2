// porter-plan end to end: exit codes for bad arguments, unreadable files and invalid starts, the
// JSON result of a successful plan, the planner settings files and the flags that override them,
// and how it finds its config without a build-machine path in the binary. (--stages full with a
// back-end: porter_plan_full_test.cpp.)

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "frontend_test_utils.hpp"
#include "plan_cli_test.hpp"

namespace {

namespace fs = std::filesystem;

class PorterPlan : public porter::test::PlanCliTest {
 protected:
  void SetUp() override {
    PlanCliTest::SetUp();
    // A copy of the shipped robot config (URDF path made absolute), for --robot.
    std::ifstream in(porter::test::robot_yaml());
    std::stringstream text;
    text << in.rdbuf();
    std::string robot = text.str();
    const std::string key = "urdf: scout_mini_piper.urdf";
    robot.replace(robot.find(key), key.size(),
                  "urdf: " + porter::test::source_dir() + "/config/robots/scout_mini_piper/scout_mini_piper.urdf");
    std::ofstream(dir_ / "robot.yaml") << robot;
  }
  std::string robot() const { return (dir_ / "robot.yaml").string(); }
  std::string scene(const std::string& name) const { return porter::test::scene_yaml(name); }
};

TEST_F(PorterPlan, BadArgumentsAreExitCode2) {
  EXPECT_EQ(run(""), 2);
  EXPECT_NE(file("stderr.txt").find("--scene is required"), std::string::npos);
  EXPECT_EQ(run("--scene " + scene("empty") + " --seed -3"), 2);
  EXPECT_EQ(run("--scene " + scene("empty") + " --frontend-budget-ms 0"), 2);
  EXPECT_EQ(run("--scene " + scene("empty") + " --set h_b"), 2);
  EXPECT_EQ(run("--scene " + scene("empty") + " --stages back"), 2);
  EXPECT_EQ(run("--help"), 0);
}

TEST_F(PorterPlan, UnreadableFilesAreExitCode3) {
  EXPECT_EQ(run("--scene " + (dir_ / "missing.yaml").string()), 3);
  EXPECT_NE(file("stderr.txt").find("missing.yaml"), std::string::npos);
  EXPECT_EQ(run("--scene " + scene("bridge") + " --set no_such_parameter=1"), 3);
  EXPECT_EQ(run("--scene " + scene("empty") + " --robot " + (dir_ / "nope.yaml").string()), 3);
}

TEST_F(PorterPlan, MidStageWritesTheTrajectoryAndTheDirectExecutionDecision) {
  EXPECT_EQ(run("--scene " + scene("empty") + " --stages mid --out " + (dir_ / "r.json").string()), 0);
  const auto doc = nlohmann::json::parse(file("r.json"));
  EXPECT_EQ(doc["exit_code"], 0);
  ASSERT_TRUE(doc["midend"].is_object());
  EXPECT_GT(doc["midend"]["iterations"].get<int>(), 0);
  ASSERT_TRUE(doc["trajectory"].is_object());
  EXPECT_EQ(doc["trajectory"]["pieces"].size(), doc["midend"]["num_pieces"].get<std::size_t>());
  // In the empty scene nothing can collide: the kernel check accepts it for direct execution.
  EXPECT_TRUE(doc["midend"]["direct_execution"].get<bool>());
  // With nothing in collision, the full pipeline needs no back-end either.
  EXPECT_EQ(run("--scene " + scene("empty") + " --stages full"), 0);
}

TEST_F(PorterPlan, SelfCollidingMidendTrajectoryIsSolvedAgainCloserToThePath) {
  // Bridge h_b = 1.1, seed 17: the first mid-end trajectory folds link 4 into link 1 (the arm
  // leaves the front-end's arm path by up to rho_m); the retry with half the arm residual bound
  // is collision-free and executed directly. Budgets large enough that no stage stops on time.
  EXPECT_EQ(run("--scene " + scene("bridge") + " --set h_b=1.1 --seed 17 --stages mid --frontend-budget-ms 20000" +
                " --midend-budget-ms 20000 --out " + (dir_ / "s.json").string()),
            0)
      << file("stderr.txt");
  const auto doc = nlohmann::json::parse(file("s.json"));
  ASSERT_TRUE(doc["midend"]["retry"].is_string()) << "the fixture needs a self-colliding first solve";
  EXPECT_NE(doc["midend"]["retry"].get<std::string>().find("0.35 -> 0.175 rad"), std::string::npos);
  EXPECT_TRUE(doc["midend"]["direct_execution"].get<bool>());
  EXPECT_TRUE(doc["final_check"]["collision_free"].get<bool>());
  // Without a self-collision there is no retry.
  EXPECT_EQ(run("--scene " + scene("empty") + " --stages mid --out " + (dir_ / "e.json").string()), 0);
  EXPECT_TRUE(nlohmann::json::parse(file("e.json"))["midend"]["retry"].is_null());
}

TEST_F(PorterPlan, InvalidStartIsExitCode4) {
  std::ifstream in(scene("empty"));
  std::stringstream text;
  text << in.rdbuf();
  std::string yaml = text.str();
  const std::string arm = "start: {base: [0.0, 0.0, 0.0], arm: [0.0, 0.6, -0.9, 0.0, 0.5, 0.0]}";
  ASSERT_NE(yaml.find(arm), std::string::npos);
  yaml.replace(yaml.find(arm), arm.size(), "start: {base: [0.0, 0.0, 0.0], arm: [0.0, 3.5, -0.9, 0.0, 0.5, 0.0]}");
  const std::string payload = "payload: ../payloads/t_bar.yaml";
  yaml.replace(yaml.find(payload), payload.size(), "payload: " + porter::test::source_dir() + "/config/payloads/t_bar.yaml");
  std::ofstream(dir_ / "bad_start.yaml") << yaml;
  EXPECT_EQ(run("--scene " + (dir_ / "bad_start.yaml").string() + " --robot " + robot()), 4);
  EXPECT_NE(file("stderr.txt").find("joint 2"), std::string::npos) << file("stderr.txt");
}

TEST_F(PorterPlan, PlansAtTheScenesResolution) {
  // The kernels follow the scene's voxel size; a size they cannot use is a bad scene file.
  std::ifstream in(scene("empty"));
  std::stringstream text;
  text << in.rdbuf();
  const std::string original = text.str();
  auto with = [&](const std::string& resolution) {
    std::string yaml = original;
    const std::string key = "resolution: 0.05";
    yaml.replace(yaml.find(key), key.size(), "resolution: " + resolution);
    const std::string payload = "payload: ../payloads/t_bar.yaml";
    yaml.replace(yaml.find(payload), payload.size(), "payload: " + porter::test::source_dir() + "/config/payloads/t_bar.yaml");
    const fs::path path = dir_ / ("empty_" + resolution + ".yaml");
    std::ofstream(path) << yaml;
    return path.string();
  };
  ASSERT_NE(original.find("resolution: 0.05"), std::string::npos);
  EXPECT_EQ(run("--scene " + with("0.1") + " --robot " + robot() + " --stages front --frontend-budget-ms 20000"), 0)
      << file("stdout.txt") << file("stderr.txt");
  EXPECT_EQ(run("--scene " + with("0.025") + " --robot " + robot() + " --stages front --frontend-budget-ms 20000"), 0)
      << file("stdout.txt") << file("stderr.txt");
}

TEST_F(PorterPlan, SuccessWritesTheDocumentedJson) {
  const std::string out = (dir_ / "r.json").string();
  ASSERT_EQ(run("--scene " + scene("empty") + " --seed 7 --robot " + robot() + " --frontend-budget-ms 20000 --out " + out), 0)
      << file("stdout.txt") << file("stderr.txt");
  EXPECT_EQ(file("stdout.txt").rfind("front-end: success", 0), 0u) << file("stdout.txt");
  const auto doc = nlohmann::json::parse(file("r.json"));
  EXPECT_EQ(doc["format"], "porter-plan-result/4");
  EXPECT_EQ(doc["status"], "success");
  EXPECT_EQ(doc["scene"]["seed"], 7);
  EXPECT_EQ(doc["checker"], "kernels");
  EXPECT_EQ(doc["frontend"]["stages"]["hybrid_astar"]["status"], "success");
  const auto& path = doc["path"];
  ASSERT_GE(path["segments"].size(), 1u);
  const auto& first = path["segments"][0]["nodes"][0];
  EXPECT_EQ(first["t_s"], 0.0);
  EXPECT_EQ(first["base"][0], 0.0);
  EXPECT_EQ(first["q_rad"].size(), 6u);
  const auto& last_seg = path["segments"][path["segments"].size() - 1];
  const auto& last = last_seg["nodes"][last_seg["nodes"].size() - 1];
  EXPECT_NEAR(last["base"][0].get<double>(), 8.0, 1e-9);
  EXPECT_NEAR(path["duration_s"].get<double>(), last["t_s"].get<double>(), 1e-12);
  EXPECT_TRUE(doc["trajectory"].is_null());
  EXPECT_TRUE(doc["backend"].is_null());
  EXPECT_TRUE(doc["final_check"].is_null());
}

TEST_F(PorterPlan, FindsItsConfigFromAnyWorkingDirectory) {
  // No --robot, no --planner-config, run from a scratch directory: the config directory above
  // the executable (the source tree's) is used.
  const std::string out = (dir_ / "r.json").string();
  ASSERT_EQ(run_in(dir_.string(), "--scene " + scene("empty") + " --stages front --frontend-budget-ms 20000 --out " + out), 0)
      << file("stderr.txt");
  const auto doc = nlohmann::json::parse(file("r.json"));
  const fs::path robot = doc["robot_file"].get<std::string>();
  const fs::path planner = doc["planner_config"].get<std::string>();
  EXPECT_TRUE(fs::equivalent(robot, porter::test::robot_yaml())) << robot;
  EXPECT_TRUE(fs::equivalent(planner, porter::test::source_dir() + "/config/planner")) << planner;
}

TEST_F(PorterPlan, NoPathOfTheBuildMachineIsInTheBinary) {
  // What the program itself holds, without the debug sections a RelWithDebInfo build (the
  // sanitizer build) adds: those name every source file, and a shipped binary can drop them.
  const std::string stripped = (dir_ / "porter-plan.stripped").string();
  ASSERT_EQ(std::system(("objcopy --strip-debug '" + std::string(PORTER_PLAN_EXE) + "' '" + stripped + "'").c_str()), 0);
  std::ifstream in(stripped, std::ios::binary);
  std::stringstream bytes;
  bytes << in.rdbuf();
  ASSERT_GT(bytes.str().size(), 100000u);
  EXPECT_EQ(bytes.str().find(porter::test::source_dir()), std::string::npos);
}

TEST_F(PorterPlan, SettingsFilesAreReadStrictlyAndFlagsOverrideThem) {
  const fs::path settings = dir_ / "planner";
  fs::create_directories(settings);
  for (const char* f : {"pipeline.yaml", "frontend.yaml", "midend.yaml", "backend.yaml"})
    fs::copy_file(porter::test::source_dir() + "/config/planner/" + f, settings / f);
  auto edit = [&](const std::string& file, const std::string& from, const std::string& to) {
    std::ifstream in(settings / file);
    std::stringstream text;
    text << in.rdbuf();
    std::string s = text.str();
    ASSERT_NE(s.find(from), std::string::npos) << from;
    s.replace(s.find(from), from.size(), to);
    std::ofstream(settings / file) << s;
  };
  const std::string base = "--scene " + scene("empty") + " --planner-config " + settings.string() + " --out ";
  edit("pipeline.yaml", "  midend_s: 0.1 ", "  midend_s: 0.25 ");
  ASSERT_EQ(run(base + (dir_ / "a.json").string()), 0) << file("stderr.txt");
  EXPECT_EQ(nlohmann::json::parse(file("a.json"))["budgets_ms"]["midend"], 250.0);
  ASSERT_EQ(run(base + (dir_ / "b.json").string() + " --midend-budget-ms 50"), 0) << file("stderr.txt");
  EXPECT_EQ(nlohmann::json::parse(file("b.json"))["budgets_ms"]["midend"], 50.0);
  EXPECT_EQ(nlohmann::json::parse(file("b.json"))["budgets_ms"]["frontend"], 1000.0);  // the file's

  edit("midend.yaml", "  memory_size: 32", "  memory_size: 100");
  EXPECT_EQ(run(base + (dir_ / "c.json").string()), 3);
  EXPECT_NE(file("stderr.txt").find("midend.yaml"), std::string::npos) << file("stderr.txt");
  EXPECT_NE(file("stderr.txt").find("solver.memory_size"), std::string::npos) << file("stderr.txt");
  const auto doc = nlohmann::json::parse(file("c.json"));
  EXPECT_EQ(doc["status"], "bad_input");
  EXPECT_EQ(doc["exit_code"], 3);
}

}  // namespace
