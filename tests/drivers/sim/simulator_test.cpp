// The Simulator library: devices on named buses (frames crossing endpoints and between devices),
// dropped buses, sensors on contiguous intervals with exact truth, ground-truth and LIO rates and
// noise, faults routed to devices, and the Scout Mini firmware driving the world's base.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <memory>
#include <vector>

#include "porter/can/memory_bus.hpp"
#include "porter/scout_mini/firmware.hpp"
#include "porter/sim/pose_sensors.hpp"
#include "porter/sim/simulator.hpp"

namespace porter::sim {
namespace {

using can::CanFrame;

Scene empty_scene() {
  Scene scene;
  scene.name = "empty";
  scene.start.base = {0.5, -0.5, 0.25};
  scene.start.q_rad << 0.1, 0.2, -0.3, 0.0, 0.4, 0.0;
  return scene;
}

CanFrame frame(std::uint32_t id, std::uint8_t b0 = 0) {
  CanFrame f;
  f.id = id;
  f.dlc = 1;
  f.data[0] = b0;
  return f;
}

// Replies to every frame it receives with ID + 1 on its next advance; supports no faults.
class EchoNode final : public can::SimulatedNode {
 public:
  explicit EchoNode(std::string name) : name_(std::move(name)) {}
  void receive(const CanFrame& f, double t_s) override {
    received.push_back({t_s, f});
  }
  void advance(double t_s, std::vector<CanFrame>& out) override {
    for (; replied_ < received.size(); ++replied_) {
      CanFrame r = received[replied_].second;
      r.id += 1;
      r.utime = std::llround(t_s * 1e6);
      out.push_back(r);
    }
  }
  std::string name() const override { return name_; }
  std::vector<std::pair<double, CanFrame>> received;

