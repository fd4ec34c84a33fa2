// porter-bench-map-update: how long porter-planner takes from a MAP_OCTOMAP to its decision
// about the trajectory it executes, stage by stage, on the maps of a recorded run.
//
// For every MAP_OCTOMAP of the log, in order, it does what porter-planner's worker does with it:
// decode the OctoMap stream, build the planning grid (bounds around the tree, the robot and the
// goal; the unknown-below fill), hand it to the pipeline (kernel map full or incremental, the
// front-end's heuristic grid), and check the rest of the trajectory executing at the map's log
// time against it (the newest TRAJECTORY of the log, first_collision_s). It prints each map's
// times and a summary per stage (median, p90, max) and the count of full and incremental updates.
//
// usage: porter-bench-map-update --log LOG [--config PLANNER_YAML] [--payload ID] [--quiet]
// exit codes: 0 done, 2 bad arguments, 3 unreadable log or config.

#include <octomap/OcTree.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "planner_config.hpp"
#include "planner_messages.hpp"
#include "planner_node.hpp"
#include "porter/channels.hpp"
#include "porter/msg/trajectory_msg.hpp"
#include "porter/pipeline/config_dir.hpp"
#include "porter/planner_daemon/replan.hpp"

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

template <class Msg>
bool decode(const lcm::LogEvent& e, Msg* m) {
  return m->decode(e.data, 0, static_cast<int>(e.datalen)) >= 0;
}

struct Row {
  double decode_ms = 0, grid_ms = 0, set_ms = 0, check_ms = 0;
  double total() const { return decode_ms + grid_ms + set_ms + check_ms; }
};

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t i = std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5));
  return v[i];
}

void summary(const char* name, const std::vector<Row>& rows, double Row::*field) {
  std::vector<double> v;
  for (const Row& r : rows) v.push_back(r.*field);
  std::printf("  %-10s %9.1f %9.1f %9.1f\n", name, quantile(v, 0.5), quantile(v, 0.9),
              v.empty() ? 0.0 : *std::max_element(v.begin(), v.end()));
}

}  // namespace

int main(int argc, char** argv) {
  std::string log_path, config_path, payload_id;
  bool quiet = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "porter-bench-map-update: %s needs a value\n", a.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--log") log_path = value();
    else if (a == "--config") config_path = value();
    else if (a == "--payload") payload_id = value();
    else if (a == "--quiet") quiet = true;
    else {
      std::fprintf(stderr, "usage: porter-bench-map-update --log LOG [--config PLANNER_YAML] [--payload ID] [--quiet]\n");
      return 2;
    }
  }
  if (log_path.empty()) {
    std::fprintf(stderr, "porter-bench-map-update: --log is required\n");
    return 2;
  }
  if (config_path.empty()) config_path = porter::pipeline::find_config_dir() + "/planner/porter_planner.yaml";

  porter::planner_app::PlannerConfig config;
  std::unique_ptr<porter::pipeline::Planner> planner;
  try {
    config = porter::planner_app::load_planner_config(config_path);
    if (payload_id.empty()) payload_id = config.payload_id;
    planner = porter::planner_app::make_planner(config, payload_id);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "porter-bench-map-update: %s\n", e.what());
    return 3;
  }
  lcm::LogFile log(log_path, "r");
  if (!log.good()) {
    std::fprintf(stderr, "porter-bench-map-update: cannot read %s\n", log_path.c_str());
    return 3;
  }

  std::optional<Eigen::Vector2d> goal_xy;
  std::optional<porter::StampedTrajectory> executing;
  std::vector<Row> rows;
  int full = 0, incremental = 0, refused = 0;
  if (!quiet) std::printf("map    dims            decode_ms  grid_ms  set_ms  check_ms  update\n");
  for (const lcm::LogEvent* e = log.readNextEvent(); e != nullptr; e = log.readNextEvent()) {
    if (e->channel == porter::channels::kPlanGoal.name()) {
      porter::plan_goal_t m;
      if (decode(*e, &m)) goal_xy = Eigen::Vector2d(m.x_m, m.y_m);
      continue;
    }
    if (e->channel == porter::channels::kTrajectory.name()) {
      porter::minco_trajectory_t m;
      if (!decode(*e, &m)) continue;
      auto r = porter::from_msg(m);
      if (r.value) executing = *r.value;
      continue;
    }
    if (e->channel != porter::channels::kMapOctomap.name()) continue;
    porter::octomap_t m;
    if (!decode(*e, &m)) continue;
    Row row;
    auto t0 = Clock::now();
    const porter::planner_app::TreeConversion t = porter::planner_app::decode_octomap(m, config.frame_id, config.map);
    row.decode_ms = ms_since(t0);
    if (!t.tree) {
      ++refused;
      continue;
    }
    const Eigen::Vector2d robot(m.robot_x_m, m.robot_y_m);
    std::vector<Eigen::Vector2d> keep{robot};
    if (goal_xy) keep.push_back(*goal_xy);
    t0 = Clock::now();
    const porter::planner_app::GridConversion g = porter::planner_app::to_grid(*t.tree, keep, config.map, &robot);
    row.grid_ms = ms_since(t0);
    if (!g.grid) {
      ++refused;
      continue;
    }
    t0 = Clock::now();
    const porter::pipeline::MapUpdate u = planner->set_map(*g.grid);
    row.set_ms = ms_since(t0);
    if (!u.ok) {
      ++refused;
      continue;
    }
    (u.incremental ? incremental : full)++;
    if (executing) {
      const double t_from = std::clamp(static_cast<double>(e->timestamp - executing->start_utime) * 1e-6, 0.0,
                                       executing->trajectory.total_duration_s());
      t0 = Clock::now();
      (void)porter::planner_daemon::first_collision_s(planner->kernel_checker(), executing->trajectory, t_from,
                                                      config.loop.collision_step_s);
      row.check_ms = ms_since(t0);
    }
    rows.push_back(row);
    if (!quiet) {
      const auto& d = g.grid->dims();
      std::printf("%4lld  %4dx%4dx%3d  %9.1f %8.1f %7.1f %9.1f  %s (%lld voxels changed)\n",
                  static_cast<long long>(m.map_id), d.x(), d.y(), d.z(), row.decode_ms, row.grid_ms, row.set_ms,
                  row.check_ms, u.incremental ? "incremental" : "full", static_cast<long long>(u.changed_voxels));
    }
  }
  std::printf("%zu maps (%d full, %d incremental updates, %d refused) from %s\n", rows.size(), full, incremental,
              refused, log_path.c_str());
  std::printf("  stage ms      median       p90       max\n");
  summary("decode", rows, &Row::decode_ms);
  summary("grid", rows, &Row::grid_ms);
  summary("set_map", rows, &Row::set_ms);
  summary("check", rows, &Row::check_ms);
  std::vector<double> tot;
  for (const Row& r : rows) tot.push_back(r.total());
  std::printf("  %-10s %9.1f %9.1f %9.1f\n", "total", quantile(tot, 0.5), quantile(tot, 0.9),
              tot.empty() ? 0.0 : *std::max_element(tot.begin(), tot.end()));
  return 0;
}
