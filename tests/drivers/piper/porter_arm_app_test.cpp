// porter-arm's config loader (strict: file and key in every error; joint limits from the robot
// model) and its ARM_CMD / ARM_STATE conversions.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>

#include "arm_messages.hpp"
#include "porter/piper/arm_driver.hpp"
#include "porter/piper/feedback.hpp"
#include "porter/core/load_error.hpp"
#include "porter_arm_params.hpp"
#include "hostile_config.hpp"

namespace porter::piper {
namespace {

namespace fs = std::filesystem;

const fs::path kSource = PORTER_SOURCE_DIR;
const fs::path kShipped = kSource / "config/drivers/porter_arm.yaml";

class PorterArmConfig : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("porter_arm_config_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    std::ifstream in(kShipped);
    shipped_.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    shipped_ = std::regex_replace(shipped_, std::regex("\\.\\./robots/"), (kSource / "config/robots/").string());
  }
  void TearDown() override { fs::remove_all(dir_); }

  /// The shipped config with `from` replaced by `to`, written to a scratch file.
  std::string variant(const std::string& from, const std::string& to) {
    std::string text = shipped_;
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
    const fs::path path = dir_ / "porter_arm.yaml";
    std::ofstream(path) << text;
    return path.string();
  }
  /// The LoadError message for `path` ("" when it loads).
  static std::string error_of(const std::string& path) {
    try {
      load_porter_arm_params(path);
    } catch (const LoadError& e) {
      return e.what();
    }
    return "";
  }

