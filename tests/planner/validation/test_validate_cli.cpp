// porter-validate as a process: exit codes, the summary line and the JSON report, on result
// files written here (hand-made trajectories in the shipped empty scene).
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "validation_fixture.hpp"

namespace porter::validation {
namespace {

namespace fs = std::filesystem;

class ValidateCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("porter_validate_cli_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  int run(const std::string& args) const {
    const std::string cmd = std::string(PORTER_VALIDATE_EXE) + " " + args + " > " + (dir_ / "out.txt").string() +
                            " 2> " + (dir_ / "err.txt").string();
    const int status = std::system(cmd.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  std::string read(const std::string& name) const {
    std::ifstream in(dir_ / name);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }
  // A result file with a straight drive from x0 to x1 (the empty scene's start is x = 0).
  std::string write_result(double x0, double x1, const std::string& name = "result.json") const {
    const PolyPiece p = test::ramp(test::flat(x0, 0, test::carry_arm()), test::flat(x1, 0, test::carry_arm()), 24.0);
    nlohmann::json coeffs = nlohmann::json::array();
    for (int k = 0; k < kPolyCoeffs; ++k) {
      nlohmann::json row = nlohmann::json::array();
      for (int d = 0; d < kFlatDim; ++d) row.push_back(p.coeffs(k, d));
      coeffs.push_back(row);
    }
    nlohmann::json doc = {{"format", "porter-plan-result/3"}, {"exit_code", 0}, {"status", "converged"},
                          {"final_check", {{"collision_free", true}, {"stage", "midend"}}},
                          {"trajectory", {{"dimension", 8}, {"degree", 5}, {"start_yaw_rad", 0.0},
                                          {"pieces", {{{"duration_s", 24.0}, {"eta", 1}, {"coeffs", coeffs}}}}}}};
    std::ofstream(dir_ / name) << doc.dump(2);
    return (dir_ / name).string();
  }
  std::string scene() const { return test::source_path("config/scenes/empty.yaml"); }

  fs::path dir_;
};

TEST_F(ValidateCli, AValidTrajectoryExitsZeroWithALineAndAJsonReport) {
  const std::string result = write_result(0, 8);
  const std::string json_path = (dir_ / "report.json").string();
  ASSERT_EQ(run("--scene " + scene() + " --seed 3 " + result + " --json " + json_path), 0) << read("err.txt");
  EXPECT_EQ(read("out.txt").rfind("valid |", 0), 0u) << read("out.txt");
  const auto report = nlohmann::json::parse(read("report.json"));
  EXPECT_EQ(report["format"], "porter-validate/1");
  EXPECT_TRUE(report["valid"].get<bool>());
  EXPECT_TRUE(report["plan"]["collision_free"].get<bool>());
  EXPECT_FALSE(report["collision"]["found"].get<bool>());
  EXPECT_EQ(report["clearance"].size(), 1u);  // the ground only
  EXPECT_EQ(report["limits"].size(), 5u);
  EXPECT_GT(report["samples"].get<int>(), 800);  // 8 m at <= 1 cm per sample
}

TEST_F(ValidateCli, AMissedGoalExitsOneAndSaysWhy) {
  const std::string result = write_result(0, 7.5);
  EXPECT_EQ(run("--scene " + scene() + " " + result + " --json -"), 1);
  const std::string out = read("out.txt");
  EXPECT_EQ(out.rfind("INVALID: goal missed: position 0.500 m", 0), 0u) << out;
  const auto report = nlohmann::json::parse(out.substr(out.find('\n') + 1));
  EXPECT_FALSE(report["valid"].get<bool>());
  EXPECT_NEAR(report["goal"]["position_error_m"].get<double>(), 0.5, 1e-12);
}

TEST_F(ValidateCli, ExitCodesForNoTrajectoryBadInputAndBadArguments) {
  std::ofstream(dir_ / "failed.json") << R"({"exit_code": 1, "status": "timeout", "trajectory": null})";
  EXPECT_EQ(run("--scene " + scene() + " " + (dir_ / "failed.json").string()), 4);
  EXPECT_NE(read("out.txt").find("no trajectory"), std::string::npos);
  std::ofstream(dir_ / "broken.json") << R"({"trajectory": {"dimension": 8}})";
  EXPECT_EQ(run("--scene " + scene() + " " + (dir_ / "broken.json").string()), 3);
  EXPECT_NE(read("err.txt").find("trajectory.degree"), std::string::npos);
  const std::string result = write_result(0, 8);
  EXPECT_EQ(run("--scene " + (dir_ / "missing.yaml").string() + " " + result), 3);
  EXPECT_EQ(run("--scene " + scene() + " --set h_b=0.9 " + result), 3);  // empty declares no h_b
  EXPECT_EQ(run(result), 2);
  EXPECT_EQ(run("--scene " + scene() + " --max-step-m 0 " + result), 2);
  EXPECT_EQ(run("--scene " + scene() + " --frobnicate 1 " + result), 2);
  EXPECT_NE(read("err.txt").find("usage:"), std::string::npos);
}

TEST_F(ValidateCli, TraceHoldsObstaclesBasePathAndPayloadTriangles) {
  const std::string result = write_result(0, 8);
  const std::string trace = (dir_ / "trace.json").string();
  ASSERT_EQ(run("--scene " + test::source_path("config/scenes/bridge.yaml") + " --no-ground --quiet " + result +
                " --trace " + trace),
            1);  // the bridge scene's start and goal are elsewhere, and the wall is in the way
  const auto t = nlohmann::json::parse(read("trace.json"));
  EXPECT_EQ(t["format"], "porter-validate-trace/1");
  EXPECT_EQ(t["obstacles"].size(), 3u);
  EXPECT_EQ(t["obstacles"][0]["kind"], "box");
  EXPECT_GT(t["base"].size(), 100u);
  EXPECT_GT(t["payload"].size(), 100u);  // a pose every 5 cm of payload motion over 8 m
  EXPECT_EQ(t["payload"][0]["triangles"][0].size(), 3u);
}

}  // namespace
}  // namespace porter::validation
