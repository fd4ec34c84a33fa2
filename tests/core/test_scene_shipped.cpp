// The shipped scenes (config/scenes/*.yaml) load and are sized for the Scout Mini + Piper.

#include <cmath>
#include <deque>
#include <filesystem>
#include <vector>

#include <gtest/gtest.h>

#include "porter/core/scene_loader.hpp"
#include "porter/core/scene_ray_cast.hpp"
#include "porter/core/scene_voxelizer.hpp"

namespace porter {
namespace {

std::string scene_path(const std::string& name) {
  return std::string(PORTER_SOURCE_DIR) + "/config/scenes/" + name + ".yaml";
}

// Half the diagonal of the 0.612 x 0.58 m Scout Mini footprint.
constexpr double kBaseHalfDiagonal_m = 0.422;

double min_footprint_distance(const Scene& s, const BasePose& b) {
  double d = 1e300;
  for (const auto& o : s.obstacles) d = std::min(d, footprint_distance(o, {b.x_m, b.y_m}));
  return d;
}

/// Can a disc of radius r (a stand-in for the base turning on the spot) get from start to goal
/// through the voxels at base height (z in [0.05, 0.30])? 8-connected search on a 2D map in
/// which every cell within r + one voxel of an occupied voxel, or of the bounds, is blocked.
bool base_disc_passes(const Scene& s, double r) {
  const OccupancyGrid g = voxelize(s);
  const int nx = g.dims().x(), ny = g.dims().y();
  const double res = g.resolution_m();
  const int k = static_cast<int>(std::ceil(r / res)) + 1;
  std::vector<char> blocked(static_cast<std::size_t>(nx) * ny, 0);
  auto at = [nx](int x, int y) { return static_cast<std::size_t>(x) + static_cast<std::size_t>(nx) * y; };
  for (int iy = 0; iy < ny; ++iy)
    for (int ix = 0; ix < nx; ++ix) {
      if (ix * res < r || iy * res < r || (nx - ix) * res < r || (ny - iy) * res < r) blocked[at(ix, iy)] = 1;
      bool occ = false;
      for (int iz = 1; iz < 6; ++iz) occ = occ || g.occupied(ix, iy, iz);
      if (!occ) continue;
      for (int dy = -k; dy <= k; ++dy)
        for (int dx = -k; dx <= k; ++dx)
          if ((dx * dx + dy * dy) * res * res <= (r + res) * (r + res) && ix + dx >= 0 && iy + dy >= 0 &&
              ix + dx < nx && iy + dy < ny)
            blocked[at(ix + dx, iy + dy)] = 1;
    }
  const Eigen::Vector3i a = g.world_to_index({s.start.base.x_m, s.start.base.y_m, 0.1});
  const Eigen::Vector3i b = g.world_to_index({s.goal.base.x_m, s.goal.base.y_m, 0.1});
  if (blocked[at(a.x(), a.y())] || blocked[at(b.x(), b.y())]) return false;
  std::vector<char> seen(blocked.size(), 0);
  std::deque<Eigen::Vector2i> queue{{a.x(), a.y()}};
  seen[at(a.x(), a.y())] = 1;
  while (!queue.empty()) {
    const Eigen::Vector2i c = queue.front();
    queue.pop_front();
    if (c.x() == b.x() && c.y() == b.y()) return true;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int x = c.x() + dx, y = c.y() + dy;
        if (x < 0 || y < 0 || x >= nx || y >= ny || seen[at(x, y)] || blocked[at(x, y)]) continue;
        seen[at(x, y)] = 1;
        queue.emplace_back(x, y);
      }
  }
  return false;
}

TEST(ShippedScenes, LoadWithStartAndGoalClearOfObstacles) {
  for (const char* name : {"empty", "bridge", "tunnel", "forest"}) {
    const Scene s = load_scene(scene_path(name));
    EXPECT_EQ(s.name, name);
    EXPECT_EQ(s.resolution_m, 0.05) << name;
    EXPECT_EQ(s.bounds_W.min().z(), 0.0) << name;  // z = 0 is the ground
    EXPECT_GE(s.bounds_W.max().z(), 2.0) << name;
    EXPECT_TRUE(std::filesystem::is_regular_file(s.payload_file)) << s.payload_file;
    EXPECT_GT(min_footprint_distance(s, s.start.base), kBaseHalfDiagonal_m) << name;
    EXPECT_GT(min_footprint_distance(s, s.goal.base), kBaseHalfDiagonal_m) << name;
    EXPECT_TRUE(s.bounds_W.contains(Eigen::Vector3d(s.start.base.x_m, s.start.base.y_m, 0.0))) << name;
    // Start and goal on either side of the obstacles, at least 5 m apart.
    EXPECT_GT(std::hypot(s.goal.base.x_m - s.start.base.x_m, s.goal.base.y_m - s.start.base.y_m), 4.99) << name;
    const OccupancyGrid g = voxelize(s);
    EXPECT_FALSE(g.occupied_at({s.start.base.x_m, s.start.base.y_m, 0.3})) << name;
    EXPECT_EQ(g.count() == 0, std::string(name) == "empty") << name;
  }
}

TEST(ShippedScenes, BridgeClearanceFollowsHb) {
  for (const double h_b : {0.8, 0.9, 1.0, 1.1}) {
    SceneLoadOptions o;
    o.parameter_overrides = {{"h_b", h_b}};
    const Scene s = load_scene(scene_path("bridge"), o);
    ASSERT_EQ(s.obstacles.size(), 3u);
    const Eigen::AlignedBox3d deck = shape_bounds(s.obstacles[2]);
    EXPECT_NEAR(deck.min().z(), h_b, 1e-12);
    EXPECT_GE(deck.sizes().y(), 1.0);  // opening 1.0 .. 1.2 m wide
    EXPECT_LE(deck.sizes().y(), 1.2);
    // The wall spans the bounds: no way around it.
    const Eigen::AlignedBox3d left = shape_bounds(s.obstacles[0]), right = shape_bounds(s.obstacles[1]);
    EXPECT_GE(std::max(left.max().y(), right.max().y()), s.bounds_W.max().y());
    EXPECT_LE(std::min(left.min().y(), right.min().y()), s.bounds_W.min().y());
  }
}

TEST(ShippedScenes, TunnelBlocksTheStraightLine) {
  const Scene s = load_scene(scene_path("tunnel"));
  const SceneRayCaster caster(s);
  const Eigen::Vector3d from(s.start.base.x_m, s.start.base.y_m, 0.3);
  const Eigen::Vector3d to(s.goal.base.x_m, s.goal.base.y_m, 0.3);
  EXPECT_TRUE(caster.cast(from, (to - from).normalized(), (to - from).norm()).hit());
  EXPECT_GE(s.obstacles.size(), 10u);
}

TEST(ShippedScenes, ForestHasThreeHolesAndFortyFiveSeededColumns) {
  const Scene s = load_scene(scene_path("forest"));
  int columns = 0, decks = 0;
  for (const auto& o : s.obstacles) {
    columns += std::holds_alternative<Cylinder>(o.geometry);
    decks += o.name.size() > 5 && o.name.substr(o.name.size() - 5) == ".deck";
  }
  EXPECT_EQ(columns, 45);
  EXPECT_EQ(decks, 3);
  EXPECT_EQ(s.obstacles.size(), 54u);
  EXPECT_GT(s.bounds_W.sizes().x(), 18.0);
  SceneLoadOptions o;
  o.seed = s.seed + 1;
  const Scene other = load_scene(scene_path("forest"), o);
  const Scene same = load_scene(scene_path("forest"));
  EXPECT_FALSE(other.obstacles.back().T_parent_shape.isApprox(s.obstacles.back().T_parent_shape));
  EXPECT_TRUE(same.obstacles.back().T_parent_shape.isApprox(s.obstacles.back().T_parent_shape));
  // Each hole's opening is free below the deck.
  const OccupancyGrid g = voxelize(s);
  for (const auto& ob : s.obstacles) {
    if (ob.name.size() < 5 || ob.name.substr(ob.name.size() - 5) != ".deck") continue;
    const Eigen::Vector3d c = ob.T_parent_shape.translation();
    EXPECT_FALSE(g.occupied_at({c.x(), c.y(), 0.5})) << ob.name;
  }
}

TEST(ShippedScenes, BaseCanGetThroughButOnlyTightly) {
  // Possible but tight: a disc of the base's half-diagonal passes everywhere on the way, one of
  // radius 0.55 m does not (every scene has a passage narrower than 1.2 m).
  for (const char* name : {"bridge", "tunnel", "forest"}) {
    const Scene s = load_scene(scene_path(name));
    EXPECT_TRUE(base_disc_passes(s, kBaseHalfDiagonal_m)) << name;
    EXPECT_FALSE(base_disc_passes(s, 0.55)) << name;
  }
  // The check itself fails when the way is shut: the bridge with the opening closed.
  SceneLoadOptions o;
  o.parameter_overrides = {{"opening_width", 0.5}};
  EXPECT_FALSE(base_disc_passes(load_scene(scene_path("bridge"), o), kBaseHalfDiagonal_m));
}

}  // namespace
}  // namespace porter
