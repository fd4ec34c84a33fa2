// porter-bench-livox: the simulated MID-360's speed on one core, and porter-lidar's CPU share
// at the sensor's 200,000 points/s. A benchmark, not a test: it prints, asserts nothing.
//
//   build/tests/bench/porter-bench-livox [--seconds S] [--part sim|driver|all]
//
// sim: SimulatedMid360 on one thread (Embree with one build thread) for S simulated seconds
//   (default 5) in 10 ms steps, on the shipped scenes `bridge` (T bar), `forest` (long bar,
//   seed 0) and a closed 8 x 8 x 3 m room (every ray returns), the robot driving forward at
//   0.5 m/s while joint 1 turns by 0.5 rad. rays/s = rays per thread-CPU second of advance();
//   real-time factor = simulated seconds per wall second. Also world-only casts of the same
//   rays through Embree and through core's SceneRayCaster (the exact-geometry reference).
// driver: porter-lidar as a child process (LCM on a free udpm port, nobody subscribed) fed S
//   seconds (default 10) of simulated packets over loopback at the real packet rate from this
//   process; its CPU share = (utime + stime from /proc/<pid>/stat) / wall time of the feed.
// Frozen fixture: seeds, scenes, motion and durations fixed; change them and results stop
// being comparable.

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "porter/core/payload.hpp"
#include "porter/core/payload_loader.hpp"
#include "porter/core/robot_loader.hpp"
#include "porter/core/scene_loader.hpp"
#include "porter/core/scene_ray_cast.hpp"
#include "porter/livox/udp.hpp"
#include "porter/livox_sim/scripted_motion.hpp"
#include "porter/livox_sim/simulated_mid360.hpp"
#include "private_lcm_url.hpp"

namespace {

using namespace porter;
using namespace porter::livox;
using namespace porter::livox::sim;

std::string source(const std::string& rel) { return std::string(PORTER_SOURCE_DIR) + "/" + rel; }

double thread_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}
double wall_s() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

CollisionShape box(Eigen::Vector3d c, Eigen::Vector3d size) {
  CollisionShape s;
  s.geometry = Box{size};
  s.T_parent_shape.translation() = c;
  return s;
}

std::vector<CollisionShape> room() {
  return {box({4.1, 0, 1.5}, {0.2, 8.4, 3}), box({-4.1, 0, 1.5}, {0.2, 8.4, 3}),
          box({0, 4.1, 1.5}, {8.4, 0.2, 3}), box({0, -4.1, 1.5}, {8.4, 0.2, 3}),
          box({0, 0, 3.1}, {8.4, 8.4, 0.2})};
}

struct Case {
  std::string name;
  std::vector<CollisionShape> obstacles;
  RobotModel robot;
  RobotConfiguration start;
};

std::vector<Case> cases() {
  const RobotModel bare = load_robot_model(source("config/robots/scout_mini_piper/robot.yaml"));
  std::vector<Case> out;
  for (const char* name : {"bridge", "forest"}) {
    const Scene s = load_scene(source(std::string("config/scenes/") + name + ".yaml"));
    out.push_back({name, s.obstacles, attach_payload(bare, load_payload(s.payload_file)), s.start});
  }
  RobotConfiguration c;
  c.base = {-1.0, 0.0, 0.0};
  c.q_rad << 0.0, 0.6, -0.9, 0.0, 0.5, 0.0;
  out.push_back({"room", room(), attach_payload(bare, load_payload(source("config/payloads/t_bar.yaml"))), c});
  return out;
}

ScriptedMotion motion_from(const RobotConfiguration& start, double seconds) {
  RobotConfiguration end = start;
  end.base.x_m += 0.5 * seconds;
  end.q_rad[0] += 0.5;
  return ScriptedMotion({{0.0, start}, {seconds, end}});
}

Mid360SimParams params() {
  Mid360SimParams p;
  p.T_B_S.translation() = Eigen::Vector3d(-0.22, 0.0, 0.5325);  // config/drivers/porter_lidar_sim.yaml
  p.seed = 1;
  return p;
}

