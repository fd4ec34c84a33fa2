// Map quality after a simulated drive through the forest: the window's occupied voxels against
// stock OctoMap insertion of the same filtered clouds (>= 99 % precision and recall) and
// against the scene's own voxelization (reported); free-space clearing of a removed obstacle.
#include <cstdio>
#include <set>
#include <tuple>

#include <gtest/gtest.h>

#include "mapping_support.hpp"
#include "porter/core/scene_voxelizer.hpp"

namespace porter::mapping {
namespace {

using livox::sim::HitKind;
using livox::sim::Waypoint;

struct Agreement {
  std::int64_t ours = 0, reference = 0, both = 0;
  double precision() const { return ours ? static_cast<double>(both) / ours : 1.0; }
  double recall() const { return reference ? static_cast<double>(both) / reference : 1.0; }
};

// OctoMap's model (no shadows of new surfaces) against stock, and the shipped configuration,
// whose shadows may only add voxels where the scene has something (a static scene: nothing new
// appears, so a shadow there is a phantom).
TEST(MapQuality, ForestDriveAgreesWithStockOctomapAndTheScene) {
  const Scene scene = load_scene(test::config_path("scenes/forest.yaml"));
  const app::MapperConfig shipped = test::shipped_config();
  ASSERT_GT(shipped.mapper.map.new_surface_shadow_m, 0.0);
  double scene_precision_without_shadows = 0.0;
  std::int64_t occupied_without_shadows = 0;
  for (const double shadow : {0.0, shipped.mapper.map.new_surface_shadow_m}) {
  SCOPED_TRACE("new_surface_shadow_m " + std::to_string(shadow));
  app::MapperConfig cfg = shipped;
  cfg.mapper.map.new_surface_shadow_m = shadow;
  cfg.mapper.recenter_distance_m = 100.0;  // one window for the whole drive: comparable to stock
  const double y = test::clear_lane(scene, 3.5, 0.4);
  ASSERT_FALSE(std::isnan(y));
  const RobotModel robot = test::robot_with("long_bar");
  test::SimDrive drive(robot, scene.obstacles,
                       {Waypoint{0.0, test::config_at(0.0, y, 0.0)}, Waypoint{1.5, test::config_at(1.2, y, 0.15)},
                        Waypoint{3.0, test::config_at(2.6, y, -0.1)}},
                       cfg.mapper.T_B_S);
  Mapper mapper(robot, cfg.mapper);
  octomap::OcTree stock(cfg.mapper.map.resolution_m);
  StateBuffer states;
  std::vector<Eigen::Vector3f> obstacle_hits;
  for (int k = 0; k < 30; ++k) {
    const test::SimCloud c = drive.next(states);
    FilteredCloud f;
    const FilterStats fs = mapper.filter(c.cloud, states, f);
    EXPECT_EQ(fs.state_outside, 0u);
    mapper.integrate(f);
    test::stock_insert(stock, f, cfg.mapper.max_range_m);
    for (const livox::sim::SimRay& r : c.rays)
      if (r.kind == HitKind::obstacle) obstacle_hits.push_back(r.hit_W);
  }
  const RollingMap& map = mapper.map();
  const int ground_key = map.key_of(cfg.mapper.ground_height_m);

  // Against stock: occupied voxels of the window above the ground layer.
  Agreement vs_stock;
  map.for_each_known([&](const Eigen::Vector3i& k, float v) {
    if (k.z() < ground_key) return;
    const octomap::OcTreeNode* n = stock.search(octomap::OcTreeKey(static_cast<octomap::key_type>(k.x()),
                                                                   static_cast<octomap::key_type>(k.y()),
                                                                   static_cast<octomap::key_type>(k.z())));
    const bool s = n && stock.isNodeOccupied(n);
    vs_stock.ours += map.occupied(v);
    vs_stock.both += map.occupied(v) && s;
  });
  for (auto it = stock.begin_leafs(), end = stock.end_leafs(); it != end; ++it) {
    const Eigen::Vector3i k(it.getKey()[0], it.getKey()[1], it.getKey()[2]);
    if (it.getSize() > stock.getResolution() + 1e-9) continue;  // pruned: only free leaves merge here
    if (k.z() >= ground_key && map.in_window(k) && stock.isNodeOccupied(*it)) ++vs_stock.reference;
  }

  // Against the scene: our occupied voxels on an obstacle (precision), and the voxels that hold a
  // true obstacle hit within range of the robot's final pose and are occupied in the map
  // (recall; OctoMap's model lets rays grazing a surface later clear voxels hit earlier, the
  // same in stock insertion).
  const OccupancyGrid truth = voxelize(scene);
  Agreement vs_scene;
  map.for_each_known([&](const Eigen::Vector3i& k, float v) {
    if (k.z() < ground_key || !map.occupied(v)) return;
    const Eigen::Vector3d c(map.key_to_coord(k.x()), map.key_to_coord(k.y()), map.key_to_coord(k.z()));
    if (!scene.bounds_W.contains(c)) return;  // the walls reach past the scene's bounds
    ++vs_scene.ours;
    // A hit exactly on an obstacle face that lies on a voxel face (the forest's walls do) falls
    // on either side of it by rounding; the voxelization keeps only the inner side. So a voxel
    // counts as right when the scene occupies it or an obstacle touches it.
    bool t = truth.occupied_at(c);
    for (std::size_t i = 0; i < scene.obstacles.size() && !t; ++i) {
      t = shape_signed_distance(scene.obstacles[i], c) <= 0.5 * std::sqrt(3.0) * map.resolution_m();
    }
    vs_scene.both += t;
  });
  std::set<std::tuple<int, int, int>> seen;
  std::int64_t seen_occupied = 0, stock_seen_occupied = 0;
  for (const Eigen::Vector3f& h : obstacle_hits) {
    const Eigen::Vector3i k = map.key_of(h.cast<double>());
    if (k.z() < ground_key || !map.in_window(k) || !scene.bounds_W.contains(h.cast<double>()) || (h - drive.motion().at(3.0).base.T_W_B().translation().cast<float>()).norm() > cfg.mapper.max_range_m - 1.0) continue;
    if (!seen.insert({k.x(), k.y(), k.z()}).second) continue;
    seen_occupied += map.state(k) == VoxelState::occupied;
    const octomap::OcTreeNode* n = stock.search(octomap::OcTreeKey(static_cast<octomap::key_type>(k.x()),
                                                                   static_cast<octomap::key_type>(k.y()),
                                                                   static_cast<octomap::key_type>(k.z())));
    stock_seen_occupied += n && stock.isNodeOccupied(n);
  }
  vs_scene.reference = static_cast<std::int64_t>(seen.size());
  const double scene_recall = seen.empty() ? 1.0 : static_cast<double>(seen_occupied) / seen.size();
  const double stock_scene_recall = seen.empty() ? 1.0 : static_cast<double>(stock_seen_occupied) / seen.size();

  RecordProperty("lane_y_m", std::to_string(y));
  RecordProperty("occupied_ours", static_cast<int>(vs_stock.ours));
  RecordProperty("occupied_stock", static_cast<int>(vs_stock.reference));
  RecordProperty("precision_vs_stock", std::to_string(vs_stock.precision()));
  RecordProperty("recall_vs_stock", std::to_string(vs_stock.recall()));
  RecordProperty("precision_vs_scene", std::to_string(vs_scene.precision()));
  RecordProperty("recall_vs_scene", std::to_string(scene_recall));
  RecordProperty("stock_recall_vs_scene", std::to_string(stock_scene_recall));
  std::printf("forest drive, shadow %.2f m: occupied ours %lld, stock %lld; vs stock precision %.4f recall %.4f; vs scene "
              "precision %.4f recall %.4f (stock %.4f; %zu hit voxels)\n", shadow,
              static_cast<long long>(vs_stock.ours), static_cast<long long>(vs_stock.reference), vs_stock.precision(),
              vs_stock.recall(), vs_scene.precision(), scene_recall, stock_scene_recall, seen.size());
  EXPECT_GT(vs_stock.ours, 2000);
  EXPECT_GE(vs_stock.recall(), 0.99);
  EXPECT_GE(vs_scene.precision(), 0.95);
  EXPECT_GE(scene_recall, 0.70);
  if (shadow == 0.0) {
    EXPECT_GE(vs_stock.precision(), 0.99);
    scene_precision_without_shadows = vs_scene.precision();
    occupied_without_shadows = vs_stock.ours;
  } else {
    // Shadows in a static scene: at most 1 point of precision lost, at most 10 % more voxels.
    EXPECT_GE(vs_scene.precision(), scene_precision_without_shadows - 0.01);
    EXPECT_LE(vs_stock.ours, occupied_without_shadows + occupied_without_shadows / 10);
  }
  }
}

TEST(MapQuality, AnObstacleRemovedFromTheWorldDisappears) {
  app::MapperConfig cfg = test::shipped_config();
  const RobotModel robot = test::robot_with("t_bar");
  CollisionShape wall, post;
  wall.name = "wall";
  wall.geometry = Box{Eigen::Vector3d(8.0, 0.2, 2.0)};
  wall.T_parent_shape.translation() = Eigen::Vector3d(0.0, 4.0, 1.0);
  post.name = "post";
  post.geometry = Box{Eigen::Vector3d(0.3, 0.3, 1.2)};
  // Beside the robot, where the carried payload does not shadow it.
  post.T_parent_shape.translation() = Eigen::Vector3d(-0.4, 2.0, 0.6);
  test::SimDrive drive(robot, {wall, post}, {Waypoint{0.0, test::config_at(0, 0, 0)}}, cfg.mapper.T_B_S);
  Mapper mapper(robot, cfg.mapper);
  StateBuffer states;
  for (int k = 0; k < 10; ++k) {
    const CloudReport r = mapper.process(drive.next(states).cloud, states);
    EXPECT_EQ(r.filter.state_outside, 0u);
  }
  const RollingMap& map = mapper.map();
  std::vector<Eigen::Vector3i> post_voxels;
  const Eigen::AlignedBox3d post_box(Eigen::Vector3d(-0.55, 1.85, 0.05), Eigen::Vector3d(-0.25, 2.15, 1.2));
  map.for_each_known([&](const Eigen::Vector3i& k, float v) {
    const Eigen::Vector3d c(map.key_to_coord(k.x()), map.key_to_coord(k.y()), map.key_to_coord(k.z()));
    if (map.occupied(v) && post_box.contains(c)) post_voxels.push_back(k);
  });
  ASSERT_GT(post_voxels.size(), 50u);

  drive.lidar().set_obstacles({wall});
  int clouds = 0, still = static_cast<int>(post_voxels.size());
  for (; clouds < 50 && still > 0; ++clouds) {
    mapper.process(drive.next(states).cloud, states);
    still = 0;
    for (const auto& k : post_voxels) still += map.state(k) == VoxelState::occupied;
  }
  RecordProperty("post_voxels", static_cast<int>(post_voxels.size()));
  RecordProperty("clouds_to_clear", clouds);
  std::printf("post: %zu occupied voxels, all cleared after %d clouds (%d left)\n", post_voxels.size(), clouds, still);
  EXPECT_EQ(still, 0);
  // The wall behind stays.
  EXPECT_EQ(map.state(map.key_of(Eigen::Vector3d(-0.375, 3.925, 0.525))), VoxelState::occupied);
}

}  // namespace
}  // namespace porter::mapping