  fs::path dir_;
  std::string shipped_;
};

TEST_F(PorterArmConfig, ShippedConfigLoadsWithTheRobotModelsLimits) {
  const PorterArmParams p = load_porter_arm_params(kShipped.string());
  EXPECT_EQ(p.can_bus, "lcm:CAN_ARM");
  EXPECT_EQ(p.lcm_url, "");
  EXPECT_EQ(p.loop_rate_hz, 200.0);
  EXPECT_EQ(p.driver.cmd_timeout_s, 0.2);
  EXPECT_EQ(p.driver.default_speed_pct, 50);
  EXPECT_EQ(p.driver.gripper_max_m, 0.07);
  // config/robots/scout_mini_piper's URDF: the SDK's table (J4 +-1.745, J6 +-2.09439).
  EXPECT_DOUBLE_EQ(p.driver.lower_rad[0], -2.6179);
  EXPECT_DOUBLE_EQ(p.driver.upper_rad[1], 3.14);
  EXPECT_DOUBLE_EQ(p.driver.lower_rad[2], -2.967);
  EXPECT_DOUBLE_EQ(p.driver.upper_rad[3], 1.745);
  EXPECT_DOUBLE_EQ(p.driver.upper_rad[4], 1.22);
  EXPECT_DOUBLE_EQ(p.driver.lower_rad[5], -2.09439);
}

TEST_F(PorterArmConfig, EveryErrorNamesTheFileAndTheKey) {
  struct Case {
    std::string from, to, key;
  };
  const std::vector<Case> cases = {
      {"loop_rate_hz: 200", "loop_rate_hz: 200\nloop_rate: 100", "loop_rate"},        // unknown key
      {"cmd_timeout_s: 0.2\n", "", "cmd_timeout_s"},                                   // missing key
      {"cmd_timeout_s: 0.2", "cmd_timeout_s: -0.1", "cmd_timeout_s"},                 // out of range
      {"loop_rate_hz: 200", "loop_rate_hz: 5000", "loop_rate_hz"},
      {"default_speed_pct: 50", "default_speed_pct: 0", "default_speed_pct"},
      {"default_speed_pct: 50", "default_speed_pct: fast", "default_speed_pct"},      // wrong type
      {"  max_m: 0.07", "  max_m: 0.2", "gripper.max_m"},
      {"  effort_max_nm: 5.0", "  effort_max_nm: 5.0\n  speed: 1", "speed"},
      {"can_bus: lcm:CAN_ARM", "can_bus: can0", "can_bus"},
      {"retry_period_s: 0.1", "retry_period_s: 0", "retry_period_s"},
  };
  for (const Case& c : cases) {
    const std::string path = variant(c.from, c.to);
    const std::string error = error_of(path);
    EXPECT_NE(error.find(path), std::string::npos) << c.to << " -> " << error;
    EXPECT_NE(error.find(c.key), std::string::npos) << c.to << " -> " << error;
  }
  // A robot config that does not exist fails with its path.
  const std::string error = error_of(variant("scout_mini_piper/robot.yaml", "nowhere/robot.yaml"));
  EXPECT_NE(error.find("nowhere/robot.yaml"), std::string::npos) << error;
}

porter::arm_cmd_t valid_cmd() {
  porter::arm_cmd_t m;
  m.enabled = true;
  m.num_joints = 6;
  m.q_rad = {0.1, 0.2, -0.3, 0.4, -0.5, 0.6};
  m.qd_radps.assign(6, 0.0);
  m.speed_pct = 70;
  m.has_gripper = true;
  m.gripper_m = 0.03;
  m.gripper_effort_nm = 1.5;
  m.source = "test";
  return m;
}

TEST(PorterArmMessages, CommandsConvertOrSayWhyNot) {
  std::string why;
  auto cmd = to_command(valid_cmd(), why);
  ASSERT_TRUE(cmd.has_value()) << why;
  EXPECT_EQ(cmd->q_rad[2], -0.3);
  EXPECT_EQ(cmd->speed_pct, 70);
  EXPECT_TRUE(cmd->has_gripper);
  EXPECT_EQ(cmd->gripper_m, 0.03);
  porter::arm_cmd_t m = valid_cmd();
  m.num_joints = 7;
  m.q_rad.push_back(0);
  EXPECT_FALSE(to_command(m, why));
  EXPECT_NE(why.find("num_joints"), std::string::npos);
  m = valid_cmd();
  m.q_rad.pop_back();
  EXPECT_FALSE(to_command(m, why));
  EXPECT_NE(why.find("q_rad"), std::string::npos);
  m = valid_cmd();
  m.q_rad[4] = std::nan("");
  EXPECT_FALSE(to_command(m, why));
  EXPECT_NE(why.find("q_rad[4]"), std::string::npos);
  m = valid_cmd();
  m.gripper_m = INFINITY;
  EXPECT_FALSE(to_command(m, why));
  m.has_gripper = false;  // ignored when there is no gripper command
  EXPECT_TRUE(to_command(m, why));
  m.speed_pct = std::nan("");
  ASSERT_TRUE(to_command(m, why));
  EXPECT_EQ(to_command(m, why)->speed_pct, 0.0);  // = the driver's default speed
}

TEST(PorterArmMessages, StateCarriesFeedbackFlagsAndFaultNames) {
  ArmFeedback fb;
  fb.q_rad = {0.1, 0.2, 0.3, 0.4, 0.5, 0.6};
  fb.qd_radps[1] = -0.5;
  fb.effort_nm[2] = 1.25;
  fb.motor_temperature_c[3] = 41;
  fb.driver_status = {0x40, 0x40, 0x44, 0x40, 0x40, 0x40};
  fb.joint_enabled = {true, true, true, true, true, false};
  fb.gripper_m = 0.02;
  fb.have_status = true;
  fb.ctrl_mode = 1;
  fb.arm_status = 7;
  fb.err_code = 0x0402;
  ArmDriverStatus st;
  st.link_ok = true;
  st.cmd_stale = true;
  st.estop_active = false;
  st.fault = true;
  st.faults = {"collision", "joint3_over_current"};
  const porter::arm_state_t m = to_arm_state(fb, st, 123456);
  EXPECT_EQ(m.utime, 123456);
  EXPECT_EQ(m.num_joints, 6);
  ASSERT_EQ(m.q_rad.size(), 6u);
  ASSERT_EQ(m.joint_status_bits.size(), 6u);
  ASSERT_EQ(m.joint_enabled.size(), 6u);
  EXPECT_EQ(m.q_rad[5], 0.6);
  EXPECT_EQ(m.qd_radps[1], -0.5);
  EXPECT_EQ(m.effort_nm[2], 1.25);
  EXPECT_EQ(m.motor_temperature_c[3], 41);
  EXPECT_EQ(m.joint_status_bits[2], 0x44);
  EXPECT_FALSE(m.joint_enabled[5]);
  EXPECT_EQ(m.ctrl_mode, porter::arm_state_t::CTRL_CAN);
  EXPECT_EQ(m.arm_status, 7);
  EXPECT_EQ(m.err_code, 0x0402);
  EXPECT_TRUE(m.fault);
  EXPECT_EQ(m.faults, "collision, joint3_over_current");
  EXPECT_TRUE(m.cmd_stale);
  EXPECT_TRUE(m.link_ok);
  fb.have_status = false;
  EXPECT_EQ(to_arm_state(fb, st, 0).ctrl_mode, porter::arm_state_t::CTRL_UNKNOWN);
}

TEST(PorterArmMessages, StateIsStampedWithTheJointFramesOwnTime) {
  ArmFeedback fb;
  EXPECT_EQ(arm_state_utime(fb, 5'000'000, 10.0), 0);  // no joint-angle frame yet
  // A joint-angle frame through the driver: its CanFrame::utime (porter-sim's clock here, 2 s
  // behind the wall clock) is the stamp, not the time the driver handled it.
  ArmDriver driver(ArmDriverParams{});
  can::CanFrame f = encode_joint_angle_pair({0, {1000, 2000}});
  f.utime = 3'000'000;
  driver.on_frame(f, 9.99);
  EXPECT_EQ(driver.feedback().joints_frame_utime, 3'000'000);
  EXPECT_EQ(arm_state_utime(driver.feedback(), 5'000'000, 10.0), 3'000'000);
  // A bus without stamps: the wall-clock time of the receipt.
  fb.joints_t_s = 9.5;
  EXPECT_EQ(arm_state_utime(fb, 5'000'000, 10.0), 4'500'000);
}

}  // namespace
}  // namespace porter::piper

// Every number of the shipped file replaced by hostile values: NaN, infinities and 1e300 are
// refused naming the file; 0, -1, 1e-300, 1e9 load or are refused, never crash
// (tests/support/hostile_config.hpp).
TEST(ArmConfigHostile, EveryNumberIsRangeChecked) {
  const int replaced = porter::test::check_hostile_numbers("drivers/porter_arm.yaml", [](const std::string& f) { porter::piper::load_porter_arm_params(f); });
  EXPECT_GE(replaced, 11 * 11);
}
