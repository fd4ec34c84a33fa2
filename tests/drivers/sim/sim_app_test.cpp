// porter-sim's pieces: the strict config (the shipped file, and errors naming the key), the
// SIM_COMMAND checks and the truth / LIO messages, and the process body built from a config
// (scene file, robot config, payload) and stepped directly.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <regex>
#include <string>

#include "porter/core/load_error.hpp"
#include "porter/scout_mini/protocol.hpp"
#include "sim_config.hpp"
#include "sim_messages.hpp"
#include "sim_process.hpp"
#include "hostile_config.hpp"

namespace porter::sim {
namespace {

const std::string kSource = PORTER_SOURCE_DIR;

std::string shipped_text() {
  std::ifstream in(kSource + "/config/drivers/porter_sim.yaml");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  // Relative paths of the shipped file, made absolute for a copy elsewhere.
  text = std::regex_replace(text, std::regex(R"(\.\./)"), kSource + "/config/");
  return text;
}

std::string write(const std::string& text, const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / "porter_sim_config_test";
  std::filesystem::create_directories(dir);
  const std::string path = (dir / name).string();
  std::ofstream(path) << text;
  return path;
}

std::string error_of(const std::string& text, const std::string& name) {
  const std::string path = write(text, name);
  try {
    load_sim_config(path);
  } catch (const LoadError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    return e.what();
  }
  return "";
}

std::string replaced(const std::string& text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  std::string out = text;
  if (at != std::string::npos) out.replace(at, from.size(), to);
  return out;
}

TEST(SimConfig, TheShippedFileLoads) {
  const SimConfig c = load_sim_config(kSource + "/config/drivers/porter_sim.yaml");
  EXPECT_NE(c.scene_path.find("scenes/bridge.yaml"), std::string::npos);
  EXPECT_EQ(c.payload_path, "scene");
  EXPECT_DOUBLE_EQ(c.step_s, 0.001);
  EXPECT_FALSE(c.arm_joints_rad.has_value());
  ASSERT_EQ(c.buses.size(), 2u);
  EXPECT_EQ(c.buses[0].name, "base");
  EXPECT_EQ(c.buses[0].can, "lcm:CAN_BASE");
  EXPECT_EQ(c.buses[0].devices, std::vector<std::string>{"scout_mini"});
  EXPECT_EQ(c.buses[1].devices, std::vector<std::string>{"piper"});
  EXPECT_DOUBLE_EQ(c.piper.max_speed_radps, 3.0);
  EXPECT_TRUE(c.lidar.enabled);
  EXPECT_EQ(c.lidar.network.point_port, 56301);
  EXPECT_DOUBLE_EQ(c.lidar.sensor.pattern.point_rate_hz, 200000.0);
  // The mount resolves the URDF's lidar_mast link: 0.2875 m above it.
  EXPECT_NEAR(c.lidar.sensor.T_B_S.translation().z(), 0.245 + 0.2875, 1e-9);
  EXPECT_DOUBLE_EQ(c.scout_mini.command_timeout_s, 0.5);
  EXPECT_EQ(error_of(shipped_text(), "ok.yaml"), "");
}

TEST(SimConfig, BadKeysAreErrorsNamingTheKey) {
  const std::string ok = shipped_text();
  EXPECT_NE(error_of(replaced(ok, "step_s: 0.001", "step_s: 0.5"), "step.yaml").find("'step_s'"),
            std::string::npos);
  EXPECT_NE(error_of(replaced(ok, "status_period_s", "status_periods"), "unknown.yaml")
                .find("status_periods"),
            std::string::npos);
  EXPECT_NE(error_of(replaced(ok, "  seed: 1\n", ""), "missing.yaml").find("'lio.seed'"),
            std::string::npos);
  EXPECT_NE(error_of(replaced(ok, "devices: [scout_mini]", "devices: [scout_maxi]"), "dev.yaml")
                .find("unknown device 'scout_maxi'"),
            std::string::npos);
  EXPECT_NE(error_of(replaced(ok, "name: arm", "name: base"), "dup.yaml").find("buses[1].name"),
            std::string::npos);
  EXPECT_NE(error_of(replaced(ok, "arm_joints_rad: scene", "arm_joints_rad: [0, 1]"), "arm.yaml")
                .find("'arm_joints_rad'"),
            std::string::npos);
  EXPECT_NE(error_of(replaced(ok, "time_constant_s: 0.05", "time_constant_s: -1"), "tau.yaml")
                .find("'scout_mini.time_constant_s'"),
            std::string::npos);
  EXPECT_NE(error_of(replaced(ok, "devices: [piper]", "devices: [piper, scout_mini]"), "twice.yaml")
                .find("hosted twice"),
            std::string::npos);
  EXPECT_NE(error_of(replaced(ok, "max_speed_radps: 3.0", "max_speed_radps: 4.0"), "speed.yaml")
                .find("'piper.max_speed_radps'"),
            std::string::npos);
  EXPECT_NE(error_of(replaced(ok, "point_port: 56301", "point_port: 70000"), "port.yaml")
                .find("'lidar.point_port'"),
            std::string::npos);
  EXPECT_NE(error_of(replaced(ok, "dropout_probability: 0.0", "dropout_probability: 1.5"), "drop.yaml")
                .find("'lidar.sensor.dropout_probability'"),
            std::string::npos);
  EXPECT_NE(error_of(replaced(ok, "link: lidar_mast", "link: no_such_link"), "mount.yaml")
                .find("no_such_link"),
            std::string::npos);
  EXPECT_NE(error_of(replaced(ok, "  imu_source_port: 56400\n", ""), "nokey.yaml")
                .find("'lidar.imu_source_port'"),
            std::string::npos);
  const SimConfig fixed = load_sim_config(write(
      replaced(ok, "arm_joints_rad: scene", "arm_joints_rad: [0, 1.5, -1, 0, 0.5, 0]"), "q.yaml"));
  ASSERT_TRUE(fixed.arm_joints_rad.has_value());
  EXPECT_DOUBLE_EQ((*fixed.arm_joints_rad)[1], 1.5);
}

TEST(SimMessages, SimCommandsAreCheckedBeforeTheyReachTheSimulator) {
  porter::sim_command_t m;
  m.command = porter::sim_command_t::POWER_CYCLE;
  m.target = "scout_mini";
  m.duration_s = 0.5;
  SimCommand c;
  EXPECT_TRUE(to_sim_command(m, c).ok);
  EXPECT_EQ(c.kind, SimCommand::Kind::power_cycle);
  EXPECT_DOUBLE_EQ(c.duration_s, 0.5);
  m.duration_s = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(to_sim_command(m, c).ok);
  m.command = 42;
  EXPECT_NE(to_sim_command(m, c).message.find("unknown command 42"), std::string::npos);
  m.command = porter::sim_command_t::STOP_STREAM;
  m.can_id = -1;
  EXPECT_FALSE(to_sim_command(m, c).ok);
  m.can_id = 0x221;
  EXPECT_TRUE(to_sim_command(m, c).ok);
  EXPECT_EQ(c.can_id, 0x221u);
  m.command = porter::sim_command_t::RAISE_ERROR;
  m.error_code = 0;
  EXPECT_FALSE(to_sim_command(m, c).ok);
  m.command = porter::sim_command_t::ADD_BOX;
  m.target = "";
  EXPECT_NE(to_sim_command(m, c).message.find("empty target"), std::string::npos);
  m.target = "crate";
  m.center_x_m = 1;
  m.size_x_m = m.size_y_m = m.size_z_m = 0.5;
  m.yaw_rad = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(to_sim_command(m, c).ok);
  m.yaw_rad = 0.3;
  ASSERT_TRUE(to_sim_command(m, c).ok);
  EXPECT_DOUBLE_EQ(c.center_W.x(), 1.0);
  EXPECT_DOUBLE_EQ(c.yaw_rad, 0.3);
}

TEST(SimMessages, TruthAndLioMessages) {
  RobotSample s;
  s.config.base = {1.0, 2.0, M_PI / 2};
  s.config.q_rad << 1, 2, 3, 4, 5, 6;
  s.v_mps = 0.4;
  const porter::robot_state_t truth = to_truth_message(s, 77);
  EXPECT_EQ(truth.pose_source, porter::robot_state_t::POSE_SIM_TRUTH);
  EXPECT_EQ(truth.num_joints, 6);
  EXPECT_EQ(truth.q_rad.size(), 6u);
  EXPECT_EQ(truth.q_rad[5], 6);
  EXPECT_TRUE(truth.pose_valid && truth.base_valid && truth.arm_valid);
  PoseSample p;
  p.pose_W = s.config.base;
  const porter::pose_t lio = to_lio_message(p, 78);
  EXPECT_NEAR(lio.qw, std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(lio.qz, std::sqrt(0.5), 1e-12);
  EXPECT_EQ(lio.num_covariance, 0);
  EXPECT_EQ(lio.child_frame_id, "base");
}

TEST(SimProcessTest, BuildsTheWorldFromTheSceneRobotAndPayloadFiles) {
  std::string text = shipped_text();
  text = replaced(text, "can: lcm:CAN_BASE", "can: memory:sim_process_base");
  text = replaced(text, "can: lcm:CAN_ARM", "can: memory:sim_process_arm");
  text = replaced(text, "  enabled: true", "  enabled: false");  // no UDP from a unit test
  text = replaced(text, "devices: [piper]", "devices: []");
  const SimConfig config = load_sim_config(write(text, "memory.yaml"));
  LcmBus lcm("memq://");
  SimProcess process(config, lcm);
  ASSERT_TRUE(process.ok()) << process.error();
  Simulator& sim = process.simulator();
  const World& world = sim.world();
  EXPECT_EQ(world.scene().name, "bridge");
  EXPECT_EQ(world.robot().payload_name, "t_bar");
  EXPECT_EQ(world.obstacles().size(), world.scene().obstacles.size());
  ASSERT_NE(sim.node("scout_mini"), nullptr);
  // The firmware moves the world's base from the scene's start.
  sim.inject("base", scout_mini::encode_control_mode(scout_mini::ControlMode::can));
  scout_mini::MotionCommand forward;
  forward.v_mps = 0.5;
  for (int k = 1; k <= 1500; ++k) {
    if (k % 20 == 0) sim.inject("base", scout_mini::encode_motion_command(forward));
    sim.step_to(k * 1e-3);
  }
  const BasePose start = world.scene().start.base;
  const BasePose now = world.latest().config.base;
  EXPECT_GT(std::hypot(now.x_m - start.x_m, now.y_m - start.y_m), 0.4);
  EXPECT_NEAR(now.yaw_rad, start.yaw_rad, 1e-9);
  EXPECT_EQ(world.latest().config.q_rad, world.scene().start.q_rad) << "fixed arm";
  EXPECT_EQ(process.lidar(), nullptr);
}

}  // namespace
}  // namespace porter::sim

// Every number of the shipped file replaced by hostile values: NaN, infinities and 1e300 are
// refused naming the file; 0, -1, 1e-300, 1e9 load or are refused, never crash
// (tests/support/hostile_config.hpp).
TEST(SimConfigHostile, EveryNumberIsRangeChecked) {
  const int replaced = porter::test::check_hostile_numbers("drivers/porter_sim.yaml", [](const std::string& f) { porter::sim::load_sim_config(f); });
  EXPECT_GE(replaced, 11 * 49);
}
