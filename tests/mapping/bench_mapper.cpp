// porter-bench-mapper: the mapper against stock OctoMap on the same clouds.
//
//   porter-bench-mapper [--clouds N] [--stock-clouds M] [--publish-hz F] [--pcl]
//
// --pcl: instead, the PCL voxel grid and statistical outlier removal at 0.05 m, their cost and
// what they change in the map.
//
// Fixtures (do not change them, or figures stop being comparable): the simulated MID-360 as
// shipped on the robot carrying the long bar, noiseless, 200,000 points/s in 10 Hz clouds,
// (a) "room": a closed 12 x 8 x 3 m room, the robot driving 0.5 m/s and turning (every ray
// returns: 20,000 points a cloud), (b) "forest": config/scenes/forest.yaml (seed 1), the robot
// driving along a free lane at 0.8 m/s. The mapper runs with config/mapping/porter_mapper.yaml
// at 0.1 m and 0.05 m (the window scaled to the same 20 x 20 x 3.2 m).
//
// Columns, per scene and resolution, over the same clouds:
//   pts      points per cloud given to the mapper (after the driver; before any filter)
//   filter   mapper's filter(): range, self-filter, de-skew — CPU ms per cloud
//   integ    mapper's integrate() — CPU ms per cloud
//   full     writing the OctoMap binary stream from every voxel of the window
//            (write_octomap_binary, the reference) — CPU ms per map
//   inc      the same bytes from the incremental writer the process uses, a map after every
//            cloud that makes one due at publish_rate_hz — CPU ms per map, the first map (which
//            encodes every brick) left out; checked equal to the full stream at the end ("!"
//            after the figure when not)
//   mapper pts/s   points per CPU second of filter + integrate
//   CPU@200k       share of one core for 200,000 points/s: 10 clouds/s of filter + integrate,
//                  plus publish_rate_hz maps/s (inc)
//   stock    octomap::OcTree::insertPointCloud(filtered points, origin, max_range) — CPU ms per
//            cloud on the first --stock-clouds clouds; x = stock / (mapper integrate) on those
// Then the process's node run in real time, with the window recentring as shipped (as porter-mapper runs it, without LCM): a feeder
// thread hands the clouds and their states to the node at 10 Hz, a worker thread steps it and
// encodes MAP_OCTOMAP at publish_rate_hz (--publish-hz overrides the shipped rate):
//   c2m      cloud-to-published-map: wall time from a cloud's arrival (on_cloud) to its map
//            message encoded, ready to publish — median, p95 and max over the maps
//   cpu      the worker's CPU time on that path (processing the cloud, writing and encoding the
//            map), median over the maps: what c2m would be with a core to itself
//   maps     maps made; busy = clouds that arrived while another was processed (dropped ones
//            are counted in it too)
//   CPU      process CPU time (both threads) over the run's wall time, % of one core
#include <time.h>

#include <algorithm>
#include <atomic>
#include <thread>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "mapper_conversions.hpp"
#include "mapper_node.hpp"
#include "mapping_support.hpp"
#include "porter/mapping/octomap_binary.hpp"

namespace pm = porter::mapping;
using porter::livox::sim::Waypoint;

namespace {

double cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec + ts.tv_nsec * 1e-9;
}
double wall_s() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + ts.tv_nsec * 1e-9;
}

std::vector<porter::CollisionShape> room(double hx, double hy, double h) {
  auto box = [](Eigen::Vector3d c, Eigen::Vector3d size) {
    porter::CollisionShape s;
    s.geometry = porter::Box{size};
    s.T_parent_shape.translation() = c;
    return s;
  };
  const double t = 0.2;
  return {box({hx + t / 2, 0, h / 2}, {t, 2 * hy + 2 * t, h}), box({-hx - t / 2, 0, h / 2}, {t, 2 * hy + 2 * t, h}),
          box({0, hy + t / 2, h / 2}, {2 * hx + 2 * t, t, h}), box({0, -hy - t / 2, h / 2}, {2 * hx + 2 * t, t, h}),
          box({0, 0, h + t / 2}, {2 * hx + 2 * t, 2 * hy + 2 * t, t}),
          box({2.5, 1.5, 0.75}, {0.4, 0.4, 1.5}), box({-3.0, -2.0, 0.5}, {1.0, 0.6, 1.0})};
}

