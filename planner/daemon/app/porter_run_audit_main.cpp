// porter-run-audit: what the planner knew against what was there. Reads a run's LCM log
// (scripts/launch's run.lcmlog), turns every MAP_OCTOMAP into the planning grid exactly as
// porter-planner does, and compares it with the scene's exact voxels on the same grid:
//   - per map: for each obstacle of the scene, how many of its voxels the map holds as occupied,
//     free (seen through: rays crossed them) and unknown (never seen);
//   - per TRAJECTORY: the first collision of the kernel check on the map the planner had when
//     it was published (the newest map before it), on every later map while it executed (what
//     the daemon's check saw), and on the scene's voxels; its exact clearance (FCL, the
//     validator); and where the closest obstacle's voxels are missing from the map there;
//   - tracking: the simulator's truth (SIM_TRUTH) against the trajectory executing at that time,
//     base along-track / cross-track and the largest joint error, and porter-state's estimate
//     (ROBOT_STATE) against the truth.
//
// usage: porter-run-audit --log LOG --scene SCENE [--config PLANNER_YAML] [--payload ID]
//                         [--unknown-as-occupied R]
//        porter-run-audit --log LOG --compare OTHER_LOG
//   --compare  the maps of two runs (a recording and its replay): for every pair of maps made
//              from the same newest scan (octomap_t.utime), whether the streams are
//              byte-identical and how their occupied voxels agree (shared / only in LOG / only
//              in OTHER_LOG); the last line sums the pairs
//   --config   porter-planner's config (default: planner/porter_planner.yaml of the config
//              directory porter-plan finds)
//   --payload  the payload planned with (default: the config's)
//   --unknown-as-occupied R  also check each trajectory on its map with unknown voxels within
//              R m of the map's robot position (above ground_m) counted as occupied
// exit codes: 0 done, 2 bad arguments, 3 unreadable log, scene or config.

#include <octomap/OcTree.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "flat_trajectory.hpp"
#include "planner_config.hpp"
#include "planner_messages.hpp"
#include "planner_node.hpp"
#include "porter/channels.hpp"
#include "porter/core/kinematics.hpp"
#include "porter/core/payload_loader.hpp"
#include "porter/core/robot_loader.hpp"
#include "porter/core/scene_loader.hpp"
#include "porter/core/scene_voxelizer.hpp"
#include "porter/msg/trajectory_msg.hpp"
#include "porter/pipeline/config_dir.hpp"
#include "porter/planner_daemon/replan.hpp"
#include "porter/validation/validator.hpp"

