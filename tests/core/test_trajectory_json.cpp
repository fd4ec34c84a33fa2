// JSON form of a Trajectory: documented layout, bit-exact round trip, and every rejection.

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "porter/core/trajectory_json.hpp"

namespace porter {
namespace {

Trajectory random_trajectory(unsigned seed, int n) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  std::vector<TrajectoryPiece> pieces(static_cast<size_t>(n));
  for (auto& p : pieces) {
    p.duration_s = 0.1 + std::abs(u(rng));
    p.eta = u(rng) > 0 ? 1 : -1;
    for (int k = 0; k < kTrajNumCoeffs; ++k)
      for (int d = 0; d < kTrajDim; ++d) p.coeffs(k, d) = u(rng) * std::pow(10.0, k - 3);
  }
  TrajectoryResult r = Trajectory::create(pieces, u(rng));
  EXPECT_TRUE(r.ok()) << r.error;
  return std::move(*r.trajectory);
}

void expect_identical(const Trajectory& a, const Trajectory& b) {
  ASSERT_EQ(a.num_pieces(), b.num_pieces());
  EXPECT_EQ(a.start_yaw_rad(), b.start_yaw_rad());
  for (int i = 0; i < a.num_pieces(); ++i) {
    EXPECT_EQ(a.piece(i).duration_s, b.piece(i).duration_s) << i;
    EXPECT_EQ(a.piece(i).eta, b.piece(i).eta) << i;
    EXPECT_EQ(a.piece(i).coeffs, b.piece(i).coeffs) << i;
  }
}

TEST(TrajectoryJson, RoundTripIsBitExact) {
  for (int indent : {-1, 2}) {
    const Trajectory traj = random_trajectory(42, 7);
    const std::string text = to_json(traj, indent);
    const TrajectoryResult back = trajectory_from_json(text);
    ASSERT_TRUE(back.ok()) << back.error;
    expect_identical(traj, *back.trajectory);
    EXPECT_EQ(to_json(*back.trajectory, indent), text);
  }
  EXPECT_EQ(to_json(random_trajectory(1, 1)).find('\n'), std::string::npos);
  EXPECT_NE(to_json(random_trajectory(1, 1), 2).find('\n'), std::string::npos);
}

// A hand-written document in the documented layout.
std::string documented(const std::string& eta = "-1", const std::string& extra = "") {
  return R"({"dimension": 8, "degree": 5, "start_yaw_rad": 0.5,)" + extra + R"(
    "pieces": [
      {"duration_s": 2.0, "eta": )" +
         eta + R"(, "coeffs": [
        [1, 2, 0, 0, 0, 0, 0, 0.25],
        [0, 3, 0, 0, 0, 0, 0, 0],
        [0, 0, 0, 0, 0, 0, 0, 0],
        [0, 0, 0, 0, 0, 0, 0, 0],
        [0, 0, 0, 0, 0, 0, 0, 0],
        [0, 0, 0, 0, 0, 0, 0, -1e-3]]}
    ]})";
}

TEST(TrajectoryJson, ReadsTheDocumentedLayout) {
  const TrajectoryResult r = trajectory_from_json(documented());
  ASSERT_TRUE(r.ok()) << r.error;
  const Trajectory& traj = *r.trajectory;
  EXPECT_EQ(traj.num_pieces(), 1);
  EXPECT_EQ(traj.total_duration_s(), 2.0);
  EXPECT_EQ(traj.piece(0).eta, -1);
  EXPECT_EQ(traj.start_yaw_rad(), 0.5);
  // Row k multiplies tau^k, column d is z_d.
  EXPECT_DOUBLE_EQ(traj.position(1.0)[0], 1.0);
  EXPECT_DOUBLE_EQ(traj.position(1.0)[1], 5.0);
  EXPECT_DOUBLE_EQ(traj.position(2.0)[7], 0.25 - 32e-3);
  EXPECT_DOUBLE_EQ(traj.base_motion(1.0).yaw_rad, -3.14159265358979323846 / 2);
}

void expect_rejected(const std::string& text, const std::string& fragment) {
  const TrajectoryResult r = trajectory_from_json(text);
  EXPECT_FALSE(r.ok()) << text;
  EXPECT_NE(r.error.find(fragment), std::string::npos) << "error: " << r.error;
}