struct Recorded {
  std::vector<pm::SensorCloud> clouds;
  std::vector<std::vector<std::pair<std::int64_t, porter::RobotConfiguration>>> states;  // per cloud
};

Recorded record(const porter::RobotModel& robot, const std::vector<porter::CollisionShape>& obstacles,
                std::vector<Waypoint> waypoints, const Eigen::Isometry3d& T_B_S, int n) {
  pm::test::SimDrive drive(robot, obstacles, std::move(waypoints), T_B_S);
  Recorded r;
  pm::StateBuffer unused;
  for (int k = 0; k < n; ++k) {
    std::vector<std::pair<std::int64_t, porter::RobotConfiguration>> s;
    r.clouds.push_back(drive.next(unused, &s).cloud);
    r.states.push_back(std::move(s));
  }
  return r;
}

double process_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return ts.tv_sec + ts.tv_nsec * 1e-9;
}

/// Quantile q of v (nearest rank); 0 when empty.
double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t i = static_cast<std::size_t>(std::ceil(q * static_cast<double>(v.size()))) - (q > 0.0 ? 1 : 0);
  return v[std::min(i, v.size() - 1)];
}

std::vector<porter::robot_state_t> state_messages(const Recorded& rec, std::size_t k) {
  std::vector<porter::robot_state_t> out;
  for (const auto& [t, c] : rec.states[k]) {
    porter::robot_state_t s{};
    s.utime = t;
    s.x_m = c.base.x_m;
    s.y_m = c.base.y_m;
    s.yaw_rad = c.base.yaw_rad;
    s.num_joints = 6;
    s.q_rad.assign(c.q_rad.data(), c.q_rad.data() + 6);
    out.push_back(s);
  }
  return out;
}

porter::point_cloud_t cloud_message(const Recorded& rec, std::size_t k, const std::string& frame_id) {
  porter::point_cloud_t msg{};
  const pm::SensorCloud& c = rec.clouds[k];
  msg.utime = c.utime;
  msg.frame_id = frame_id;
  msg.scan_id = static_cast<std::int64_t>(k);
  msg.num_points = static_cast<std::int32_t>(c.size());
  msg.x_m = c.x_m;
  msg.y_m = c.y_m;
  msg.z_m = c.z_m;
  msg.intensity.assign(c.size(), 0.0f);
  msg.time_offset_ns = c.time_offset_ns;
  msg.line.assign(c.size(), 0);
  msg.tag.assign(c.size(), 0);
  return msg;
}

struct PacedResult {
  std::vector<double> c2m_s;
  std::vector<double> path_cpu_s;  ///< worker CPU time of the same maps: the cloud's processing + the map
  std::uint64_t busy = 0, dropped = 0, processed = 0;
  double cpu_share = 0.0;
};

