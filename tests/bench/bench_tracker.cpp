// porter-bench-tracker: runs porter-tracker as a process (its shipped config: 100 Hz, SCHED_FIFO
// when permitted) on a private udpm port for --duration-s seconds while this program plays the
// rest of the robot: ROBOT_STATE at 100 Hz from a unicycle that obeys BASE_CMD, and one
// TRAJECTORY (a circle, 0.4 m/s, longer than the run) so the tracker does its real work every
// period. Reports
//   - the tracker's period jitter (|period - 10 ms|) and wake-up lateness, p50 / p99 / p99.9 /
//     max, from the process's own statistics (its --stats-out JSON, written at SIGTERM);
//   - BASE_CMD one-way latency on loopback udpm: receive time here minus the message's utime
//     (the tracker stamps it just before publishing; same host, same clock), taken by a thread
//     blocked in lcm_handle; and the arrival part of it: the kernel's receive timestamp of the
//     datagram (LCM's recv_utime, SO_TIMESTAMP) minus utime, which leaves out this program's
//     own wake-up (LCM's receive thread, then the handling thread, both SCHED_OTHER);
//   - the tracking errors the tracker reported, to show it was tracking throughout.
// Nothing here is a test; figures depend on the machine and its load.
//
// usage: porter-bench-tracker [--duration-s 60] [--port P (default: a free port)] [--tracker PATH] [--config PATH]

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fcntl.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "../tracker/trajectory_fixtures.hpp"
#include "porter/channels.hpp"
#include "porter/lcm_bus.hpp"
#include "porter/msg/trajectory_msg.hpp"
#include "porter/runtime/clock.hpp"
#include "private_lcm_url.hpp"

namespace {

std::string load_average() {
  std::ifstream in("/proc/loadavg");
  std::string line;
  std::getline(in, line);
  return line.empty() ? "unknown" : line;
}

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const auto i = static_cast<std::size_t>(std::ceil(q * static_cast<double>(v.size()))) ;
  return v[std::min(v.size() - 1, i == 0 ? 0 : i - 1)];
}

}  // namespace