TEST(TrajectoryJson, RejectsMalformedDocuments) {
  expect_rejected("{\"dimension\": 8,", "not valid JSON");
  expect_rejected("[1, 2]", "JSON object");
  expect_rejected(documented("1", R"( "colour": "red",)"), "colour: unknown key");
  expect_rejected(R"({"degree": 5, "start_yaw_rad": 0, "pieces": []})", "dimension: missing key");
  expect_rejected(R"({"dimension": 3, "degree": 5, "start_yaw_rad": 0, "pieces": []})",
                  "dimension: expected 8");
  expect_rejected(R"({"dimension": 8, "degree": 7, "start_yaw_rad": 0, "pieces": []})",
                  "degree: expected 5");
  expect_rejected(R"({"dimension": 8.5, "degree": 5, "start_yaw_rad": 0, "pieces": []})",
                  "dimension: expected an integer");
  expect_rejected(R"({"dimension": 8, "degree": 5, "start_yaw_rad": "x", "pieces": []})",
                  "start_yaw_rad: expected a number");
  expect_rejected(R"({"dimension": 8, "degree": 5, "start_yaw_rad": 0})", "pieces: missing key");
  expect_rejected(R"({"dimension": 8, "degree": 5, "start_yaw_rad": 0, "pieces": {}})",
                  "pieces: expected an array");
  expect_rejected(R"({"dimension": 8, "degree": 5, "start_yaw_rad": 0, "pieces": []})",
                  "at least one piece");
  expect_rejected(R"({"dimension": 8, "degree": 5, "start_yaw_rad": 0, "pieces": [3]})",
                  "pieces[0]: expected an object");
  expect_rejected(documented("0"), "pieces[0].eta: must be +1 or -1");
  // A number beyond double: nlohmann::json throws out_of_range, which used to escape.
  expect_rejected(R"({"dimension": 8, "degree": 5, "start_yaw_rad": 1e309, "pieces": []})",
                  "not valid JSON");
  expect_rejected(std::string(65 << 20, ' '), "exceeds the");
  expect_rejected(documented("1.0"), "pieces[0].eta: expected an integer");
}

TEST(TrajectoryJson, RejectsMalformedPieces) {
  std::vector<TrajectoryPiece> pieces = random_trajectory(3, 3).pieces();
  pieces[0].coeffs(0, 0) = 0.5;
  const std::string text = to_json(*Trajectory::create(pieces, 0.0).trajectory);
  auto replace = [](std::string s, const std::string& from, const std::string& to) {
    const size_t at = s.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return s.replace(at, from.size(), to);
  };
  // The writer's key order is alphabetical: coeffs, duration_s, eta.
  const size_t first_coeffs = text.find("\"coeffs\":[[");
  ASSERT_NE(first_coeffs, std::string::npos);
  expect_rejected(replace(text, "\"coeffs\":[[", "\"coeffs\":[[2.0,"),
                  "pieces[0].coeffs[0]: expected an array of 8 numbers");
  expect_rejected(replace(text, "\"coeffs\":[[", "\"coeffs\":[[1.0],["), "pieces[0].coeffs");
  expect_rejected(replace(text, "\"coeffs\":[[", "\"coeffs\":[[0,0,0,0,0,0,0,0],["),
                  "pieces[0].coeffs: expected an array of 6 rows");
  expect_rejected(replace(text, "\"coeffs\":[[0.5,", "\"coeffs\":[[true,"),
                  "pieces[0].coeffs[0][0]: expected a number");
  expect_rejected(replace(text, "\"duration_s\":", "\"duration_s\":-"),
                  "pieces[0].duration_s: must be finite and > 0");
  expect_rejected(replace(text, "\"duration_s\":", "\"durations\":"),
                  "pieces[0].durations: unknown key");
  expect_rejected(replace(text, "\"eta\":", "\"et\":"), "pieces[0].et: unknown key");
  const std::string no_eta = replace(text, ",\"eta\":1", "");
  if (no_eta != text) expect_rejected(no_eta, "eta: missing key");
}

}  // namespace
}  // namespace porter
