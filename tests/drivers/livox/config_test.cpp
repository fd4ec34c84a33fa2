// porter-lidar's and porter-lidar-sim's config files: the shipped ones load, and every kind of
// mistake is a LoadError naming the file and the key.
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include <gtest/gtest.h>
#include <unistd.h>

#include "lidar_params.hpp"
#include "lidar_sim_params.hpp"
#include "porter/core/load_error.hpp"
#include "sim_support.hpp"
#include "hostile_config.hpp"

namespace porter::livox::app {
namespace {

std::string read(const std::string& path) {
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

/// Writes `text` to a file of its own in the temp directory.
class TempConfig {
 public:
  explicit TempConfig(const std::string& text) {
    path_ = (std::filesystem::temp_directory_path() /
             ("porter_livox_config_" + std::to_string(::getpid()) + "_" + std::to_string(counter_++) + ".yaml"))
                .string();
    std::ofstream(path_) << text;
  }
  ~TempConfig() { std::filesystem::remove(path_); }
  const std::string& path() const { return path_; }

 private:
  static inline int counter_ = 0;
  std::string path_;
};

std::string lidar_yaml() { return read(test::config_path("drivers/porter_lidar.yaml")); }
/// The shipped simulator config with its relative paths made absolute.
std::string sim_yaml() {
  return std::regex_replace(read(test::config_path("drivers/porter_lidar_sim.yaml")),
                            std::regex("\\.\\./"), test::config_path(""));
}

/// The LoadError message of loading `text` with `load`, "" when it loads.
template <class F>
std::string error_of(const std::string& text, F load) {
  TempConfig c(text);
  try {
    load(c.path());
  } catch (const LoadError& e) {
    EXPECT_NE(std::string(e.what()).find(c.path()), std::string::npos) << e.what();
    return e.what();
  }
  return "";
}

TEST(LidarConfig, ShippedFileLoads) {
  const LidarParams p = load_lidar_params(test::config_path("drivers/porter_lidar.yaml"));
  EXPECT_EQ(p.point_port, 56301);
  EXPECT_EQ(p.imu_port, 56401);
  EXPECT_EQ(p.listen_address, "0.0.0.0");
  EXPECT_DOUBLE_EQ(p.stream.cloud.period_s, 0.1);
  EXPECT_EQ(p.cloud_frame_id, "lidar");
  EXPECT_TRUE(p.stream.cloud.T_out_sensor.isApprox(Eigen::Isometry3d::Identity()));
  EXPECT_TRUE(p.stream.decode.check_crc);
  EXPECT_DOUBLE_EQ(p.stream.host_time.window_s, 1.0);
  EXPECT_FALSE(p.device.configure);
  EXPECT_EQ(p.device.lidar_command_port, 56100);
}

TEST(LidarConfig, MistakesNameTheKey) {
  auto load = [](const std::string& f) { load_lidar_params(f); };
  const std::string y = lidar_yaml();
  EXPECT_NE(error_of(y + "\nextra_key: 1\n", load).find("extra_key"), std::string::npos);
  EXPECT_NE(error_of(std::regex_replace(y, std::regex("  point_port: 56301"), "  point_port: 70000"), load)
                .find("network.point_port"), std::string::npos);
  EXPECT_NE(error_of(std::regex_replace(y, std::regex("  imu_port: 56401"), "  imu_port: 56301"), load)
                .find("network.imu_port"), std::string::npos);
  EXPECT_NE(error_of(std::regex_replace(y, std::regex("  rate_hz: 10.0"), "  rate_hz: 500"), load)
                .find("cloud.rate_hz"), std::string::npos);
  EXPECT_NE(error_of(std::regex_replace(y, std::regex("check_crc: true"), "check_crc: yes please"), load)
                .find("check_crc"), std::string::npos);
  EXPECT_NE(error_of(std::regex_replace(y, std::regex("  frame_id: lidar_imu"), "  frame: lidar_imu"), load)
                .find("imu.frame"), std::string::npos);
  EXPECT_NE(error_of(std::regex_replace(y, std::regex("lidar_address: 192.168.1.100"), "lidar_address: lidar.local"), load)
                .find("device.lidar_address"), std::string::npos);
  const std::string missing = error_of(std::regex_replace(y, std::regex("stream_timeout_s: 1.0"), ""), load);
  EXPECT_NE(missing.find("stream_timeout_s"), std::string::npos) << missing;
  EXPECT_NE(error_of(std::regex_replace(y, std::regex("rpy: \\[0.0, 0.0, 0.0\\]"), "rpy: [0.0, 0.0]"), load)
                .find("cloud.extrinsic.rpy"), std::string::npos);
}

TEST(LidarSimConfig, ShippedFileLoadsWithTheMountFromTheUrdf) {
  const LidarSimSetup s = load_lidar_sim_setup(test::config_path("drivers/porter_lidar_sim.yaml"));
  // lidar_mast at (-0.22, 0, 0.245) on the base, the point frame 0.2875 m above it.
  EXPECT_TRUE(s.sensor.T_B_S.translation().isApprox(Eigen::Vector3d(-0.22, 0.0, 0.5325), 1e-12));
  EXPECT_TRUE(s.sensor.T_B_S.linear().isApprox(Eigen::Matrix3d::Identity()));
  EXPECT_EQ(s.robot.payload_name, "t_bar");  // the bridge scene's payload
  ASSERT_EQ(s.waypoints.size(), 1u);
  EXPECT_EQ(s.waypoints[0].config.q_rad, s.scene.start.q_rad);
  EXPECT_DOUBLE_EQ(s.sensor.pattern.point_rate_hz, 200000.0);
  EXPECT_DOUBLE_EQ(s.sensor.pattern.elevation_min_deg, -7.0);
  EXPECT_DOUBLE_EQ(s.sensor.pattern.elevation_max_deg, 52.0);
  EXPECT_EQ(s.sensor.data_type, DataType::kCartesianHigh);
  EXPECT_EQ(s.network.point_port, 56301);
}

TEST(LidarSimConfig, MistakesNameTheKey) {
  auto load = [](const std::string& f) { load_lidar_sim_setup(f); };
  const std::string y = sim_yaml();
  EXPECT_NE(error_of(std::regex_replace(y, std::regex("  seed: 1"), "  seed: 1\n  colour: red"), load)
                .find("sensor.colour"), std::string::npos);
  // A link that moves with the arm cannot carry the sensor.
  const std::string moving = error_of(std::regex_replace(y, std::regex("link: lidar_mast"), "link: link3"), load);
  EXPECT_NE(moving.find("sensor.mount.link"), std::string::npos) << moving;
  EXPECT_NE(moving.find("fixed joints"), std::string::npos) << moving;
  EXPECT_NE(error_of(std::regex_replace(y, std::regex("link: lidar_mast"), "link: no_such_link"), load)
                .find("no such link"), std::string::npos);
  EXPECT_NE(error_of(std::regex_replace(y, std::regex("elevation_deg: \\[-7.0, 52.0\\]"), "elevation_deg: [52.0, -7.0]"), load)
                .find("sensor.elevation_deg"), std::string::npos);
  EXPECT_NE(error_of(std::regex_replace(y, std::regex("dropout_probability: 0.0"), "dropout_probability: 1.5"), load)
                .find("sensor.dropout_probability"), std::string::npos);
  EXPECT_NE(error_of(std::regex_replace(y, std::regex("data_type: cartesian_high"), "data_type: polar"), load)
                .find("sensor.data_type"), std::string::npos);
  EXPECT_NE(error_of(std::regex_replace(y, std::regex("waypoints: \\[\\]"),
                                        "waypoints: [[1, 0, 0, 0, 0, 0, 0, 0, 0, 0], [0.5, 0, 0, 0, 0, 0, 0, 0, 0, 0]]"), load)
                .find("motion.waypoints[1]"), std::string::npos);
  EXPECT_NE(error_of(std::regex_replace(y, std::regex("waypoints: \\[\\]"), "waypoints: [[1, 0, 0]]"), load)
                .find("motion.waypoints[0]"), std::string::npos);
}

}  // namespace
}  // namespace porter::livox::app

// Every number of the shipped files replaced by hostile values: NaN, infinities and 1e300 are
// refused naming the file; 0, -1, 1e-300, 1e9 load or are refused, never crash
// (tests/support/hostile_config.hpp).
TEST(LidarConfigHostile, EveryNumberIsRangeChecked) {
  EXPECT_GE(porter::test::check_hostile_numbers("drivers/porter_lidar.yaml",
                                                [](const std::string& f) { porter::livox::app::load_lidar_params(f); }),
            11 * 20);
  EXPECT_GE(porter::test::check_hostile_numbers("drivers/porter_lidar_sim.yaml",
                                                [](const std::string& f) { porter::livox::app::load_lidar_sim_setup(f); }),
            11 * 31);
}