 private:
  std::string name_;
  std::size_t replied_ = 0;
};

class RecordingSensor final : public SimSensor {
 public:
  std::string name() const override { return "recorder"; }
  void advance(const World& world, double t0, double t1) override {
    intervals.emplace_back(t0, t1);
    mid_x.push_back(world.robot_at(0.5 * (t0 + t1)).config.base.x_m);
    obstacles = world.obstacles().size();
  }
  std::vector<std::pair<double, double>> intervals;
  std::vector<double> mid_x;
  std::size_t obstacles = 0;
};

TEST(Simulator, FramesCrossEndpointsAndDevicesOnTheSameBusOnly) {
  Simulator sim(World(empty_scene(), RobotModel{}));
  auto endpoint = can::MemoryBus::open("sim_test_a");
  auto peer = can::MemoryBus::open("sim_test_a");
  ASSERT_TRUE(sim.add_bus("a", endpoint.get()));
  ASSERT_TRUE(sim.add_bus("b", nullptr));
  EXPECT_FALSE(sim.add_bus("a", nullptr));
  auto* echo = static_cast<EchoNode*>(sim.add_node("a", std::make_unique<EchoNode>("echo")));
  auto* other = static_cast<EchoNode*>(sim.add_node("b", std::make_unique<EchoNode>("other")));
  ASSERT_NE(echo, nullptr);
  ASSERT_NE(other, nullptr);
  EXPECT_EQ(sim.add_node("a", std::make_unique<EchoNode>("echo")), nullptr) << "names are unique";
  EXPECT_EQ(sim.add_node("nope", std::make_unique<EchoNode>("x")), nullptr);
  sim.world().set_utime_origin(5000000);
  sim.step_to(0.010);
  ASSERT_EQ(peer->send(frame(0x100, 7)), can::CanStatus::ok);
  sim.step_to(0.011);
  ASSERT_EQ(echo->received.size(), 1u);
  EXPECT_DOUBLE_EQ(echo->received[0].first, 0.010) << "delivered at the step's start";
  CanFrame reply;
  ASSERT_EQ(peer->receive(reply, 0), can::CanStatus::ok);
  EXPECT_EQ(reply.id, 0x101u);
  EXPECT_EQ(reply.data[0], 7);
  EXPECT_EQ(reply.utime, 5000000 + 11000) << "stamped with wall-clock time";
  EXPECT_TRUE(other->received.empty()) << "bus b is another bus";
  EXPECT_EQ(sim.bus_stats("a")->frames_in, 1u);
  EXPECT_EQ(sim.bus_stats("a")->frames_out, 1u);
  // A second device on bus a hears the first one's frames.
  auto* second = static_cast<EchoNode*>(sim.add_node("a", std::make_unique<EchoNode>("second")));
  ASSERT_TRUE(sim.inject("a", frame(0x200)));
  sim.step_to(0.012);
  ASSERT_GE(second->received.size(), 2u);
  EXPECT_EQ(second->received[0].second.id, 0x200u);
  EXPECT_EQ(second->received[1].second.id, 0x201u) << "echo's reply crossed the bus";
}

TEST(Simulator, ADroppedBusCarriesNothingEitherWay) {
  Simulator sim(World(empty_scene(), RobotModel{}));
  auto endpoint = can::MemoryBus::open("sim_test_drop");
  auto peer = can::MemoryBus::open("sim_test_drop");
  sim.add_bus("a", endpoint.get());
  auto* echo = static_cast<EchoNode*>(sim.add_node("a", std::make_unique<EchoNode>("echo")));
  EXPECT_TRUE(sim.drop_bus("a", true).ok);
  EXPECT_FALSE(sim.drop_bus("zz", true).ok);
  peer->send(frame(0x100));
  sim.step_to(0.01);
  EXPECT_TRUE(echo->received.empty());
  EXPECT_EQ(sim.bus_stats("a")->frames_dropped, 1u);
  EXPECT_TRUE(sim.drop_bus("a", false).ok);
  peer->send(frame(0x100));
  sim.step_to(0.02);
  EXPECT_EQ(echo->received.size(), 1u);
}

TEST(Simulator, SensorsSeeContiguousIntervalsWithExactTruth) {
  Simulator sim(World(empty_scene(), RobotModel{}), SimParams{0.002});
  double t_now = 0.0;
  sim.set_base_source(std::make_unique<FunctionBaseSource>([&sim] {
    BaseTruth b;
    b.pose_W.x_m = 2.0 * sim.time_s();  // 2 m/s along x, read at the step's end
    b.v_mps = 2.0;
    return b;
  }));
  auto sensor = std::make_unique<RecordingSensor>();
  RecordingSensor* rec = sensor.get();
  sim.add_sensor(std::move(sensor));
  sim.world().add_box("late", Eigen::Vector3d(1, 1, 1), Eigen::Vector3d(1, 1, 1), 0);
  for (double t : {0.001, 0.0015, 0.0105, 0.5}) {
    sim.step_to(t);
    t_now = t;
  }
  ASSERT_FALSE(rec->intervals.empty());
  EXPECT_DOUBLE_EQ(rec->intervals.front().first, 0.0);
  for (std::size_t i = 1; i < rec->intervals.size(); ++i) {
    EXPECT_DOUBLE_EQ(rec->intervals[i].first, rec->intervals[i - 1].second);
    EXPECT_LE(rec->intervals[i].second - rec->intervals[i].first, 0.002 + 1e-12);
  }
  EXPECT_DOUBLE_EQ(rec->intervals.back().second, t_now);
  for (std::size_t i = 0; i < rec->intervals.size(); ++i) {
    const double mid = 0.5 * (rec->intervals[i].first + rec->intervals[i].second);
    EXPECT_NEAR(rec->mid_x[i], 2.0 * mid, 1e-9) << i;
  }
  EXPECT_EQ(rec->obstacles, 1u);
  // Without sources the world holds the scene's start.
  Simulator still(World(empty_scene(), RobotModel{}));
  still.step_to(0.1);
  EXPECT_DOUBLE_EQ(still.world().latest().config.base.yaw_rad, 0.25);
  EXPECT_DOUBLE_EQ(still.world().latest().config.q_rad[4], 0.4);
}

TEST(Simulator, TruthAndLioComeAtTheirRatesWithTheConfiguredNoise) {
  for (double step : {0.001, 0.0037}) {
    Simulator sim(World(empty_scene(), RobotModel{}), SimParams{step});
    std::vector<RobotSample> truth;
    std::vector<PoseSample> lio;
    sim.add_sensor(std::make_unique<TruthSensor>(100.0, [&](const RobotSample& s) {
      truth.push_back(s);
    }));
    LioNoise noise;
    noise.position_sigma_m = 0.02;
    noise.yaw_sigma_rad = 0.01;
    noise.seed = 7;
    sim.add_sensor(std::make_unique<LioPoseSensor>(10.0, noise, [&](const PoseSample& p) {
      lio.push_back(p);
    }));
    sim.step_to(1.0);
    ASSERT_EQ(truth.size(), 100u) << step;
    EXPECT_NEAR(truth.front().t_s, 0.01, 1e-12);
    EXPECT_NEAR(truth.back().t_s, 1.0, 1e-12);
    ASSERT_EQ(lio.size(), 10u) << step;
    EXPECT_TRUE(lio[0].has_covariance);
    EXPECT_DOUBLE_EQ(lio[0].covariance[0], 0.0004);
    EXPECT_DOUBLE_EQ(lio[0].covariance[35], 0.0001);
  }
  // Noise statistics over many samples.
  Simulator sim(World(empty_scene(), RobotModel{}), SimParams{0.01});
  LioNoise noise;
  noise.position_sigma_m = 0.05;
  noise.yaw_sigma_rad = 0.02;
  double sx = 0, sxx = 0, syaw = 0, syy = 0;
  int n = 0;
  sim.add_sensor(std::make_unique<LioPoseSensor>(100.0, noise, [&](const PoseSample& p) {
    const double ex = p.pose_W.x_m - 0.5;
    const double eyaw = p.pose_W.yaw_rad - 0.25;
    sx += ex;
    sxx += ex * ex;
    syaw += eyaw;
    syy += eyaw * eyaw;
    ++n;
  }));
  sim.step_to(100.0);
  ASSERT_EQ(n, 10000);
  EXPECT_NEAR(sx / n, 0.0, 0.002);
  EXPECT_NEAR(std::sqrt(sxx / n), 0.05, 0.0025);
  EXPECT_NEAR(std::sqrt(syy / n), 0.02, 0.001);
  // No noise: the exact pose, no covariance.
  Simulator exact(World(empty_scene(), RobotModel{}));
  std::vector<PoseSample> clean;
  exact.add_sensor(std::make_unique<LioPoseSensor>(10.0, LioNoise{}, [&](const PoseSample& p) {
    clean.push_back(p);
  }));
  exact.step_to(0.2);
  ASSERT_EQ(clean.size(), 2u);
  EXPECT_DOUBLE_EQ(clean[0].pose_W.x_m, 0.5);
  EXPECT_FALSE(clean[0].has_covariance);
}

TEST(Simulator, FaultsReachTheNamedDeviceOrSayWhyNot) {
  Simulator sim(World(empty_scene(), RobotModel{}));
  sim.add_bus("base", nullptr);
  auto* fw = static_cast<scout_mini::ScoutMiniFirmware*>(
      sim.add_node("base", std::make_unique<scout_mini::ScoutMiniFirmware>()));
  sim.add_node("base", std::make_unique<EchoNode>("echo"));
  SimCommand c;
  c.kind = SimCommand::Kind::raise_error;
  c.target = "scout_mini";
  c.error_code = scout_mini::error_bit::kMotor1Comm;
  EXPECT_TRUE(sim.apply(c).ok);
  EXPECT_EQ(fw->errors(), scout_mini::error_bit::kMotor1Comm);
  c.kind = SimCommand::Kind::clear_errors;
  EXPECT_TRUE(sim.apply(c).ok);
  EXPECT_EQ(fw->errors(), 0);
  c.kind = SimCommand::Kind::stop_stream;
  c.can_id = 0x221;
  EXPECT_TRUE(sim.apply(c).ok) << sim.apply(c).message;
  c.can_id = 0x999;
  const SimResult bad_stream = sim.apply(c);
  EXPECT_FALSE(bad_stream.ok);
  EXPECT_NE(bad_stream.message.find("no stream 0x999"), std::string::npos) << bad_stream.message;
  c.kind = SimCommand::Kind::power_cycle;
  c.duration_s = 0.2;
  EXPECT_TRUE(sim.apply(c).ok);
  EXPECT_FALSE(fw->powered());
  sim.step_to(0.3);
  EXPECT_TRUE(fw->powered());
  c.duration_s = -1;
  EXPECT_FALSE(sim.apply(c).ok);
  c.target = "echo";  // supports no faults
  c.duration_s = 0.1;
  const SimResult unsupported = sim.apply(c);
  EXPECT_FALSE(unsupported.ok);
  EXPECT_NE(unsupported.message.find("cannot power-cycle"), std::string::npos);
  c.target = "nobody";
  EXPECT_NE(sim.apply(c).message.find("no device 'nobody'"), std::string::npos);
  c.kind = SimCommand::Kind::add_box;
  c.target = "crate";
  c.center_W = Eigen::Vector3d(1, 0, 0.5);
  c.size_m = Eigen::Vector3d(0.5, 0.5, 1.0);
  EXPECT_TRUE(sim.apply(c).ok);
  EXPECT_EQ(sim.world().obstacles().size(), 1u);
  EXPECT_FALSE(sim.apply(c).ok) << "duplicate name";
  c.kind = SimCommand::Kind::remove_obstacle;
  EXPECT_TRUE(sim.apply(c).ok);
  EXPECT_TRUE(sim.world().obstacles().empty());
}

TEST(Simulator, TheScoutMiniFirmwareDrivesTheWorldsBase) {
  const Scene scene = empty_scene();
  Simulator sim(World(scene, RobotModel{}));
  sim.add_bus("base", nullptr);
  scout_mini::PlanarPose start{scene.start.base.x_m, scene.start.base.y_m, scene.start.base.yaw_rad};
  auto* fw = static_cast<scout_mini::ScoutMiniFirmware*>(sim.add_node(
      "base", std::make_unique<scout_mini::ScoutMiniFirmware>(scout_mini::FirmwareParams{}, start)));
  sim.set_base_source(std::make_unique<FunctionBaseSource>([fw] {
    BaseTruth b;
    b.pose_W = {fw->pose().x_m, fw->pose().y_m, fw->pose().yaw_rad};
    b.v_mps = fw->v_mps();
    b.omega_radps = fw->omega_radps();
    return b;
  }));
  std::map<std::uint32_t, int> seen;
  sim.set_frame_tap([&](const std::string&, const CanFrame& f, bool from_device) {
    if (from_device) ++seen[f.id];
  });
  sim.inject("base", scout_mini::encode_control_mode(scout_mini::ControlMode::can));
  scout_mini::MotionCommand forward;
  forward.v_mps = 0.5;
  for (int k = 1; k <= 2000; ++k) {
    if (k % 20 == 0) sim.inject("base", scout_mini::encode_motion_command(forward));
    sim.step_to(k * 1e-3);
  }
  EXPECT_DOUBLE_EQ(sim.world().latest().v_mps, 0.5);
  const double travelled = sim.world().latest().config.base.x_m - scene.start.base.x_m;
  EXPECT_NEAR(travelled / std::cos(0.25), fw->wheel_left_m(), 1e-9);
  EXPECT_GT(travelled, 0.6);
  EXPECT_EQ(seen[0x221], 100);
  EXPECT_EQ(seen[0x211], 20);
}

}  // namespace
}  // namespace porter::sim
