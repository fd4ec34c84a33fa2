// porter-bench-mapper: the mapper against stock OctoMap on the same clouds.
//
//   porter-bench-mapper [--clouds N] [--stock-clouds M] [--pcl]
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
//   map      writing the OctoMap binary stream of the whole window — CPU ms per map
//   mapper pts/s   points per CPU second of filter + integrate
//   CPU@200k       share of one core for 200,000 points/s: 10 clouds/s of filter + integrate,
//                  plus 2 maps/s (publish_rate_hz)
//   stock    octomap::OcTree::insertPointCloud(filtered points, origin, max_range) — CPU ms per
//            cloud on the first --stock-clouds clouds; x = stock / (mapper integrate) on those
//   c2m      cloud-to-map: wall time from the LIDAR_POINTS message to an encoded MAP_OCTOMAP
//            message for the cloud that makes a map due (conversion, filter, integrate, stream,
//            LCM encoding) — median and max over the clouds
#include <time.h>

#include <algorithm>
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

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

void run(const char* scene, const Recorded& rec, const porter::RobotModel& robot, pm::app::MapperConfig cfg,
         double res, int stock_clouds) {
  const double scale = 0.05 / res;
  cfg.mapper.map.resolution_m = res;
  cfg.mapper.map.dims = (cfg.mapper.map.dims.cast<double>() * scale).array().round().cast<int>().matrix();
  cfg.mapper.recenter_distance_m = 100.0;

  // Mapper, phase by phase.
  pm::Mapper mapper(robot, cfg.mapper);
  pm::StateBuffer states;
  std::vector<pm::FilteredCloud> filtered(rec.clouds.size());
  std::vector<double> integ_s(rec.clouds.size());
  double filter_cpu = 0.0, integ_cpu = 0.0, points = 0.0;
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
  }
  std::vector<std::uint8_t> stream;
  double map_cpu = 0.0;
  for (int i = 0; i < 3; ++i) {
    const double t0 = cpu_s();
    pm::write_octomap_binary(mapper.map(), stream);
    map_cpu += (cpu_s() - t0) / 3.0;
  }
  const double n = static_cast<double>(rec.clouds.size());
  const double cpu_share = 10.0 * (filter_cpu + integ_cpu) / n + cfg.publish_rate_hz * map_cpu;

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

  // Cloud-to-map through the process's node, a map due on every cloud.
  cfg.publish_rate_hz = 20.0;
  pm::app::MapperNode node(cfg, robot);
  std::vector<double> c2m;
  std::int64_t fake_ns = 0;
  porter::octomap_t map_msg;
  std::vector<std::uint8_t> buf;
  for (std::size_t k = 0; k < rec.clouds.size(); ++k) {
    for (const auto& [t, c] : rec.states[k]) {
      porter::robot_state_t s{};
      s.utime = t;
      s.x_m = c.base.x_m;
      s.y_m = c.base.y_m;
      s.yaw_rad = c.base.yaw_rad;
      s.num_joints = 6;
      s.q_rad.assign(c.q_rad.data(), c.q_rad.data() + 6);
      node.on_state(s);
    }
    porter::point_cloud_t msg{};
    const pm::SensorCloud& c = rec.clouds[k];
    msg.utime = c.utime;
    msg.frame_id = cfg.cloud_frame_id;
    msg.scan_id = static_cast<std::int64_t>(k);
    msg.num_points = static_cast<std::int32_t>(c.size());
    msg.x_m = c.x_m;
    msg.y_m = c.y_m;
    msg.z_m = c.z_m;
    msg.intensity.assign(c.size(), 0.0f);
    msg.time_offset_ns = c.time_offset_ns;
    msg.line.assign(c.size(), 0);
    msg.tag.assign(c.size(), 0);
    fake_ns += 100'000'000;
    const double t0 = wall_s();
    node.on_cloud(msg, fake_ns);
    pm::app::StepResult r;
    if (!node.step(fake_ns, 0, r) || !r.map_due) continue;
    node.make_map(map_msg);
    buf.resize(static_cast<std::size_t>(map_msg.getEncodedSize()));
    map_msg.encode(buf.data(), 0, static_cast<int>(buf.size()));
    c2m.push_back(wall_s() - t0);
  }

  std::printf("%-7s %5.2f %6.0f %7.2f %7.2f %7.2f %10.3g %8.1f%% | %9.1f %7.1fx | %6.1f %6.1f | %7zu\n", scene, res,
              points / n, 1e3 * filter_cpu / n, 1e3 * integ_cpu / n, 1e3 * map_cpu, points / (filter_cpu + integ_cpu),
              100.0 * cpu_share, 1e3 * stock_cpu / std::max(1, ns), stock_cpu / std::max(1e-12, ours_same),
              1e3 * median(c2m), 1e3 * (c2m.empty() ? 0.0 : *std::max_element(c2m.begin(), c2m.end())), stream.size());
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
  bool pcl = false;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--clouds") && i + 1 < argc) {
      clouds = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--pcl")) {
      pcl = true;
    } else if (!std::strcmp(argv[i], "--stock-clouds") && i + 1 < argc) {
      stock_clouds = std::atoi(argv[++i]);
    } else {
      std::fprintf(stderr, "usage: porter-bench-mapper [--clouds N] [--stock-clouds M] [--pcl]\n");
      return 2;
    }
  }
  const pm::app::MapperConfig cfg = pm::test::shipped_config();
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
  std::printf("scene     res    pts  filter   integ     map  mapper pts/s  CPU@200k |  stock ms   speedup |  c2m med/max ms | stream B\n");
  for (double res : {0.1, 0.05}) {
    run("room", room_rec, robot, cfg, res, stock_clouds);
    run("forest", forest_rec, robot, cfg, res, stock_clouds);
  }
  return 0;
}