void bench_sim(double seconds) {
  std::printf("== simulated MID-360, one thread, %.0f s simulated per scene (200,000 points/s) ==\n", seconds);
  std::printf("%-8s %9s %8s %9s %12s %8s %8s %8s | %12s %14s %6s\n", "scene", "triangles", "returns", "self hits",
              "rays/s (CPU)", "CPU %", "RTF CPU", "RTF wall", "Embree world", "SceneRayCaster", "ratio");
  for (const Case& c : cases()) {
    const ScriptedMotion motion = motion_from(c.start, seconds);
    SimulatedMid360 lidar(params(), c.robot, c.obstacles, [&](double t) { return motion.at(t); });
    std::vector<SimPacket> packets;
    packets.reserve(3000);
    const double cpu0 = thread_cpu_s(), wall0 = wall_s();
    for (double t = 0.0; t < seconds - 1e-9;) {
      const double next = std::min(seconds, t + 0.01);
      packets.clear();
      lidar.advance(t, next, packets);
      t = next;
    }
    const double cpu = thread_cpu_s() - cpu0, wall = wall_s() - wall0;
    const SimStats& st = lidar.stats();
    const double self = static_cast<double>(st.hits_by_kind[static_cast<int>(HitKind::robot)] +
                                            st.hits_by_kind[static_cast<int>(HitKind::payload)]);

    // World-only casts of one frame's rays from the start pose: Embree vs the exact reference.
    const ScanPattern pattern;
    const Eigen::Isometry3d T_W_S = c.start.base.T_W_B() * params().T_B_S;
    RaySceneParams rp;
    rp.ground_plane = false;
    RayScene embree(rp);
    embree.set_obstacles(c.obstacles);
    const SceneRayCaster reference(c.obstacles);
    const int n = 20000;
    std::vector<Eigen::Vector3d> dirs(n);
    for (int i = 0; i < n; ++i) dirs[i] = T_W_S.linear() * pattern.direction(i);
    const Eigen::Vector3d o = T_W_S.translation();
    double sink = 0.0;
    double t0 = thread_cpu_s();
    for (int rep = 0; rep < 5; ++rep) {
      for (int i = 0; i < n; ++i) sink += embree.cast_world(o.cast<float>(), dirs[i].cast<float>(), 0.1f, 40.0f).distance_m;
    }
    const double embree_rate = 5.0 * n / (thread_cpu_s() - t0);
    t0 = thread_cpu_s();
    for (int i = 0; i < n; ++i) sink += reference.cast(o, dirs[i], 40.0).distance_m;
    const double ref_rate = n / (thread_cpu_s() - t0);
    std::printf("%-8s %9zu %7.1f%% %8.2f%% %12.3g %7.1f%% %8.1f %8.1f | %12.3g %14.3g %5.2fx%s\n", c.name.c_str(),
                embree.world_triangles() + lidar.scene().robot_triangles(), 100.0 * st.returns / st.rays,
                100.0 * self / st.rays, st.rays / cpu, 100.0 * cpu / seconds, seconds / cpu, seconds / wall,
                embree_rate, ref_rate, embree_rate / ref_rate, sink == 12345.0 ? " " : "");
  }
  std::printf("columns: returns = rays with a return; self hits = rays ending on the robot or payload;\n"
              "rays/s = rays per thread-CPU second of advance() (ray casting, motion, IMU, encoding);\n"
              "CPU %% = CPU s per simulated s (share of one core needed to keep real time); RTF CPU =\n"
              "simulated s per CPU s (the real-time factor on a core of its own); RTF wall = simulated s\n"
              "per wall s in this run (lower when other processes share the core);\n"
              "last three: world-only casts of 20,000 rays of the pattern from the start pose, rays/s.\n");
}