int main(int argc, char** argv) {
  double duration_s = 60.0;
  int port = 0;  // 0: a free port
  std::string tracker = PORTER_TRACKER_BIN;
  std::string config = std::string(PORTER_SOURCE_DIR) + "/config/tracker/porter_tracker.yaml";
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--duration-s") duration_s = std::stod(argv[i + 1]);
    else if (a == "--port") port = std::stoi(argv[i + 1]);
    else if (a == "--tracker") tracker = argv[i + 1];
    else if (a == "--config") config = argv[i + 1];
    else {
      std::fprintf(stderr, "unknown argument %s\n", argv[i]);
      return 2;
    }
  }
  const std::string url = port == 0 ? porter::test::private_lcm_url()
                                    : "udpm://239.255.76.67:" + std::to_string(port) + "?ttl=0";
  const std::string stats = "/tmp/porter-bench-tracker-" + std::to_string(getpid()) + ".json";
  const std::string log = "/tmp/porter-bench-tracker-" + std::to_string(getpid()) + ".log";

  porter::LcmBus bus(url);
  porter::LcmBus listen_bus(url);
  if (!bus.good() || !listen_bus.good()) {
    std::fprintf(stderr, "LCM unavailable at %s\n", url.c_str());
    return 4;
  }
  std::mutex mutex;
  porter::base_cmd_t last_cmd;
  std::vector<double> latency_us;
  latency_us.reserve(static_cast<std::size_t>(duration_s * 110));
  double max_cross_m = 0.0, max_along_m = 0.0;
  std::int64_t tracking_reports = 0, other_reports = 0;
  // LCM calls a channel's handlers in subscription order: the raw one (kernel receive time)
  // runs just before the typed one for the same datagram.
  std::vector<double> arrival_us;
  arrival_us.reserve(latency_us.capacity());
  std::int64_t recv_utime = 0;
  listen_bus.lcm().subscribeFunction(
      std::string(porter::channels::kBaseCmd.name()),
      +[](const lcm::ReceiveBuffer* rbuf, const std::string&, std::int64_t* out) {
        *out = rbuf->recv_utime;
      },
      &recv_utime);
  listen_bus.subscribe(porter::channels::kBaseCmd, [&](const porter::base_cmd_t& m) {
    const double lat = static_cast<double>(porter::runtime::wall_utime() - m.utime);
    std::lock_guard<std::mutex> lock(mutex);
    latency_us.push_back(lat);
    arrival_us.push_back(static_cast<double>(recv_utime - m.utime));
    last_cmd = m;
  });
  listen_bus.subscribe(porter::channels::kTrackerStatus, [&](const porter::tracker_status_t& m) {
    std::lock_guard<std::mutex> lock(mutex);
    if (m.state == porter::tracker_status_t::STATE_TRACKING) {
      ++tracking_reports;
      max_cross_m = std::max(max_cross_m, std::abs(m.cross_track_error_m));
      max_along_m = std::max(max_along_m, std::abs(m.along_track_error_m));
    } else {
      ++other_reports;
    }
  });
  std::atomic<bool> listening{true};
  std::thread listener([&] {
    while (listening) listen_bus.handle_timeout(100);
  });

  const pid_t pid = fork();
  if (pid == 0) {
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) dup2(fd, STDERR_FILENO);
    execl(tracker.c_str(), tracker.c_str(), "--config", config.c_str(), "--lcm-url", url.c_str(),
          "--stats-out", stats.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  std::printf("porter-tracker pid %d on %s for %.0f s (log %s); load average %s\n", pid,
              url.c_str(), duration_s, log.c_str(), load_average().c_str());
  std::fflush(stdout);

  // A circle of radius 1.5 m at 0.4 m/s, long enough for the whole run, starting 0.5 s from now.
  const porter::Trajectory circle = porter::test::arc(0.4, 1.5, duration_s + 10.0, +1);
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  porter::minco_trajectory_t traj =
      porter::to_msg(circle, porter::runtime::wall_utime() + 500'000, 1, "world", "");
  traj.utime = porter::runtime::wall_utime();
  bus.publish(porter::channels::kTrajectory, traj);

  porter::BasePose pose;
  auto next = std::chrono::steady_clock::now();
  std::int64_t last = porter::runtime::wall_utime();
  const std::int64_t end = last + static_cast<std::int64_t>(duration_s * 1e6);
  while (porter::runtime::wall_utime() < end) {
    next += std::chrono::milliseconds(10);
    std::this_thread::sleep_until(next);
    const std::int64_t now = porter::runtime::wall_utime();
    porter::base_cmd_t cmd;
    {
      std::lock_guard<std::mutex> lock(mutex);
      cmd = last_cmd;
    }
    const double dt = static_cast<double>(now - last) * 1e-6;
    last = now;
    if (cmd.enabled) {
      pose.x_m += cmd.v_mps * std::cos(pose.yaw_rad) * dt;
      pose.y_m += cmd.v_mps * std::sin(pose.yaw_rad) * dt;
      pose.yaw_rad += cmd.omega_radps * dt;
    }
    porter::robot_state_t s{};
    s.utime = now;
    s.frame_id = "world";
    s.x_m = pose.x_m;
    s.y_m = pose.y_m;
    s.yaw_rad = std::remainder(pose.yaw_rad, 2.0 * M_PI);
    s.v_mps = cmd.enabled ? cmd.v_mps : 0.0;
    s.omega_radps = cmd.enabled ? cmd.omega_radps : 0.0;
    s.num_joints = 6;
    s.q_rad.assign(6, 0.0);
    s.qd_radps.assign(6, 0.0);
    s.pose_source = porter::robot_state_t::POSE_SIM_TRUTH;
    s.base_valid = s.arm_valid = s.pose_valid = true;
    s.base_utime = s.arm_utime = s.pose_utime = now;
    bus.publish(porter::channels::kRobotState, s);
  }
  kill(pid, SIGTERM);
  int status = 0;
  waitpid(pid, &status, 0);
  listening = false;
  listener.join();

  std::ifstream in(stats);
  const std::string json((std::istreambuf_iterator<char>(in)), {});
  std::printf("porter-tracker exit status %d; load average %s; its statistics (%s):\n%s",
              WEXITSTATUS(status), load_average().c_str(), stats.c_str(),
              json.empty() ? "(none written)\n" : json.c_str());
  std::lock_guard<std::mutex> lock(mutex);
  std::printf("BASE_CMD one-way latency, udpm loopback, %zu messages: p50 %.0f us, p99 %.0f us, "
              "p99.9 %.0f us, max %.0f us\n",
              latency_us.size(), quantile(latency_us, 0.5), quantile(latency_us, 0.99),
              quantile(latency_us, 0.999), quantile(latency_us, 1.0));
  std::printf("BASE_CMD utime to kernel receive timestamp, %zu messages: p50 %.0f us, p99 %.0f us, "
              "p99.9 %.0f us, max %.0f us\n",
              arrival_us.size(), quantile(arrival_us, 0.5), quantile(arrival_us, 0.99),
              quantile(arrival_us, 0.999), quantile(arrival_us, 1.0));
  std::printf("TRACKER_STATUS: %lld TRACKING reports (max |cross-track| %.4f m, max |along-track| "
              "%.4f m), %lld in other states\n",
              static_cast<long long>(tracking_reports), max_cross_m, max_along_m,
              static_cast<long long>(other_reports));
  std::remove(stats.c_str());
  return json.empty() ? 1 : 0;
}
