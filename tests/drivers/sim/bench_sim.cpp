// porter-sim benchmark: how many times faster than real time the simulation runs with the Scout
// Mini firmware hosted, i.e. its real-time factor headroom (porter-sim itself runs at factor 1
// and logs the share of a core its steps use).
//
//   porter-bench-sim [--seconds 120] [--scene config/scenes/forest.yaml]
//
// Built as porter-sim builds it (SimProcess from the shipped config, the base bus in memory,
// SIM_TRUTH at 100 Hz and LIO_POSE at 10 Hz encoded and published on an in-process LCM), with
// the driver's logic (BaseDriver) on the other end of the bus in lockstep: 0x421 and 0x111 at
// 50 Hz, every feedback frame decoded, the base driving a slalom. Stepped at the configured
// 1 ms as fast as possible on one thread; reports simulated seconds per wall second and the
// cost per step (mean, p99, max), then the same without the driver (the simulator alone).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include "porter/can/memory_bus.hpp"
#include "porter/runtime/clock.hpp"
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

struct Result {
  double rtf;
  double mean_us, p99_us, max_us;
  std::uint64_t frames;
};

Result run(const std::string& scene, double seconds, bool with_driver, const std::string& tag) {
  const std::string source = PORTER_SOURCE_DIR;
  std::ifstream in(source + "/config/drivers/porter_sim.yaml");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  text = std::regex_replace(text, std::regex(R"(\.\./)"), source + "/config/");
  text = std::regex_replace(text, std::regex("lcm:CAN_BASE"), "memory:bench_sim_base_" + tag);
  text = std::regex_replace(text, std::regex("lcm:CAN_ARM"), "memory:bench_sim_arm_" + tag);
  const std::string path = "/tmp/porter_bench_sim_" + tag + ".yaml";
  std::ofstream(path) << text;
  sim::SimConfig config = sim::load_sim_config(path);
  if (!scene.empty()) config.scene_path = scene;
  LcmBus lcm("memq://");
  sim::SimProcess process(config, lcm);
  sim::Simulator& sim = process.simulator();
  auto driver_bus = can::MemoryBus::open("bench_sim_base_" + tag);
  scout_mini::BaseDriver driver{scout_mini::DriverParams{}};
  std::vector<can::CanFrame> out;
  std::vector<double> cost_us;
  const long steps = std::lround(seconds / config.step_s);
  cost_us.reserve(static_cast<std::size_t>(steps));
  std::uint64_t frames = 0;
  const auto wall0 = std::chrono::steady_clock::now();
  for (long k = 1; k <= steps; ++k) {
    const auto a = std::chrono::steady_clock::now();
    const double t = k * config.step_s;
    if (with_driver) {
      can::CanFrame f;
      while (driver_bus->receive(f, 0) == can::CanStatus::ok) {
        driver.on_frame(f, t);
        ++frames;
      }
      if (k % 20 == 0) {
        driver.on_command({true, 0.6, 0.8 * std::sin(0.5 * t)}, t);
        out.clear();
        driver.tick(t, out);
        for (const can::CanFrame& c : out) driver_bus->send(c);
      }
    }
    sim.step_to(t);
    if (k % 100 == 0) lcm.handle_pending();  // drain the in-process LCM queue
    cost_us.push_back(
        std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - a).count());
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  std::sort(cost_us.begin(), cost_us.end());
  double sum = 0;
  for (double c : cost_us) sum += c;
  Result r;
  r.rtf = seconds / wall;
  r.mean_us = sum / cost_us.size();
  r.p99_us = cost_us[static_cast<std::size_t>(0.99 * (cost_us.size() - 1))];
  r.max_us = cost_us.back();
  r.frames = frames;
  const sim::RobotSample last = sim.world().latest();
  std::printf("%-38s scene %-8s %6.0f s simulated in %6.2f s: real-time factor %7.1f; per 1 ms "
              "step mean %.1f us, p99 %.1f us, max %.1f us; %llu feedback frames decoded; base at "
              "(%.1f, %.1f)\n",
              with_driver ? "simulator + Scout Mini + driver logic" : "simulator + Scout Mini",
              sim.world().scene().name.c_str(), seconds, wall, r.rtf, r.mean_us, r.p99_us,
              r.max_us, static_cast<unsigned long long>(frames), last.config.base.x_m,
              last.config.base.y_m);
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  runtime::init_log("porter-bench-sim", runtime::LogLevel::warn);
  const double seconds = std::stod(arg(argc, argv, "--seconds", "120"));
  const std::string scene = arg(argc, argv, "--scene", "");
  run(scene, seconds, true, "a");
  run(scene, seconds, false, "b");
  return 0;
}
