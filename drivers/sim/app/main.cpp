// porter-sim: the simulated hardware. Hosts the firmware models on their CAN buses, moves the
// robot in the scene, publishes SIM_TRUTH and LIO_POSE, applies SIM_COMMAND faults.
//
//   porter-sim --config config/drivers/porter_sim.yaml [--lcm-url URL] [--scene FILE]
//
// Exit codes: 0 after SIGINT/SIGTERM, 1 when LCM or a bus cannot be opened, 2 for a bad command
// line or config, scene, robot or payload file.
#include <string>

#include "porter/core/load_error.hpp"
#include "porter/core/yaml_reader.hpp"
#include "porter/runtime/clock.hpp"
#include "porter/runtime/log.hpp"
#include "porter/runtime/stop.hpp"
#include "sim_config.hpp"
#include "sim_process.hpp"

int main(int argc, char** argv) {
  using namespace porter;
  runtime::init_log("porter-sim");
  const std::string usage = "usage: porter-sim --config FILE [--lcm-url URL] [--scene FILE]";
  std::string config_path, lcm_url, scene;
  bool have_url = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (i + 1 < argc && arg == "--config") {
      config_path = argv[++i];
    } else if (i + 1 < argc && arg == "--lcm-url") {
      lcm_url = argv[++i];
      have_url = true;
    } else if (i + 1 < argc && arg == "--scene") {
      scene = argv[++i];
    } else {
      runtime::log_error(usage + " (unexpected '" + arg + "')");
      return 2;
    }
  }
  if (config_path.empty()) {
    runtime::log_error(usage);
    return 2;
  }
  runtime::install_stop_handlers();
  const double t0 = runtime::mono_s();
  sim::SimConfig config;
  try {
    config = sim::load_sim_config(config_path);
  } catch (const LoadError& e) {
    runtime::log_error(std::string("config: ") + e.what());
    return 2;
  }
  if (have_url) config.lcm_url = lcm_url;
  if (!scene.empty()) config.scene_path = scene;
  LcmBus lcm(config.lcm_url);
  if (!lcm.good()) {
    runtime::log_error("LCM could not be opened at '" + config.lcm_url + "'");
    return 1;
  }
  try {
    sim::SimProcess process(config, lcm);
    if (!process.ok()) {
      runtime::log_error(process.error());
      return 1;
    }
    runtime::log_info("built from " + config_path + " in " +
                      runtime::format_ms(runtime::mono_s() - t0));
    process.run([] { return runtime::stop_requested(); });
    runtime::log_info("stopped: real-time factor " + std::to_string(process.real_time_factor()) +
                      ", process CPU " + std::to_string(100.0 * process.cpu_fraction()) +
                      " % of one core, stepping took " +
                      std::to_string(100.0 * process.busy_fraction()) + " % of wall time");
  } catch (const LoadError& e) {
    runtime::log_error(e.what());
    return 2;
  }
  return 0;
}
