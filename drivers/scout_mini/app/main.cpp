// porter-base: the Agilex Scout Mini driver (CAN protocol V2).
//
//   porter-base --config config/drivers/porter_base.yaml [--lcm-url URL] [--can SPEC]
//
// Reads BASE_CMD and ESTOP, sends 0x421/0x111 on the base's CAN bus, publishes BASE_STATE and
// HEARTBEAT. Exit codes: 0 after SIGINT/SIGTERM, 1 when LCM or the CAN bus cannot be opened or
// the bus closes, 2 for a bad command line or config file.
#include <string>

#include "base_config.hpp"
#include "base_node.hpp"
#include "porter/can/can_transport.hpp"
#include "porter/core/load_error.hpp"
#include "porter/runtime/clock.hpp"
#include "porter/runtime/log.hpp"
#include "porter/runtime/stop.hpp"

int main(int argc, char** argv) {
  using namespace porter;
  runtime::init_log("porter-base");
  std::string config_path, lcm_url, can_spec;
  bool have_url = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (i + 1 < argc && arg == "--config") {
      config_path = argv[++i];
    } else if (i + 1 < argc && arg == "--lcm-url") {
      lcm_url = argv[++i];
      have_url = true;
    } else if (i + 1 < argc && arg == "--can") {
      can_spec = argv[++i];
    } else {
      runtime::log_error("usage: porter-base --config FILE [--lcm-url URL] [--can SPEC] "
                         "(unexpected '" + arg + "')");
      return 2;
    }
  }
  if (config_path.empty()) {
    runtime::log_error("usage: porter-base --config FILE [--lcm-url URL] [--can SPEC]");
    return 2;
  }
  runtime::install_stop_handlers();
  const double t0 = runtime::mono_s();
  scout_mini::BaseNodeConfig config;
  try {
    config = scout_mini::load_base_config(config_path);
  } catch (const LoadError& e) {
    runtime::log_error(std::string("config: ") + e.what());
    return 2;
  }
  if (have_url) config.lcm_url = lcm_url;
  if (!can_spec.empty()) config.can_bus = can_spec;
  runtime::log_info("config " + config_path + " loaded in " +
                    runtime::format_ms(runtime::mono_s() - t0) + " (robot " + config.robot_config +
                    ", |v| <= " + std::to_string(config.driver.v_max_mps) + " m/s, |omega| <= " +
                    std::to_string(config.driver.omega_max_radps) + " rad/s)");

  LcmBus lcm(config.lcm_url);
  if (!lcm.good()) {
    runtime::log_error("LCM could not be opened at '" + config.lcm_url + "'");
    return 1;
  }
  const double t1 = runtime::mono_s();
  const std::string spec = can::with_lcm_url(config.can_bus, config.lcm_url);
  auto bus = can::open_can_bus(spec, "porter-base");
  if (!bus->is_open()) {
    runtime::log_error("CAN bus: " + bus->last_error());
    return 1;
  }
  runtime::log_info("CAN bus " + bus->describe() + " open in " +
                    runtime::format_ms(runtime::mono_s() - t1));
  scout_mini::BaseNode node(config, std::move(bus), lcm);
  const int code = node.run([] { return runtime::stop_requested(); });
  runtime::log_info(code == 0 ? "stopped" : "stopped with an error");
  return code;
}