/// The node in real time: clouds at 10 Hz from a feeder thread, a worker as porter-mapper's.
PacedResult run_paced(const Recorded& rec, const porter::RobotModel& robot, const pm::app::MapperConfig& cfg) {
  std::vector<std::vector<porter::robot_state_t>> states;
  std::vector<porter::point_cloud_t> clouds;
  for (std::size_t k = 0; k < rec.clouds.size(); ++k) {
    states.push_back(state_messages(rec, k));
    clouds.push_back(cloud_message(rec, k, cfg.cloud_frame_id));
  }
  pm::app::MapperNode node(cfg, robot);
  const auto now_ns = [] { return static_cast<std::int64_t>(wall_s() * 1e9); };
  PacedResult out;
  std::atomic<bool> fed{false};
  const double cpu0 = process_cpu_s(), wall0 = wall_s();
  std::thread worker([&] {
    porter::octomap_t map_msg;
    std::vector<std::uint8_t> buf;
    for (;;) {
      pm::app::StepResult r;
      const bool done = fed.load();
      const double cpu_before = cpu_s();  // waiting inside step() costs no CPU
      if (!node.step(now_ns(), 20'000'000, r)) {
        if (done && node.counters().clouds_processed + node.counters().dropped_queue_full >= clouds.size()) break;
        continue;
      }
      if (!r.map_due) continue;
      node.make_map(map_msg);
      buf.resize(static_cast<std::size_t>(map_msg.getEncodedSize()));
      map_msg.encode(buf.data(), 0, static_cast<int>(buf.size()));
      out.c2m_s.push_back((now_ns() - r.received_ns) * 1e-9);
      out.path_cpu_s.push_back(cpu_s() - cpu_before);
    }
  });
  const std::int64_t start = now_ns();
  for (std::size_t k = 0; k < clouds.size(); ++k) {
    const std::int64_t due = start + static_cast<std::int64_t>(k) * 100'000'000;
    for (std::int64_t t = now_ns(); t < due; t = now_ns()) std::this_thread::sleep_for(std::chrono::nanoseconds(due - t));
    for (const porter::robot_state_t& s : states[k]) node.on_state(s);
    node.on_cloud(clouds[k], now_ns());
  }
  fed = true;
  worker.join();
  out.cpu_share = (process_cpu_s() - cpu0) / (wall_s() - wall0);
  const pm::app::MapperCounters c = node.counters();
  out.busy = c.arrived_while_busy;
  out.dropped = c.dropped_queue_full;
  out.processed = c.clouds_processed;
  return out;
}

