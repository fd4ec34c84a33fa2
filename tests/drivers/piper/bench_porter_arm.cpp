// porter-bench-arm: porter-arm (the real process) against a firmware hosted on the LCM arm bus,
// in real time. Measures
//   1. the 0x155 send period while streaming (porter-arm's send stamps): mean, p99, max and
//      jitter against the configured 5 ms;
//   2. stale ARM_CMD -> hold: from the last ARM_CMD published while the arm moves to the first
//      target frame carrying the hold position, and to the simulated arm at rest (N trials);
//   3. power cycle -> arm enabled and in CAN mode again (M trials).
// Timings depend on the machine's load; this is a benchmark, no test asserts them.
//
//   porter-bench-arm [--stream-s 10] [--trials 100] [--power-cycles 20]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "arm_process_support.hpp"
#include "porter/piper/feedback.hpp"
#include "porter/runtime/clock.hpp"
#include "private_lcm_url.hpp"

using namespace porter::piper;
using namespace porter::piper::test;

namespace {

const std::string kCanUrl = porter::test::private_lcm_url();
const std::string kLcmUrl = porter::test::private_lcm_url();

struct Stats {
  double mean = 0, p50 = 0, p99 = 0, max = 0;
};
Stats stats_of(std::vector<double> v) {
  Stats s;
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  for (double x : v) s.mean += x / static_cast<double>(v.size());
  s.p50 = v[v.size() / 2];
  s.p99 = v[std::min(v.size() - 1, static_cast<std::size_t>(std::ceil(0.99 * static_cast<double>(v.size()))) - 1)];
  s.max = v.back();
  return s;
}

double j1_target_rad(const porter::can::CanFrame& f) {
  const std::int32_t mdeg = porter::piper::wire::get_i32(f, 0);
  return mdeg_to_rad(mdeg);
}

}  // namespace

