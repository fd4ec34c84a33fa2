// porter-base benchmark: porter-base's real loop (BaseNode) against the simulated Scout Mini in
// real time, BASE_CMD over LCM (udpm, private port), the CAN bus in memory or LCM-carried. A
// third node on the CAN bus (the sniffer) timestamps every frame as it arrives
// (CLOCK_MONOTONIC).
//
//   porter-bench-base stop   [--trials 100] [--can memory|lcm] [--v 0.5] [--w 0.2] [--rt-priority 0]
//   porter-bench-base crash  [--trials 20]  [--v 0.5] [--w 0.2]      (memory bus only)
//   porter-bench-base period [--seconds 60] [--can memory|lcm] [--rt-priority 0]
//
// stop:   per trial, BASE_CMD streams at 100 Hz for 0.8 s, then stops; measured from the last
//         BASE_CMD publish to (a) the first zero 0x111 on the bus (the driver's staleness stop),
//         (b) the base's first 0x221 reporting v = omega = 0 with every wheel's 0x251..0x254
//         reporting 0 rpm (zero wheel speed reported by the simulated base; includes the base's
//         deceleration), (c) BASE_STATE showing v = 0.
// crash:  the same, but at the last BASE_CMD the driver's bus is cut (a driver that dies): the
//         base stops only by the firmware's own 500 ms timeout, the last line.
// period: the 0x111 inter-arrival times on the bus (mean, p50, p99 and max |period - 20 ms|),
//         and the driver loop's own wake-up lateness. --rt-priority N runs the driver's command
//         loop (realtime_priority in porter_base.yaml) and the sniffer at SCHED_FIFO N.
// Nothing here is a test; results depend on the machine's load (report `cat /proc/loadavg`).
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <pthread.h>
#include <sched.h>

#include "private_lcm_url.hpp"
#include "node_harness.hpp"
#include "porter/can/memory_bus.hpp"
#include "porter/runtime/log.hpp"

namespace {

using namespace porter;
using namespace porter::scout_mini;
namespace harness = porter::scout_mini::test;

const std::string kLcmUrl = porter::test::private_lcm_url();
const std::string kCanLcmUrl = [] {
  std::string url = porter::test::private_lcm_url();
  while (url == kLcmUrl) url = porter::test::private_lcm_url();
  return url;
}();

struct Stamped {
  double t_s;
  can::CanFrame frame;
};

// A node on the CAN bus recording every frame with its arrival time.
class Sniffer {
 public:
  explicit Sniffer(const std::string& spec, int rt_priority = 0)
      : bus_(can::open_can_bus(spec, "sniffer")) {
    thread_ = std::thread([this, rt_priority] {
      if (rt_priority > 0) {
        sched_param param{};
        param.sched_priority = rt_priority;
        pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
      }
      can::CanFrame f;
      while (!stop_.load()) {
        if (bus_->receive(f, 50) == can::CanStatus::ok) {
          const double t = runtime::mono_s();
          std::lock_guard<std::mutex> lock(mutex_);
          frames_.push_back({t, f});
        }
      }
    });
  }
  ~Sniffer() {
    stop_ = true;
    thread_.join();
  }
  std::vector<Stamped> since(double t0) {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<Stamped> out;
    for (const Stamped& s : frames_) {
      if (s.t_s > t0) out.push_back(s);
    }
    return out;
  }
  void clear() {
    std::lock_guard<std::mutex> lock(mutex_);
    frames_.clear();
  }