void run(const char* scene, const Recorded& rec, const porter::RobotModel& robot, pm::app::MapperConfig cfg,
         double res, int stock_clouds) {
  const double scale = 0.05 / res;
  cfg.mapper.map.resolution_m = res;
  cfg.mapper.map.dims = (cfg.mapper.map.dims.cast<double>() * scale).array().round().cast<int>().matrix();
  pm::app::MapperConfig paced_cfg = cfg;  // the process as shipped: the window recentres
  cfg.mapper.recenter_distance_m = 100.0;

  // Mapper, phase by phase.
  pm::Mapper mapper(robot, cfg.mapper);
  pm::StateBuffer states;
  std::vector<pm::FilteredCloud> filtered(rec.clouds.size());
  std::vector<double> integ_s(rec.clouds.size());
  double filter_cpu = 0.0, integ_cpu = 0.0, points = 0.0, inc_cpu = 0.0;
  int inc_maps = 0;
  pm::OctomapBinaryWriter writer;
  std::vector<std::uint8_t> stream;
  const int clouds_per_map = std::max(1, static_cast<int>(std::lround(10.0 / cfg.publish_rate_hz)));
  for (std::size_t k = 0; k < rec.clouds.size(); ++k) {
    for (const auto& [t, c] : rec.states[k]) states.add(t, c);
    double t0 = cpu_s();
    mapper.filter(rec.clouds[k], states, filtered[k]);
    double t1 = cpu_s();
    mapper.integrate(filtered[k]);
    double t2 = cpu_s();
    filter_cpu += t1 - t0;
    integ_cpu += t2 - t1;
    integ_s[k] = t2 - t1;
    points += static_cast<double>(rec.clouds[k].size());
    if (k % static_cast<std::size_t>(clouds_per_map) == 0) {
      const double t3 = cpu_s();
      writer.write(mapper.map(), stream);
      if (k > 0) {  // the first map encodes every brick; steady state is what counts per map
        inc_cpu += cpu_s() - t3;
        ++inc_maps;
      }
    }
  }
  writer.write(mapper.map(), stream);  // the final map, to compare with the full stream
  std::vector<std::uint8_t> full;
  double full_cpu = 0.0;
  for (int i = 0; i < 3; ++i) {
    const double t0 = cpu_s();
    pm::write_octomap_binary(mapper.map(), full);
    full_cpu += (cpu_s() - t0) / 3.0;
  }
  const bool same_stream = inc_maps > 0 && stream == full;
  const double n = static_cast<double>(rec.clouds.size());
  const double inc_ms = inc_maps > 0 ? 1e3 * inc_cpu / inc_maps : 0.0;
  const double cpu_share = 10.0 * (filter_cpu + integ_cpu) / n + cfg.publish_rate_hz * 1e-3 * inc_ms;

  // Stock OctoMap on the same filtered clouds.
  octomap::OcTree stock(res);
  double stock_cpu = 0.0, ours_same = 0.0;
  const int ns = std::min<int>(stock_clouds, static_cast<int>(filtered.size()));
  for (int k = 0; k < ns; ++k) {
    const double t0 = cpu_s();
    pm::test::stock_insert(stock, filtered[static_cast<std::size_t>(k)], cfg.mapper.max_range_m);
    stock_cpu += cpu_s() - t0;
    ours_same += integ_s[static_cast<std::size_t>(k)];
  }

  // Cloud-to-published-map: the node in real time.
  const PacedResult paced = run_paced(rec, robot, paced_cfg);

  std::printf("%-7s %5.2f %6.0f %7.2f %7.2f %7.2f %6.2f%s %10.3g %8.1f%% | %8.1f %7.1fx | %6.1f %6.1f %6.1f %5.1f %4zu %4llu %5.1f%% | %7zu\n",
              scene, res, points / n, 1e3 * filter_cpu / n, 1e3 * integ_cpu / n, 1e3 * full_cpu, inc_ms,
              same_stream ? " " : "!", points / (filter_cpu + integ_cpu), 100.0 * cpu_share,
              1e3 * stock_cpu / std::max(1, ns), stock_cpu / std::max(1e-12, ours_same), 1e3 * quantile(paced.c2m_s, 0.5),
              1e3 * quantile(paced.c2m_s, 0.95), 1e3 * quantile(paced.c2m_s, 1.0), 1e3 * quantile(paced.path_cpu_s, 0.5),
              paced.c2m_s.size(),
              static_cast<unsigned long long>(paced.busy), 100.0 * paced.cpu_share, full.size());
  if (!same_stream) std::printf("  ! the incremental stream differs from the full one\n");
  if (paced.processed + paced.dropped != rec.clouds.size()) std::printf("  ! clouds unaccounted for\n");
  std::fflush(stdout);
}