namespace {

using porter::OccupancyGrid;

struct LoggedMap {
  std::int64_t log_utime = 0;
  std::int64_t map_id = 0;
  std::int64_t stamp_utime = 0;
  Eigen::Vector2d robot_xy;
  std::shared_ptr<const octomap::OcTree> tree;
};

struct LoggedTrajectory {
  std::int64_t log_utime = 0;
  porter::StampedTrajectory t;
};

template <class Msg>
bool decode(const lcm::LogEvent& e, Msg* m) {
  return m->decode(e.data, 0, static_cast<int>(e.datalen)) >= 0;
}

/// The scene's obstacles voxelized one by one on the grid's geometry.
std::vector<OccupancyGrid> obstacle_grids(const porter::Scene& scene, const OccupancyGrid& like) {
  std::vector<OccupancyGrid> out;
  for (const auto& o : scene.obstacles) {
    OccupancyGrid g(like.origin_W(), like.resolution_m(), like.dims());
    porter::voxelize_shape(o, g);
    out.push_back(std::move(g));
  }
  return out;
}

enum class Seen { kOccupied, kFree, kUnknown };

Seen seen(const octomap::OcTree& tree, const Eigen::Vector3d& p) {
  const octomap::OcTreeNode* n = tree.search(p.x(), p.y(), p.z());
  if (n == nullptr) return Seen::kUnknown;
  return tree.isNodeOccupied(n) ? Seen::kOccupied : Seen::kFree;
}

struct Counts {
  long occupied = 0, free = 0, unknown = 0, map_occupied = 0;
};

Counts count(const OccupancyGrid& obstacle, const OccupancyGrid& map, const octomap::OcTree& tree,
             const Eigen::AlignedBox3d& region) {
  Counts c;
  const auto& n = obstacle.dims();
  for (int z = 0; z < n.z(); ++z)
    for (int y = 0; y < n.y(); ++y)
      for (int x = 0; x < n.x(); ++x) {
        if (!obstacle.occupied(x, y, z)) continue;
        const Eigen::Vector3d p = obstacle.voxel_center_W(x, y, z);
        if (!region.isEmpty() && !region.contains(p)) continue;
        switch (seen(tree, p)) {
          case Seen::kOccupied: ++c.occupied; break;
          case Seen::kFree: ++c.free; break;
          case Seen::kUnknown: ++c.unknown; break;
        }
        if (map.occupied(x, y, z)) ++c.map_occupied;
      }
  return c;
}

std::string when(const std::optional<double>& t) {
  if (!t) return "free";
  char b[32];
  std::snprintf(b, sizeof b, "t=%.2f s", *t);
  return b;
}

std::vector<std::pair<std::int64_t, std::vector<std::uint8_t>>> map_streams(const std::string& path, bool* ok) {
  std::vector<std::pair<std::int64_t, std::vector<std::uint8_t>>> out;
  lcm::LogFile log(path, "r");
  *ok = log.good();
  if (!*ok) return out;
  for (const lcm::LogEvent* e = log.readNextEvent(); e != nullptr; e = log.readNextEvent()) {
    if (e->channel != porter::channels::kMapOctomap.name()) continue;
    porter::octomap_t m;
    if (decode(*e, &m)) out.emplace_back(m.utime, m.data);
  }
  return out;
}

/// Keys of the occupied leaf voxels (finest level) of an OctoMap binary stream.
std::set<octomap::OcTreeKey, bool (*)(const octomap::OcTreeKey&, const octomap::OcTreeKey&)> occupied_keys(
    const std::vector<std::uint8_t>& data, double resolution_m) {
  auto less = +[](const octomap::OcTreeKey& a, const octomap::OcTreeKey& b) {
    return std::tie(a[0], a[1], a[2]) < std::tie(b[0], b[1], b[2]);
  };
  std::set<octomap::OcTreeKey, bool (*)(const octomap::OcTreeKey&, const octomap::OcTreeKey&)> keys(less);
  octomap::OcTree tree(resolution_m);
  std::istringstream stream(std::string(reinterpret_cast<const char*>(data.data()), data.size()));
  tree.readBinaryData(stream);
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it) {
    if (!tree.isNodeOccupied(*it)) continue;
    const int n = 1 << (tree.getTreeDepth() - it.getDepth());
    const octomap::OcTreeKey k0 = it.getIndexKey();
    for (int x = 0; x < n; ++x)
      for (int y = 0; y < n; ++y)
        for (int z = 0; z < n; ++z)
          keys.insert(octomap::OcTreeKey(static_cast<octomap::key_type>(k0[0] + x), static_cast<octomap::key_type>(k0[1] + y),
                                         static_cast<octomap::key_type>(k0[2] + z)));
  }
  return keys;
}

