// Reading porter-plan result files: the fields used, errors naming the key, failed plans.
#include <gtest/gtest.h>

#include "porter/core/load_error.hpp"
#include "porter/validation/plan_file.hpp"

namespace porter::validation {
namespace {

const char* kPiece = R"({"duration_s": 1.5, "eta": -1, "coeffs": [[1,2,3,4,5,6,7,8],[0,0,0,0,0,0,0,0],
  [0,0,0,0,0,0,0,0],[0,0,0,0,0,0,0,0],[0,0,0,0,0,0,0,0],[0.5,0,0,0,0,0,0,9]]})";

std::string doc(const std::string& piece, const std::string& extra = "") {
  return std::string(R"({"exit_code": 1, "status": "time budget exceeded", "scene": {"name": "bridge", "seed": 4},)") +
         R"("final_check": {"collision_free": false, "stage": "backend"},)" + extra +
         R"("trajectory": {"dimension": 8, "degree": 5, "start_yaw_rad": 0.25, "pieces": [)" + piece + "]}}";
}

std::string error_of(const std::string& text) {
  try {
    parse_plan_file(text, "r.json");
  } catch (const LoadError& e) {
    return e.what();
  }
  return "";
}

TEST(PlanFile, ReadsTheTrajectoryAndThePlannersVerdict) {
  const PlanFile p = parse_plan_file(doc(kPiece), "r.json");
  ASSERT_TRUE(p.has_trajectory);
  ASSERT_EQ(p.pieces.size(), 1u);
  EXPECT_DOUBLE_EQ(p.pieces[0].duration_s, 1.5);
  EXPECT_EQ(p.pieces[0].eta, -1);
  EXPECT_DOUBLE_EQ(p.pieces[0].coeffs(0, 7), 8.0);
  EXPECT_DOUBLE_EQ(p.pieces[0].coeffs(5, 0), 0.5);
  EXPECT_DOUBLE_EQ(p.pieces[0].coeffs(5, 7), 9.0);
  EXPECT_DOUBLE_EQ(p.start_yaw_rad, 0.25);
  EXPECT_EQ(p.verdict.exit_code, 1);
  EXPECT_EQ(p.verdict.status, "time budget exceeded");
  ASSERT_TRUE(p.verdict.collision_free.has_value());
  EXPECT_FALSE(*p.verdict.collision_free);
  EXPECT_EQ(p.verdict.answer_stage, "backend");
  EXPECT_EQ(p.scene_name, "bridge");
  EXPECT_EQ(p.scene_seed.value_or(-1), 4);
}

TEST(PlanFile, AFailedPlanHasNoTrajectory) {
  const PlanFile p = parse_plan_file(R"({"exit_code": 1, "status": "timeout", "final_check": null, "trajectory": null})", "r.json");
  EXPECT_FALSE(p.has_trajectory);
  EXPECT_FALSE(p.verdict.collision_free.has_value());
  EXPECT_EQ(p.verdict.status, "timeout");
}

TEST(PlanFile, ErrorsNameTheFileAndTheKey) {
  EXPECT_EQ(error_of("{"), "r.json: not valid JSON");
  EXPECT_EQ(error_of("[]"), "r.json: expected a JSON object");
  std::string bad = kPiece;
  bad.replace(bad.find("-1"), 2, "2");
  EXPECT_EQ(error_of(doc(bad)), "r.json: key 'trajectory.pieces[0].eta': expected the integer 1 or -1");
  bad = kPiece;
  bad.replace(bad.find("1.5"), 3, "0");
  EXPECT_EQ(error_of(doc(bad)), "r.json: key 'trajectory.pieces[0].duration_s': expected a duration > 0");
  bad = kPiece;
  bad.replace(bad.find("[0.5,0,0,0,0,0,0,9]"), 19, "[0.5,0,0,0,0,0,0]");
  EXPECT_EQ(error_of(doc(bad)), "r.json: key 'trajectory.pieces[0].coeffs[5]': expected an array of 8 numbers");
  bad = kPiece;
  bad.replace(bad.find("[1,2,3"), 6, "[1,\"x\",3");
  EXPECT_EQ(error_of(doc(bad)), "r.json: key 'trajectory.pieces[0].coeffs[0]': expected a number");
  EXPECT_EQ(error_of(doc("")), "r.json: key 'trajectory.pieces': expected a non-empty array");
  EXPECT_EQ(error_of(R"({"trajectory": {"dimension": 7, "degree": 5, "start_yaw_rad": 0, "pieces": []}})"),
            "r.json: key 'trajectory.dimension': expected 8");
  EXPECT_EQ(error_of(R"({"exit_code": "0"})"), "r.json: key 'exit_code': expected an integer");
  EXPECT_EQ(error_of(R"({"final_check": {"collision_free": 1}})"),
            "r.json: key 'final_check.collision_free': expected a boolean");
  EXPECT_NE(error_of(R"({"trajectory": {"degree": 5}})").find("trajectory.dimension': missing"), std::string::npos);
}

TEST(PlanFile, AMissingFileIsALoadError) {
  EXPECT_THROW(load_plan_file("/nonexistent/porter/result.json"), LoadError);
}

}  // namespace
}  // namespace porter::validation
