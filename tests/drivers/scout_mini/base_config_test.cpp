// porter-base's config: the shipped file loads and agrees with the robot config; an unknown,
// missing or out-of-range key, or a speed limit beyond the robot's wheels, is an error naming
// the file and the key.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include "base_config.hpp"
#include "base_messages.hpp"
#include "porter/core/load_error.hpp"
#include "hostile_config.hpp"

namespace porter::scout_mini {
namespace {

const std::string kSource = PORTER_SOURCE_DIR;

std::map<std::string, std::string> shipped_keys() {
  return {{"can_bus", "lcm:CAN_BASE"},
          {"lcm_url", "\"\""},
          {"robot", kSource + "/config/robots/scout_mini_piper/robot.yaml"},
          {"command_rate_hz", "50"},
          {"command_stale_s", "0.2"},
          {"v_max_mps", "1.0"},
          {"omega_max_radps", "2.5"},
          {"feedback_timeout_s", "0.25"},
          {"mode_retry_period_s", "0.1"},
          {"odometry_jump_m", "0.5"},
          {"stats_period_s", "30"},
          {"realtime_priority", "0"}};
}

std::string write(const std::map<std::string, std::string>& keys, const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / "porter_base_config_test";
  std::filesystem::create_directories(dir);
  const std::string path = (dir / name).string();
  std::ofstream out(path);
  for (const auto& [k, v] : keys) out << k << ": " << v << "\n";
  return path;
}

// The LoadError message for `keys`, "" when it loads.
std::string error_of(const std::map<std::string, std::string>& keys, const std::string& name,
                     bool names_this_file = true) {
  const std::string path = write(keys, name);
  try {
    load_base_config(path);
  } catch (const LoadError& e) {
    if (names_this_file) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
    return e.what();
  }
  return "";
}

TEST(BaseConfig, TheShippedFileLoadsAndTakesTheRobotsGeometry) {
  const BaseNodeConfig c = load_base_config(kSource + "/config/drivers/porter_base.yaml");
  EXPECT_EQ(c.can_bus, "lcm:CAN_BASE");
  EXPECT_EQ(c.lcm_url, "");
  EXPECT_DOUBLE_EQ(c.driver.command_period_s, 0.02);
  EXPECT_DOUBLE_EQ(c.driver.command_stale_s, 0.2);
  EXPECT_DOUBLE_EQ(c.driver.track_width_m, 0.4165);
  EXPECT_DOUBLE_EQ(c.driver.wheel_radius_m, 0.0875);
  EXPECT_DOUBLE_EQ(c.driver.wheel_omega_max_radps, 12.0);
  EXPECT_LE(c.driver.v_max_mps, c.driver.wheel_omega_max_radps * c.driver.wheel_radius_m);
  EXPECT_EQ(error_of(shipped_keys(), "ok.yaml"), "");
}

TEST(BaseConfig, BadKeysAreErrorsNamingTheKey) {
  auto keys = shipped_keys();
  keys["command_rate_hx"] = "50";
  EXPECT_NE(error_of(keys, "unknown.yaml").find("command_rate_hx"), std::string::npos);

  keys = shipped_keys();
  keys.erase("command_stale_s");
  const std::string missing = error_of(keys, "missing.yaml");
  EXPECT_NE(missing.find("'command_stale_s'"), std::string::npos) << missing;
  EXPECT_NE(missing.find("missing"), std::string::npos) << missing;

  keys = shipped_keys();
  keys["command_stale_s"] = "0.8";  // beyond the firmware's 0.5 s
  EXPECT_NE(error_of(keys, "stale.yaml").find("'command_stale_s'"), std::string::npos);

  keys = shipped_keys();
  keys["v_max_mps"] = "1.2";  // beyond 12 rad/s x 0.0875 m
  const std::string fast = error_of(keys, "fast.yaml");
  EXPECT_NE(fast.find("'v_max_mps'"), std::string::npos) << fast;
  EXPECT_NE(fast.find("wheel-speed limit 1.05"), std::string::npos) << fast;

  keys = shipped_keys();
  keys["omega_max_radps"] = "3.0";
  EXPECT_NE(error_of(keys, "omega.yaml").find("'omega_max_radps'"), std::string::npos);

  keys = shipped_keys();
  keys["can_bus"] = "can0";
  EXPECT_NE(error_of(keys, "bus.yaml").find("'can_bus'"), std::string::npos);

  keys = shipped_keys();
  keys["command_rate_hz"] = "fast";
  EXPECT_NE(error_of(keys, "type.yaml").find("'command_rate_hz'"), std::string::npos);

  keys = shipped_keys();
  keys["robot"] = "nowhere/robot.yaml";
  // The robot loader's error names the robot file it could not read.
  EXPECT_NE(error_of(keys, "robot.yaml", false).find("nowhere/robot.yaml"), std::string::npos);
}

TEST(BaseMessages, FeedbackBecomesBaseState) {
  BaseFeedback fb;
  fb.v_mps = 0.1;
  fb.motor_speed_rpm = {1, 2, 3, 4};
  fb.control_mode = 9;  // not a mode the message knows
  fb.vehicle_state = 2;
  fb.error_bits = 0x0108;
  fb.link_ok = true;
  const porter::base_state_t msg = to_base_state(fb, 123);
  EXPECT_EQ(msg.utime, 123);
  EXPECT_EQ(msg.num_motors, 4);
  ASSERT_EQ(msg.motor_speed_rpm.size(), 4u);
  EXPECT_EQ(msg.motor_speed_rpm[3], 4);
  EXPECT_EQ(msg.control_mode, porter::base_state_t::MODE_UNKNOWN);
  EXPECT_EQ(msg.vehicle_state, porter::base_state_t::VEHICLE_EXCEPTION);
  EXPECT_EQ(msg.fault_bits, 0x0108);
  EXPECT_TRUE(msg.link_ok);
  EXPECT_DOUBLE_EQ(msg.battery_soc_pct, -1.0);
  porter::base_cmd_t cmd;
  cmd.enabled = true;
  cmd.v_mps = -0.2;
  cmd.omega_radps = 0.1;
  const VelocityCommand c = to_command(cmd);
  EXPECT_TRUE(c.enabled);
  EXPECT_DOUBLE_EQ(c.v_mps, -0.2);
}

}  // namespace
}  // namespace porter::scout_mini

// Every number of the shipped file replaced by hostile values: NaN, infinities and 1e300 are
// refused naming the file; 0, -1, 1e-300, 1e9 load or are refused, never crash
// (tests/support/hostile_config.hpp).
TEST(BaseConfigHostile, EveryNumberIsRangeChecked) {
  const int replaced = porter::test::check_hostile_numbers("drivers/porter_base.yaml", [](const std::string& f) { porter::scout_mini::load_base_config(f); });
  EXPECT_GE(replaced, 11 * 9);
}