int compare_logs(const std::string& a_path, const std::string& b_path, double resolution_m) {
  bool ok_a = false, ok_b = false;
  const auto a = map_streams(a_path, &ok_a), b = map_streams(b_path, &ok_b);
  if (!ok_a || !ok_b) {
    std::fprintf(stderr, "porter-run-audit: cannot read %s\n", (!ok_a ? a_path : b_path).c_str());
    return 3;
  }
  std::map<std::int64_t, const std::vector<std::uint8_t>*> by_utime;
  for (const auto& m : b) by_utime[m.first] = &m.second;
  long pairs = 0, identical = 0, shared = 0, only_a = 0, only_b = 0;
  for (const auto& m : a) {
    auto it = by_utime.find(m.first);
    if (it == by_utime.end()) continue;
    ++pairs;
    const bool same = m.second == *it->second;
    identical += same ? 1 : 0;
    const auto ka = occupied_keys(m.second, resolution_m), kb = occupied_keys(*it->second, resolution_m);
    long s = 0;
    for (const auto& k : ka) s += kb.count(k) ? 1 : 0;
    const long oa = static_cast<long>(ka.size()) - s, ob = static_cast<long>(kb.size()) - s;
    shared += s, only_a += oa, only_b += ob;
    std::printf("map of scan %lld: %s; occupied voxels shared %ld, only in the first %ld, only in the second %ld\n",
                static_cast<long long>(m.first), same ? "byte-identical" : "differs", s, oa, ob);
  }
  std::printf("maps: %zu and %zu; pairs of the same newest scan %ld, byte-identical %ld; occupied voxels shared %ld, "
              "only in the first %ld, only in the second %ld\n",
              a.size(), b.size(), pairs, identical, shared, only_a, only_b);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::string log_path, scene_path, config_path, payload_id;
  double unknown_radius_m = -1.0;
  std::string compare_path;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i], v = argv[i + 1];
    if (a == "--log") log_path = v;
    else if (a == "--scene") scene_path = v;
    else if (a == "--config") config_path = v;
    else if (a == "--payload") payload_id = v;
    else if (a == "--unknown-as-occupied") unknown_radius_m = std::atof(v.c_str());
    else if (a == "--compare") compare_path = v;
    else log_path.clear(), i = argc;
  }
  if (config_path.empty()) config_path = porter::pipeline::find_config_dir() + "/planner/porter_planner.yaml";
  if (!log_path.empty() && !compare_path.empty() && argc % 2 == 1) {
    try {
      return compare_logs(log_path, compare_path, porter::planner_app::load_planner_config(config_path).map.resolution_m);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "porter-run-audit: %s\n", e.what());
      return 3;
    }
  }
  if (log_path.empty() || scene_path.empty() || argc % 2 == 0) {
    std::fprintf(stderr, "usage: porter-run-audit --log LOG --scene SCENE [--config PLANNER_YAML] [--payload ID] "
                         "[--unknown-as-occupied R]\n       porter-run-audit --log LOG --compare OTHER_LOG\n");
    return 2;
  }
  porter::planner_app::PlannerConfig config;
  porter::Scene scene;
  porter::RobotModel robot;
  porter::Payload payload;
  std::unique_ptr<porter::pipeline::Planner> planner;
  try {
    config = porter::planner_app::load_planner_config(config_path);
    if (payload_id.empty()) payload_id = config.payload_id;
    scene = porter::load_scene(scene_path);
    robot = porter::load_robot_model(config.robot_file);
    payload = porter::load_payload(config.payloads.at(payload_id));
    planner = porter::planner_app::make_planner(config, payload_id);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "porter-run-audit: %s\n", e.what());
    return 3;
  }
  lcm::LogFile log(log_path, "r");
  if (!log.good()) {
    std::fprintf(stderr, "porter-run-audit: cannot read %s\n", log_path.c_str());
    return 3;
  }
  std::vector<LoggedMap> maps;
  std::vector<LoggedTrajectory> trajectories;
  std::optional<Eigen::Vector2d> goal_xy;
  std::vector<porter::robot_state_t> truth, estimate;
  for (const lcm::LogEvent* e = log.readNextEvent(); e != nullptr; e = log.readNextEvent()) {
    if (e->channel == porter::channels::kMapOctomap.name()) {
      porter::octomap_t m;
      if (!decode(*e, &m)) continue;
      auto t = porter::planner_app::decode_octomap(m, config.frame_id, config.map);
      if (!t.tree) continue;
      maps.push_back({e->timestamp, m.map_id, m.utime, Eigen::Vector2d(m.robot_x_m, m.robot_y_m), t.tree});
    } else if (e->channel == porter::channels::kTrajectory.name()) {
      porter::minco_trajectory_t m;
      if (!decode(*e, &m)) continue;
      auto r = porter::from_msg(m);
      if (r.value) trajectories.push_back({e->timestamp, *r.value});
    } else if (e->channel == porter::channels::kSimTruth.name() || e->channel == porter::channels::kRobotState.name()) {
      porter::robot_state_t m;
      if (decode(*e, &m) && m.num_joints == porter::kNumArmJoints)
        (e->channel == porter::channels::kSimTruth.name() ? truth : estimate).push_back(m);
    } else if (e->channel == porter::channels::kPlanGoal.name() && !goal_xy) {
      porter::plan_goal_t m;
      if (decode(*e, &m)) goal_xy = Eigen::Vector2d(m.x_m, m.y_m);
    }
  }
  std::printf("log %s: %zu maps, %zu trajectories\n", log_path.c_str(), maps.size(), trajectories.size());
  if (maps.empty()) return 0;

  auto grid_of = [&](const LoggedMap& m) {
    std::vector<Eigen::Vector2d> keep{m.robot_xy};
    if (goal_xy) keep.push_back(*goal_xy);
    return porter::planner_app::to_grid(*m.tree, keep, config.map, &m.robot_xy).grid;
  };

  // Per map: each obstacle's voxels as the map holds them.
  std::printf("\nper map (obstacle: occupied/free/unknown of its voxels inside the grid):\n");
  const std::int64_t t0 = maps.front().log_utime;
  for (const auto& m : maps) {
    const auto g = grid_of(m);
    if (!g) continue;
    const auto obstacles = obstacle_grids(scene, *g);
    std::printf("map %3lld at %6.2f s, robot (%.2f, %.2f), %lld occupied:", static_cast<long long>(m.map_id),
                static_cast<double>(m.log_utime - t0) * 1e-6, m.robot_xy.x(), m.robot_xy.y(),
                static_cast<long long>(g->count()));
    Eigen::AlignedBox3d occupied_box;
    long outside = 0;
    OccupancyGrid all(g->origin_W(), g->resolution_m(), g->dims());
    for (const auto& o : scene.obstacles) porter::voxelize_shape(o, all);
    const auto& d = g->dims();
    for (int z = 0; z < d.z(); ++z)
      for (int y = 0; y < d.y(); ++y)
        for (int x = 0; x < d.x(); ++x)
          if (g->occupied(x, y, z)) {
            occupied_box.extend(g->voxel_center_W(x, y, z));
            // Occupied where no obstacle is within one voxel.
            bool near = false;
            for (int k = -1; k <= 1 && !near; ++k)
              for (int j = -1; j <= 1 && !near; ++j)
                for (int i = -1; i <= 1 && !near; ++i) near = all.occupied(x + i, y + j, z + k);
            outside += near ? 0 : 1;
          }
    if (getenv("AUDIT_DEBUG") && m.map_id == std::atoi(getenv("AUDIT_DEBUG"))) {
      const double xs = std::atof(getenv("AUDIT_X"));
      std::printf("\nslice x=%.3f (rows z from 1.6 down, columns y -1..1): # occupied, . free, space unknown, F unknown planned as occupied\n", xs);
      for (double z = 1.575; z > 0.5; z -= 0.05) {
        std::printf("z %.3f |", z);
        for (double y = -0.975; y < 1.0; y += 0.05) {
          const octomap::OcTreeNode* nd = m.tree->search(xs, y, z);
          const bool filled = g->occupied_at(Eigen::Vector3d(xs, y, z));
          std::printf("%c", nd == nullptr ? (filled ? 'F' : ' ') : m.tree->isNodeOccupied(nd) ? '#' : '.');
        }
        std::printf("|\n");
      }
    }
    if (!occupied_box.isEmpty())
      std::printf(" in [%.2f, %.2f] x [%.2f, %.2f] x [%.2f, %.2f], %ld away from every obstacle;",
                  occupied_box.min().x(), occupied_box.max().x(), occupied_box.min().y(), occupied_box.max().y(),
                  occupied_box.min().z(), occupied_box.max().z(), outside);
    for (std::size_t i = 0; i < obstacles.size(); ++i) {
      const Counts c = count(obstacles[i], *g, *m.tree, {});
      std::printf("  %s %ld/%ld/%ld", scene.obstacles[i].name.c_str(), c.occupied, c.free, c.unknown);
    }
    std::printf("\n");
  }

  // Per trajectory.
  for (const auto& tr : trajectories) {
    const auto& traj = tr.t.trajectory;
    std::printf("\ntrajectory plan %lld, published at %.2f s, %.2f s long, start %.2f s\n",
                static_cast<long long>(tr.t.plan_id), static_cast<double>(tr.log_utime - t0) * 1e-6,
                traj.total_duration_s(), static_cast<double>(tr.t.start_utime - t0) * 1e-6);
    const auto report = porter::validation::validate_trajectory(robot, payload, scene,
                                                                porter::planner_app::to_flat(traj));
    const porter::validation::ObstacleClearance* worst = nullptr;
    for (const auto& o : report.clearances)
      if (!worst || o.min_m < worst->min_m) worst = &o;
    if (worst)
      std::printf("  exact: min clearance %.3f m to %s by %s at t=%.2f s%s\n", worst->min_m, worst->obstacle.c_str(),
                  worst->body.c_str(), worst->t_s, report.collision.found ? " (COLLISION)" : "");
    const LoggedMap* before = nullptr;
    for (const auto& m : maps)
      if (m.log_utime <= tr.log_utime) before = &m;
    if (!before) {
      std::printf("  no map before it\n");
      continue;
    }
    const auto g = grid_of(*before);
    if (!g) continue;
    planner->set_map(*g);
    std::printf("  kernel check on map %lld (its newest before): first collision %s\n",
                static_cast<long long>(before->map_id),
                when(porter::planner_daemon::first_collision_s(planner->kernel_checker(), traj, 0.0, 0.02)).c_str());
    OccupancyGrid truth(g->origin_W(), g->resolution_m(), g->dims());
    for (const auto& o : scene.obstacles) porter::voxelize_shape(o, truth);
    planner->set_map(truth);
    std::printf("  kernel check on the scene's voxels (same grid): first collision %s\n",
                when(porter::planner_daemon::first_collision_s(planner->kernel_checker(), traj, 0.0, 0.02)).c_str());
    if (unknown_radius_m > 0.0) {
      OccupancyGrid cautious = *g;
      const auto& n = g->dims();
      for (int z = 0; z < n.z(); ++z)
        for (int y = 0; y < n.y(); ++y)
          for (int x = 0; x < n.x(); ++x) {
            const Eigen::Vector3d p = g->voxel_center_W(x, y, z);
            if ((p.head<2>() - before->robot_xy).norm() > unknown_radius_m || p.z() < 0.1) continue;
            if (seen(*before->tree, p) == Seen::kUnknown) cautious.set(x, y, z);
          }
      planner->set_map(cautious);
      std::printf("  kernel check with unknown within %.1f m occupied (%lld voxels): first collision %s\n",
                  unknown_radius_m, static_cast<long long>(cautious.count()),
                  when(porter::planner_daemon::first_collision_s(planner->kernel_checker(), traj, 0.0, 0.02)).c_str());
    }
    // Unknown voxels next to occupied ones (up to k voxels away) counted as occupied.
    for (int k = 1; k <= 4; ++k) {
      OccupancyGrid grown = *g;
      const auto& n = g->dims();
      for (int z = 0; z < n.z(); ++z)
        for (int y = 0; y < n.y(); ++y)
          for (int x = 0; x < n.x(); ++x) {
            if (!g->occupied(x, y, z)) continue;
            for (int dz = -k; dz <= k; ++dz)
              for (int dy = -k; dy <= k; ++dy)
                for (int dx = -k; dx <= k; ++dx) {
                  if (!g->in_bounds(x + dx, y + dy, z + dz) || grown.occupied(x + dx, y + dy, z + dz)) continue;
                  if (seen(*before->tree, g->voxel_center_W(x + dx, y + dy, z + dz)) == Seen::kUnknown)
                    grown.set(x + dx, y + dy, z + dz);
                }
          }
      planner->set_map(grown);
      std::printf("  kernel check with unknown voxels within %d of an occupied one occupied (%lld voxels): first collision %s\n",
                  k, static_cast<long long>(grown.count()),
                  when(porter::planner_daemon::first_collision_s(planner->kernel_checker(), traj, 0.0, 0.02)).c_str());
    }
    // Later maps while it executed (what porter-planner's check saw).
    for (const auto& m : maps) {
      if (m.log_utime <= tr.log_utime) continue;
      const double t_now = static_cast<double>(m.log_utime - tr.t.start_utime) * 1e-6;
      if (t_now > traj.total_duration_s()) break;
      const auto gm = grid_of(m);
      if (!gm) continue;
      planner->set_map(*gm);
      const auto hit = porter::planner_daemon::first_collision_s(planner->kernel_checker(), traj, std::max(0.0, t_now), 0.02);
      std::printf("  map %lld at trajectory t=%.2f s: first collision ahead %s\n", static_cast<long long>(m.map_id),
                  t_now, when(hit).c_str());
    }
    // Where the closest obstacle lies in the map the plan was made on, near the worst point.
    if (worst && worst->min_m < 0.05) {
      porter::KinematicsWorkspace ws;
      std::printf("  payload link (7) bounds around t=%.2f s:\n", worst->t_s);
      for (double t = std::max(0.0, worst->t_s - 1.0); t <= std::min(traj.total_duration_s(), worst->t_s + 0.5); t += 0.1) {
        const auto c = porter::planner_daemon::configuration_at(traj, t);
        porter::forward_kinematics(planner->model(), c, ws);
        Eigen::AlignedBox3d b;
        for (const auto& sh : planner->model().links[7].shapes) b.extend(porter::shape_bounds(sh, ws.T_W_L[7]));
        std::printf("    t %.2f base x %.2f: x [%.2f, %.2f] y [%.2f, %.2f] z [%.2f, %.2f]\n", t, c.base.x_m, b.min().x(),
                    b.max().x(), b.min().y(), b.max().y(), b.min().z(), b.max().z());
      }
      const auto c = porter::planner_daemon::configuration_at(traj, worst->t_s);
      for (std::size_t i = 0; i < scene.obstacles.size(); ++i) {
        if (scene.obstacles[i].name != worst->obstacle) continue;
        OccupancyGrid o(g->origin_W(), g->resolution_m(), g->dims());
        porter::voxelize_shape(scene.obstacles[i], o);
        std::printf("  %s near the base at t=%.2f s (%.2f, %.2f), per 5 cm layer: occupied/free/unknown in the map "
                    "(of its voxels within 1 m)\n",
                    worst->obstacle.c_str(), worst->t_s, c.base.x_m, c.base.y_m);
        const auto& n = o.dims();
        for (int z = 0; z < n.z(); ++z) {
          const double zc = o.voxel_center_W(0, 0, z).z();
          const Eigen::AlignedBox3d region(Eigen::Vector3d(c.base.x_m - 1.0, c.base.y_m - 1.0, zc - 0.01),
                                           Eigen::Vector3d(c.base.x_m + 1.0, c.base.y_m + 1.0, zc + 0.01));
          const Counts k = count(o, *g, *before->tree, region);
          if (k.occupied + k.free + k.unknown == 0) continue;
          std::printf("    z %.3f: %ld/%ld/%ld (grid occupied %ld)\n", zc, k.occupied, k.free, k.unknown, k.map_occupied);
          if (zc > 1.6) break;
        }
      }
    }
  }
    // Tracking: truth against the reference of the trajectory executing then, and the estimate.
  {
    double sa = 0, sc = 0, sj = 0, ma = 0, mc = 0, mj = 0, se = 0, me = 0;
    int n = 0, ne = 0;
    std::size_t k = 0;
    for (const auto& s : truth) {
      const LoggedTrajectory* active = nullptr;
      for (const auto& tr : trajectories)
        if (tr.t.start_utime <= s.utime && tr.log_utime <= s.utime) active = &tr;
      if (active) {
        const double t = static_cast<double>(s.utime - active->t.start_utime) * 1e-6;
        if (t <= active->t.trajectory.total_duration_s() + 0.5) {
          const auto ref = porter::planner_daemon::configuration_at(active->t.trajectory, t);
          const Eigen::Vector2d d(s.x_m - ref.base.x_m, s.y_m - ref.base.y_m);
          const Eigen::Vector2d along(std::cos(ref.base.yaw_rad), std::sin(ref.base.yaw_rad));
          const double ea = d.dot(along), ec = along.x() * d.y() - along.y() * d.x();
          double ej = 0;
          for (int j = 0; j < porter::kNumArmJoints; ++j)
            ej = std::max(ej, std::abs(s.q_rad[static_cast<std::size_t>(j)] - ref.q_rad[j]));
          sa += ea * ea, sc += ec * ec, sj += ej * ej;
          ma = std::max(ma, std::abs(ea)), mc = std::max(mc, std::abs(ec)), mj = std::max(mj, ej);
          ++n;
        }
      }
      while (k + 1 < estimate.size() && estimate[k + 1].utime <= s.utime) ++k;
      if (!estimate.empty() && std::abs(estimate[k].utime - s.utime) < 20000) {
        const double e = std::hypot(estimate[k].x_m - s.x_m, estimate[k].y_m - s.y_m);
        se += e * e, me = std::max(me, e), ++ne;
      }
    }
    if (n > 0)
      std::printf("\ntracking (SIM_TRUTH against the executing trajectory, %d samples): along-track RMS %.3f m max %.3f m; "
                  "cross-track RMS %.3f m max %.3f m; largest joint error RMS %.4f rad max %.4f rad\n",
                  n, std::sqrt(sa / n), ma, std::sqrt(sc / n), mc, std::sqrt(sj / n), mj);
    if (ne > 0)
      std::printf("estimate (ROBOT_STATE against SIM_TRUTH within 20 ms, %d samples): position RMS %.4f m max %.4f m\n",
                  ne, std::sqrt(se / ne), me);
  }
  return 0;
}