long proc_cpu_ticks(pid_t pid) {
  std::ifstream f("/proc/" + std::to_string(pid) + "/stat");
  std::string s((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  const auto close = s.rfind(')');
  if (close == std::string::npos) return -1;
  std::istringstream rest(s.substr(close + 2));
  std::string field;
  long utime = 0, stime = 0;
  for (int i = 3; i <= 15; ++i) {
    rest >> field;
    if (i == 14) utime = std::stol(field);
    if (i == 15) stime = std::stol(field);
  }
  return utime + stime;
}

void bench_driver(double seconds) {
  std::printf("\n== porter-lidar at 200,000 points/s over loopback, %.0f s per scene ==\n", seconds);
  const std::string cfg = "/tmp/porter_bench_livox_" + std::to_string(::getpid()) + ".yaml";
  std::ofstream(cfg) << "lcm_url: \"" + porter::test::private_lcm_url() + "\"\n"
                        "network: {address: 127.0.0.1, point_port: 57363, imu_port: 57463, receive_buffer_bytes: 4194304}\n"
         "device: {configure: false, lidar_address: 127.0.0.1, lidar_command_port: 56100, host_address: 127.0.0.1,\n"
         "         host_command_port: 56101, host_push_port: 56201, retry_period_s: 2.0}\n"
                        "cloud: {rate_hz: 10.0, frame_id: lidar, extrinsic: {xyz: [0, 0, 0], rpy: [0, 0, 0]},\n"
                        "        keep_no_return: false, max_points: 400000}\n"
                        "imu: {frame_id: lidar_imu}\n"
                        "time: {host_window_s: 1.0, reset_threshold_s: 0.5, max_clamp_s: 0.0001}\n"
                        "check_crc: true\nstream_timeout_s: 1.0\nstatus_log_period_s: 10.0\n";
  std::printf("%-8s %10s %12s %10s %10s %9s\n", "scene", "packets", "points/s", "wall s", "CPU s", "CPU %");
  for (const Case& c : cases()) {
    if (c.name == "forest") continue;
    // Packets first (so this process only sends while porter-lidar is measured).
    const ScriptedMotion motion = motion_from(c.start, seconds);
    SimulatedMid360 lidar(params(), c.robot, c.obstacles, [&](double t) { return motion.at(t); });
    std::vector<SimPacket> packets;
    lidar.advance(0.0, seconds, packets);
    std::string error;
    auto points = UdpSender::open("127.0.0.1", 57363, 0, error);
    auto imu = UdpSender::open("127.0.0.1", 57463, 0, error);
    if (!points || !imu) {
      std::printf("%s\n", error.c_str());
      return;
    }
    const pid_t pid = ::fork();
    if (pid == 0) {
      const int null = ::open("/dev/null", O_WRONLY);
      ::dup2(null, STDERR_FILENO);
      ::execl(PORTER_LIDAR_BIN, PORTER_LIDAR_BIN, "--config", cfg.c_str(), static_cast<char*>(nullptr));
      ::_exit(127);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    const long ticks0 = proc_cpu_ticks(pid);
    const double start = wall_s();
    std::size_t k = 0;
    while (k < packets.size()) {
      const double now = wall_s() - start;
      for (; k < packets.size() && packets[k].time_s <= now; ++k) {
        (packets[k].stream == SimPacket::Stream::points ? *points : *imu).send(packets[k].bytes.data(), packets[k].size);
      }
      std::this_thread::sleep_for(std::chrono::microseconds(500));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(200));  // the last cloud is published
    const double wall = wall_s() - start;
    const long ticks1 = proc_cpu_ticks(pid);
    ::kill(pid, SIGTERM);
    ::waitpid(pid, nullptr, 0);
    const double cpu = static_cast<double>(ticks1 - ticks0) / ::sysconf(_SC_CLK_TCK);
    std::printf("%-8s %10zu %12.0f %10.2f %10.2f %8.1f%%\n", c.name.c_str(), packets.size(),
                lidar.stats().returns / seconds, wall, cpu, 100.0 * cpu / wall);
  }
  std::remove(cfg.c_str());
  std::printf("points/s = returns published (no-return points are dropped by the driver);\n"
              "CPU = porter-lidar's user + system time while it received, decoded, assembled and\n"
              "published (LCM udpm, ttl=0), from /proc/<pid>/stat (10 ms ticks).\n");
}

}  // namespace

int main(int argc, char** argv) {
  double seconds = 0.0;
  std::string part = "all";
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--seconds") && i + 1 < argc) seconds = std::atof(argv[++i]);
    else if (!std::strcmp(argv[i], "--part") && i + 1 < argc) part = argv[++i];
    else {
      std::fprintf(stderr, "usage: porter-bench-livox [--seconds S] [--part sim|driver|all]\n");
      return 2;
    }
  }
  if (part == "sim" || part == "all") bench_sim(seconds > 0 ? seconds : 5.0);
  if (part == "driver" || part == "all") bench_driver(seconds > 0 ? seconds : 10.0);
  return 0;
}