 private:
  std::unique_ptr<can::CanBus> bus_;
  std::mutex mutex_;
  std::vector<Stamped> frames_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

struct Summary {
  double mean, p50, p99, max;
};

Summary summarize(std::vector<double> v) {
  Summary s{0, 0, 0, 0};
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  double sum = 0;
  for (double x : v) sum += x;
  s.mean = sum / v.size();
  s.p50 = v[v.size() / 2];
  s.p99 = v[std::min(v.size() - 1, static_cast<std::size_t>(std::ceil(0.99 * v.size())) - 1)];
  s.max = v.back();
  return s;
}

std::string arg(int argc, char** argv, const char* key, const std::string& fallback) {
  for (int i = 2; i + 1 < argc; ++i) {
    if (std::strcmp(argv[i], key) == 0) return argv[i + 1];
  }
  return fallback;
}

// (a), (b) times after t_last from the sniffed frames; negative when not seen.
void analyse(const std::vector<Stamped>& frames, double t_last, double& zero_cmd, double& zero_report) {
  zero_cmd = zero_report = -1;
  double rpm[4] = {1, 1, 1, 1};
  bool motion_zero = false;
  for (const Stamped& s : frames) {
    MotionCommand c;
    MotionState m;
    ActuatorHighSpeed hs;
    if (zero_cmd < 0 && decode_motion_command(s.frame, c) == DecodeStatus::ok && c.v_mps == 0 &&
        c.omega_radps == 0) {
      zero_cmd = s.t_s - t_last;
    }
    if (decode_motion_state(s.frame, m) == DecodeStatus::ok) {
      motion_zero = m.v_mps == 0 && m.omega_radps == 0;
    }
    if (decode_actuator_high_speed(s.frame, hs) == DecodeStatus::ok) rpm[hs.motor] = hs.speed_rpm;
    if (zero_report < 0 && motion_zero && rpm[0] == 0 && rpm[1] == 0 && rpm[2] == 0 &&
        rpm[3] == 0) {
      zero_report = s.t_s - t_last;
    }
  }
}

int run_stop(int argc, char** argv, bool crash) {
  const int trials = std::stoi(arg(argc, argv, "--trials", crash ? "20" : "100"));
  const std::string transport = crash ? "memory" : arg(argc, argv, "--can", "memory");
  const double v = std::stod(arg(argc, argv, "--v", "0.5"));
  const double w = std::stod(arg(argc, argv, "--w", "0.2"));
  const std::string spec =
      transport == "lcm" ? "lcm:CAN_BASE@" + kCanLcmUrl : std::string("memory:bench_stop");
  harness::SimulatedBase base(spec);
  if (!base.open()) {
    std::fprintf(stderr, "bus: %s\n", base.error().c_str());
    return 1;
  }
  Sniffer sniffer(spec);
  harness::Client client(kLcmUrl);
  std::printf("%s: %d trials, CAN %s, driver loop SCHED_FIFO %s, BASE_CMD v %.2f m/s omega %.2f "
              "rad/s at 100 Hz for 0.8 s, then none\n",
              crash ? "crash (driver's bus cut at the last BASE_CMD)" : "stale stop", trials,
              spec.c_str(), arg(argc, argv, "--rt-priority", "0").c_str(), v, w);
  std::vector<double> cmd_ms, report_ms, state_ms;
  int missed = 0;
  auto driver_bus = crash ? can::MemoryBus::open("bench_stop") : nullptr;
  can::MemoryBus* cut = driver_bus.get();
  BaseNodeConfig config = harness::node_config(spec);
  config.realtime_priority = std::stoi(arg(argc, argv, "--rt-priority", "0"));
  auto driver = crash ? std::make_unique<harness::DriverProcess>(config, kLcmUrl,
                                                                 std::move(driver_bus))
                      : std::make_unique<harness::DriverProcess>(config, kLcmUrl);
  if (!client.wait_for([](const porter::base_state_t& s) { return s.link_ok && s.control_mode == 1; },
                       20.0)) {
    std::fprintf(stderr, "the base never reached CAN command mode\n");
    return 1;
  }
  for (int trial = 0; trial < trials; ++trial) {
    if (cut != nullptr) cut->reconnect();
    client.stream(v, w, 0.8);
    client.command(v, w);
    const double t_last = runtime::mono_s();
    if (cut != nullptr) cut->disconnect();
    double t_state = -1;
    while (runtime::mono_s() - t_last < 3.0) {
      const porter::base_state_t s = client.state();
      if (t_state < 0 && s.v_mps == 0 && s.omega_radps == 0 && s.utime != 0) {
        t_state = runtime::mono_s() - t_last;
      }
      double zc, zr;
      analyse(sniffer.since(t_last), t_last, zc, zr);
      if (zr >= 0 && (t_state >= 0 || crash)) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    double zc, zr;
    analyse(sniffer.since(t_last), t_last, zc, zr);
    if (zr < 0) {
      ++missed;
    } else {
      if (!crash) cmd_ms.push_back(zc * 1e3);
      report_ms.push_back(zr * 1e3);
      if (!crash && t_state >= 0) state_ms.push_back(t_state * 1e3);
    }
    sniffer.clear();
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  auto line = [](const char* what, const std::vector<double>& v) {
    if (v.empty()) return;
    const Summary s = summarize(v);
    std::printf("  %-58s n %3zu  mean %6.1f  p50 %6.1f  p99 %6.1f  max %6.1f ms\n", what, v.size(),
                s.mean, s.p50, s.p99, s.max);
  };
  if (!crash) line("last BASE_CMD -> first zero 0x111 on the bus", cmd_ms);
  line("last BASE_CMD -> base reports zero speed (0x221, 0x251..4)", report_ms);
  if (!crash) line("last BASE_CMD -> BASE_STATE v = omega = 0", state_ms);
  if (missed) std::printf("  trials without a zero report within 3 s: %d\n", missed);
  driver->stop();
  return 0;
}

int run_period(int argc, char** argv) {
  const double seconds = std::stod(arg(argc, argv, "--seconds", "60"));
  const std::string transport = arg(argc, argv, "--can", "memory");
  const std::string spec =
      transport == "lcm" ? "lcm:CAN_BASE@" + kCanLcmUrl : std::string("memory:bench_period");
  const int rt = std::stoi(arg(argc, argv, "--rt-priority", "0"));
  harness::SimulatedBase base(spec);
  Sniffer sniffer(spec, rt);
  harness::Client client(kLcmUrl);
  BaseNodeConfig config = harness::node_config(spec);
  config.realtime_priority = rt;
  harness::DriverProcess driver(config, kLcmUrl);
  client.wait_for([](const porter::base_state_t& s) { return s.link_ok && s.control_mode == 1; }, 20.0);
  const double t0 = runtime::mono_s();
  client.stream(0.3, 0.1, seconds);
  const double t1 = runtime::mono_s();
  driver.stop();
  std::vector<double> periods_ms, jitter_us;
  double prev = -1;
  for (const Stamped& s : sniffer.since(t0)) {
    // The streaming window only (shutdown adds one zero 0x111 out of the schedule).
    if (s.frame.id != id::kMotionCommand || s.t_s > t1) continue;
    if (prev >= 0) {
      periods_ms.push_back((s.t_s - prev) * 1e3);
      jitter_us.push_back(std::abs(s.t_s - prev - 0.02) * 1e6);
    }
    prev = s.t_s;
  }
  const Summary p = summarize(periods_ms);
  const Summary j = summarize(jitter_us);
  const auto& late = driver.node().lateness();
  std::printf("0x111 period on the bus (%s, SCHED_FIFO %d), %.0f s, %zu periods: mean %.4f ms, "
              "p50 %.4f ms, min..max %.3f..%.3f ms\n",
              spec.c_str(), rt, seconds, periods_ms.size(), p.mean, p.p50,
              *std::min_element(periods_ms.begin(), periods_ms.end()), p.max);
  std::printf("  |period - 20 ms|: mean %.1f us, p50 %.1f us, p99 %.1f us, max %.1f us\n", j.mean,
              j.p50, j.p99, j.max);
  std::printf("  driver loop wake-up lateness (send side): mean %.1f us, p99 %.1f us, max %.1f us "
              "over %llu cycles\n",
              late.mean_s() * 1e6, late.quantile_s(0.99) * 1e6, late.max_s() * 1e6,
              static_cast<unsigned long long>(driver.node().cycles()));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  porter::runtime::init_log("porter-bench-base", porter::runtime::LogLevel::warn);
  const std::string mode = argc > 1 ? argv[1] : "";
  if (mode == "stop") return run_stop(argc, argv, false);
  if (mode == "crash") return run_stop(argc, argv, true);
  if (mode == "period") return run_period(argc, argv);
  std::fprintf(stderr, "usage: porter-bench-base stop|crash|period [options] (see the source)\n");
  return 2;
}