int main(int argc, char** argv) {
  double stream_s = 10.0;
  int trials = 100;
  int power_cycles = 20;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--stream-s")) stream_s = std::atof(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--trials")) trials = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--power-cycles")) power_cycles = std::atoi(argv[i + 1]);
    else {
      std::fprintf(stderr, "usage: porter-bench-arm [--stream-s S] [--trials N] [--power-cycles M]\n");
      return 2;
    }
  }
  FirmwareHost host(kCanUrl, [](std::uint32_t id) { return id == id::kJointCtrl12; });
  porter::LcmBus lcm(kLcmUrl);
  ArmProcess arm(PORTER_ARM_EXE, PORTER_SOURCE_DIR, kCanUrl, kLcmUrl, "bench");
  if (!host.bus_open() || !lcm.good() || !arm.started()) {
    std::fprintf(stderr, "bench: setup failed: %s\n", host.bus_error().c_str());
    return 1;
  }
  porter::arm_cmd_t cmd;
  cmd.enabled = true;
  cmd.num_joints = 6;
  cmd.q_rad = {0, 0.5, -0.5, 0, 0, 0};
  cmd.qd_radps.assign(6, 0.0);
  cmd.speed_pct = 50;
  cmd.plan_id = -1;
  cmd.source = "porter-bench-arm";
  std::int64_t last_publish_utime = 0;
  auto publish = [&] {
    last_publish_utime = porter::runtime::wall_utime();
    lcm.publish(porter::channels::kArmCmd, cmd);
  };
  auto enabled_can = [&] {
    const PiperTruth t = host.truth();
    return t.ctrl_mode == 1 && std::all_of(t.joint_enabled.begin(), t.joint_enabled.end(), [](bool e) { return e; });
  };
  if (!wait_for(lcm, enabled_can, 30.0, publish)) {
    std::fprintf(stderr, "bench: the arm was not enabled\n%s", arm.log().c_str());
    return 1;
  }
  std::printf("porter-bench-arm: porter-arm pid %d, loop 200 Hz, cmd_timeout 0.2 s, ARM_CMD at 100 Hz\n",
              static_cast<int>(arm.pid()));

  // 1. Send period while streaming.
  wait_for(lcm, [] { return false; }, 1.0, publish);
  host.take_kept();
  wait_for(lcm, [] { return false; }, stream_s, publish);
  const std::vector<porter::can::CanFrame> frames = host.take_kept();
  std::vector<double> period_ms, jitter_ms;
  for (std::size_t i = 1; i < frames.size(); ++i) {
    const double p = static_cast<double>(frames[i].utime - frames[i - 1].utime) * 1e-3;
    period_ms.push_back(p);
    jitter_ms.push_back(std::abs(p - 5.0));
  }
  const Stats sp = stats_of(period_ms), sj = stats_of(jitter_ms);
  std::printf("0x155 send period over %.0f s (%zu frames): mean %.3f ms, p50 %.3f, p99 %.3f, max %.3f ms; "
              "|period - 5 ms|: mean %.3f, p99 %.3f, max %.3f ms\n",
              stream_s, frames.size(), sp.mean, sp.p50, sp.p99, sp.max, sj.mean, sj.p99, sj.max);

  // 2. Stale ARM_CMD -> hold.
  std::vector<double> hold_ms, rest_ms;
  int failed = 0;
  for (int trial = 0; trial < trials; ++trial) {
    cmd.q_rad[0] = (trial % 2 == 0) ? 0.6 : -0.6;
    const double commanded = mdeg_to_rad(rad_to_mdeg(cmd.q_rad[0]));
    wait_for(lcm, [] { return false; }, 0.25, publish);  // moving at 1.5 rad/s
    host.take_kept();
    const std::int64_t t_last = last_publish_utime;
    // No more commands: wait for the hold frame and the arm at rest.
    std::int64_t t_hold = 0, t_rest = 0;
    const auto deadline = Clock::now() + std::chrono::seconds(3);
    while (Clock::now() < deadline && (t_hold == 0 || t_rest == 0)) {
      lcm.handle_timeout(1);
      for (const porter::can::CanFrame& f : host.take_kept()) {
        if (t_hold == 0 && std::abs(j1_target_rad(f) - commanded) > 1e-6) t_hold = f.utime;
      }
      if (t_hold != 0 && t_rest == 0) {
        const PiperTruth t = host.truth();
        if (std::all_of(t.qd_radps.begin(), t.qd_radps.end(), [](double v) { return v == 0.0; })) {
          t_rest = porter::runtime::wall_utime();
        }
      }
    }
    if (t_hold == 0 || t_rest == 0) {
      ++failed;
      continue;
    }
    hold_ms.push_back(static_cast<double>(t_hold - t_last) * 1e-3);
    rest_ms.push_back(static_cast<double>(t_rest - t_last) * 1e-3);
  }
  const Stats sh = stats_of(hold_ms), sr = stats_of(rest_ms);
  std::printf("stale ARM_CMD -> hold target sent, %zu trials (%d failed): mean %.1f ms, p99 %.1f, max %.1f ms\n",
              hold_ms.size(), failed, sh.mean, sh.p99, sh.max);
  std::printf("stale ARM_CMD -> simulated arm at rest (1.5 rad/s, 10 rad/s^2): mean %.1f ms, p99 %.1f, max %.1f ms\n",
              sr.mean, sr.p99, sr.max);

  // 3. Power cycle -> enabled and in CAN mode again.
  std::vector<double> reenable_ms;
  int lost = 0;
  for (int i = 0; i < power_cycles; ++i) {
    wait_for(lcm, [] { return false; }, 0.2, publish);
    const auto t0 = Clock::now();
    host.with_firmware([](PiperFirmware& fw) { fw.power_cycle(); });
    if (!wait_for(lcm, enabled_can, 5.0, publish)) {
      ++lost;
      continue;
    }
    reenable_ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
  }
  const Stats se = stats_of(reenable_ms);
  std::printf("power cycle -> enabled + CAN mode, %zu cycles (%d not recovered in 5 s): mean %.1f ms, max %.1f ms "
              "(10 ms polling)\n",
              reenable_ms.size(), lost, se.mean, se.max);

  const int rc = arm.terminate(10.0);
  std::printf("porter-arm exit status %d after SIGTERM\n", rc);
  return rc == 0 && failed == 0 && lost == 0 ? 0 : 1;
}