/// The PCL filters on: filter and integrate CPU per cloud and the occupied voxels against the
/// run without them (agreement = |both| / |without|, extra = |with only| / |without|).
void run_pcl(const char* scene, const Recorded& rec, const porter::RobotModel& robot, pm::app::MapperConfig cfg,
             const char* variant, double leaf_m, int mean_k) {
  cfg.mapper.recenter_distance_m = 100.0;
  pm::Mapper base(robot, cfg.mapper);
  cfg.mapper.voxel_grid_leaf_m = leaf_m;
  cfg.mapper.outlier_mean_k = mean_k;
  pm::Mapper with(robot, cfg.mapper);
  pm::StateBuffer states;
  double filter_cpu = 0.0, integ_cpu = 0.0, removed = 0.0;
  for (std::size_t k = 0; k < rec.clouds.size(); ++k) {
    for (const auto& [t, c] : rec.states[k]) states.add(t, c);
    base.process(rec.clouds[k], states);
    pm::FilteredCloud f;
    const double t0 = cpu_s();
    const pm::FilterStats fs = with.filter(rec.clouds[k], states, f);
    const double t1 = cpu_s();
    with.integrate(f);
    integ_cpu += cpu_s() - t1;
    filter_cpu += t1 - t0;
    removed += static_cast<double>(fs.voxel_grid_removed + fs.outliers);
  }
  std::int64_t without = 0, both = 0, only_with = 0;
  base.map().for_each_known([&](const Eigen::Vector3i& key, float v) {
    const bool a = base.map().occupied(v);
    const bool b = with.map().state(key) == pm::VoxelState::occupied;
    without += a;
    both += a && b;
  });
  with.map().for_each_known([&](const Eigen::Vector3i& key, float v) {
    only_with += with.map().occupied(v) && base.map().state(key) != pm::VoxelState::occupied;
  });
  const double n = static_cast<double>(rec.clouds.size());
  std::printf("%-7s %-22s %8.2f %8.2f %9.0f %8.2f%% %7.2f%%\n", scene, variant, 1e3 * filter_cpu / n, 1e3 * integ_cpu / n,
              removed / n, 100.0 * both / std::max<std::int64_t>(1, without), 100.0 * only_with / std::max<std::int64_t>(1, without));
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  int clouds = 30, stock_clouds = 10;
  double publish_hz = 0.0;
  bool pcl = false;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--clouds") && i + 1 < argc) {
      clouds = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--publish-hz") && i + 1 < argc) {
      publish_hz = std::atof(argv[++i]);
    } else if (!std::strcmp(argv[i], "--pcl")) {
      pcl = true;
    } else if (!std::strcmp(argv[i], "--stock-clouds") && i + 1 < argc) {
      stock_clouds = std::atoi(argv[++i]);
    } else {
      std::fprintf(stderr, "usage: porter-bench-mapper [--clouds N] [--stock-clouds M] [--publish-hz F] [--pcl]\n");
      return 2;
    }
  }
  pm::app::MapperConfig cfg = pm::test::shipped_config();
  if (publish_hz > 0.0) cfg.publish_rate_hz = publish_hz;
  const porter::RobotModel robot = pm::test::robot_with("long_bar");
  const double T = clouds * 0.1;
  const porter::Scene forest = porter::load_scene(pm::test::config_path("scenes/forest.yaml"));
  const double lane = pm::test::clear_lane(forest, 0.8 * T + 0.5, 0.4);
  std::printf("recording %d clouds per scene...\n", clouds);
  std::fflush(stdout);
  const Recorded room_rec = record(robot, room(6, 4, 3),
                                   {Waypoint{0.0, pm::test::config_at(-1.0, -0.5, 0.0)},
                                    Waypoint{T, pm::test::config_at(-1.0 + 0.5 * T, -0.5, 0.5)}},
                                   cfg.mapper.T_B_S, clouds);
  const Recorded forest_rec = record(robot, forest.obstacles,
                                     {Waypoint{0.0, pm::test::config_at(0.0, lane, 0.0)},
                                      Waypoint{T, pm::test::config_at(0.8 * T, lane, 0.0)}},
                                     cfg.mapper.T_B_S, clouds);
  if (pcl) {
    std::printf("PCL filters at 0.05 m: CPU ms per cloud, points removed per cloud, occupied voxels vs without\n");
    std::printf("scene   variant                  filter    integ   removed    agree   extra\n");
    for (const Recorded* r : {&room_rec, &forest_rec}) {
      const char* name = r == &room_rec ? "room" : "forest";
      run_pcl(name, *r, robot, cfg, "voxel grid 0.05", 0.05, 0);
      run_pcl(name, *r, robot, cfg, "outliers k=8 x1.0", 0.0, 8);
    }
    return 0;
  }
  std::printf("maps at %.1f Hz; CPU ms per cloud (filter, integ) and per map (full, inc); c2m in ms\n", cfg.publish_rate_hz);
  std::printf("scene     res    pts  filter   integ    full    inc  mapper pts/s  CPU@200k |  stock ms  speedup |  c2m med    p95    max   cpu maps busy   CPU | stream B\n");
  for (double res : {0.1, 0.05}) {
    run("room", room_rec, robot, cfg, res, stock_clouds);
    run("forest", forest_rec, robot, cfg, res, stock_clouds);
  }
  return 0;
}
