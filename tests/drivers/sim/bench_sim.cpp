// porter-sim benchmark, the faster-than-real-time mode: how many times faster than real time the
// simulation runs (its real-time factor headroom; porter-sim itself runs at factor 1 and logs
// the share of a core its steps use), and the simulated MID-360's rays per CPU second.
//
//   porter-bench-sim [--seconds 60] [--scene config/scenes/forest.yaml]
//
// Built as porter-sim builds it (SimProcess from the shipped config: Scout Mini and Piper
// firmware, SIM_TRUTH at 100 Hz and LIO_POSE at 10 Hz encoded and published on an in-process
// LCM, the simulated MID-360 sending real UDP packets to a loopback socket this program holds
// open and never reads), with the buses in memory and the drivers' logic on their other ends in
// lockstep: BaseDriver (0x421, 0x111 at 50 Hz, the base driving a slalom) and ArmDriver (enable
// sequence, targets at 200 Hz, the arm swinging its first joint). Stepped at the configured 1 ms
// as fast as possible on one thread. Three runs: everything; without the LiDAR; the simulator
// alone (LiDAR on, no driver logic). Each reports simulated seconds per wall second, the process
// CPU time per simulated second, the cost per step (mean, p99, max) and, with the LiDAR, its
// rays per CPU second of the LiDAR's own work (thread CPU time inside its advance()).
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <optional>
#include <regex>
#include <string>
#include <vector>

#include "porter/can/memory_bus.hpp"
#include "porter/livox/udp.hpp"
#include "porter/piper/arm_driver.hpp"
#include "porter/runtime/log.hpp"
#include "porter/scout_mini/base_driver.hpp"
#include "sim_config.hpp"
#include "sim_process.hpp"

namespace {

using namespace porter;

std::string arg(int argc, char** argv, const char* key, const std::string& fallback) {
  for (int i = 1; i + 1 < argc; ++i) {
    if (std::strcmp(argv[i], key) == 0) return argv[i + 1];
  }
  return fallback;
}

double process_cpu_s() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_utime.tv_sec + u.ru_stime.tv_sec + 1e-6 * (u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

enum class Mode { full, no_lidar, sim_only };

void run(const std::string& scene, double seconds, Mode mode, const std::string& tag,
         std::uint16_t lidar_port) {
  const std::string source = PORTER_SOURCE_DIR;
  std::ifstream in(source + "/config/drivers/porter_sim.yaml");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  text = std::regex_replace(text, std::regex(R"(\.\./)"), source + "/config/");
  text = std::regex_replace(text, std::regex("lcm:CAN_BASE"), "memory:bench_sim_base_" + tag);
  text = std::regex_replace(text, std::regex("lcm:CAN_ARM"), "memory:bench_sim_arm_" + tag);
  text = std::regex_replace(text, std::regex("point_port: 56301"), "point_port: " + std::to_string(lidar_port));
  text = std::regex_replace(text, std::regex("imu_port: 56401"), "imu_port: " + std::to_string(lidar_port));
  text = std::regex_replace(text, std::regex("source_port: 56[34]00"), "source_port: 0");
  if (mode == Mode::no_lidar) text = std::regex_replace(text, std::regex("\n  enabled: true"), "\n  enabled: false");
  const std::string path = "/tmp/porter_bench_sim_" + std::to_string(::getpid()) + "_" + tag + ".yaml";
  std::ofstream(path) << text;
  sim::SimConfig config = sim::load_sim_config(path);
  std::remove(path.c_str());
  if (!scene.empty()) config.scene_path = scene;
  LcmBus lcm("memq://");
  sim::SimProcess process(config, lcm);
  if (!process.ok()) {
    std::printf("cannot build the simulator: %s\n", process.error().c_str());
    return;
  }
  sim::Simulator& sim = process.simulator();
  process.simulator().world().set_utime_origin(0);
  const bool drivers = mode != Mode::sim_only;
  auto base_bus = can::MemoryBus::open("bench_sim_base_" + tag);
  auto arm_bus = can::MemoryBus::open("bench_sim_arm_" + tag);
  scout_mini::BaseDriver base{scout_mini::DriverParams{}};
  piper::ArmDriverParams arm_params;
  for (int j = 0; j < piper::kNumJoints; ++j) {
    arm_params.lower_rad[j] = sim.world().robot().joints[j].lower_rad;
    arm_params.upper_rad[j] = sim.world().robot().joints[j].upper_rad;
  }
  piper::ArmDriver arm(arm_params);
  piper::ArmCommand arm_cmd;
  const JointVector q0 = sim.world().scene().start.q_rad;
  for (int j = 0; j < piper::kNumJoints; ++j) arm_cmd.q_rad[j] = q0[j];
  arm_cmd.speed_pct = 100;
  std::vector<can::CanFrame> out;
  std::vector<double> cost_us;
  const long steps = std::lround(seconds / config.step_s);
  cost_us.reserve(static_cast<std::size_t>(steps));
  std::uint64_t frames = 0;
  const double cpu0 = process_cpu_s();
  const auto wall0 = std::chrono::steady_clock::now();
  for (long k = 1; k <= steps; ++k) {
    const auto a = std::chrono::steady_clock::now();
    const double t = k * config.step_s;
    if (drivers) {
      can::CanFrame f;
      while (base_bus->receive(f, 0) == can::CanStatus::ok) {
        base.on_frame(f, t);
        ++frames;
      }
      while (arm_bus->receive(f, 0) == can::CanStatus::ok) {
        arm.on_frame(f, t);
        ++frames;
      }
      if (k % 20 == 0) {
        base.on_command({true, 0.6, 0.8 * std::sin(0.5 * t)}, t);
        out.clear();
        base.tick(t, out);
        for (const can::CanFrame& c : out) base_bus->send(c);
      }
      if (k % 5 == 0) {
        arm_cmd.q_rad[0] = 0.8 * std::sin(0.5 * t);
        arm.on_command(arm_cmd, t);
        out.clear();
        arm.step(t, out);
        for (const can::CanFrame& c : out) arm_bus->send(c);
      }
    }
    sim.step_to(t);
    if (k % 100 == 0) lcm.handle_pending();  // drain the in-process LCM queue
    cost_us.push_back(
        std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - a).count());
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  const double cpu = process_cpu_s() - cpu0;
  std::sort(cost_us.begin(), cost_us.end());
  double sum = 0;
  for (double c : cost_us) sum += c;
  const sim::RobotSample last = sim.world().latest();
  const char* label = mode == Mode::full       ? "base + arm firmware + LiDAR + drivers"
                      : mode == Mode::no_lidar ? "base + arm firmware + drivers, no LiDAR"
                                               : "base + arm firmware + LiDAR, no drivers";
  std::printf("%-40s scene %-7s %4.0f s simulated in %6.2f s: real-time factor %7.1f, CPU %.4f s "
              "per simulated s; per 1 ms step mean %.1f us, p99 %.1f us, max %.1f us; %llu "
              "feedback frames decoded; base at (%.1f, %.1f), q1 %.2f rad\n",
              label, sim.world().scene().name.c_str(), seconds, wall, seconds / wall,
              cpu / seconds, sum / cost_us.size(),
              cost_us[static_cast<std::size_t>(0.99 * (cost_us.size() - 1))], cost_us.back(),
              static_cast<unsigned long long>(frames), last.config.base.x_m, last.config.base.y_m,
              last.config.q_rad[0]);
  if (const sim::LidarSensor* lidar = process.lidar()) {
    const auto& s = lidar->stats();
    std::printf("%-40s %llu rays (%.0f per simulated s), %llu returns, %llu packets sent; LiDAR "
                "thread CPU %.2f s: %.2f million rays per CPU second (%.1f %% of one core at "
                "200,000 rays/s)\n",
                "  LiDAR:", static_cast<unsigned long long>(s.rays), s.rays / seconds,
                static_cast<unsigned long long>(s.returns),
                static_cast<unsigned long long>(process.lidar_sender()->sent()), lidar->cpu_s(),
                s.rays / lidar->cpu_s() * 1e-6, 100.0 * lidar->cpu_s() / seconds);
  }
}

}  // namespace

int main(int argc, char** argv) {
  runtime::init_log("porter-bench-sim", runtime::LogLevel::warn);
  const double seconds = std::stod(arg(argc, argv, "--seconds", "60"));
  const std::string scene = arg(argc, argv, "--scene", "");
  // A loopback socket that receives the LiDAR's datagrams and is never read (the kernel drops
  // what overflows its buffer): every send is a real send.
  std::string error;
  auto sink = livox::UdpReceiver::open("127.0.0.1", 0, 1 << 16, error);
  if (!sink) {
    std::printf("cannot open the LiDAR's sink socket: %s\n", error.c_str());
    return 1;
  }
  const std::uint16_t port = sink->port();
  run(scene, seconds, Mode::full, "a", port);
  run(scene, seconds, Mode::no_lidar, "b", port);
  run(scene, seconds, Mode::sim_only, "c", port);
  return 0;
}
