// The simulated MID-360's scan pattern and the Embree ray casting against slow references.
#include <cmath>
#include <limits>
#include <random>
#include <set>

#include <gtest/gtest.h>

#include "porter/core/kinematics.hpp"
#include "porter/core/scene_loader.hpp"
#include "porter/core/scene_ray_cast.hpp"
#include "porter/livox_sim/ray_scene.hpp"
#include "porter/livox_sim/scan_pattern.hpp"
#include "sim_support.hpp"

namespace porter::livox::sim {
namespace {

constexpr double kDeg = M_PI / 180.0;

/// Fraction of 1 x 1 deg cells of the field of view hit by points [0, n).
double coverage(const ScanPattern& p, std::uint64_t first, std::uint64_t n) {
  std::vector<char> cells(360 * 59, 0);
  for (std::uint64_t i = first; i < first + n; ++i) {
    double az = 0, el = 0;
    p.angles(i, az, el);
    const int a = std::min(359, static_cast<int>(az / kDeg));
    const int e = std::min(58, static_cast<int>((el / kDeg + 7.0)));
    cells[a * 59 + e] = 1;
  }
  std::size_t hit = 0;
  for (char c : cells) hit += c;
  return static_cast<double>(hit) / cells.size();
}

TEST(ScanPattern, FieldOfViewIs360By7To52Degrees) {
  ScanPattern p;
  double el_min = 1e9, el_max = -1e9;
  std::set<int> az_bins;
  for (std::uint64_t n = 0; n < 200000; ++n) {
    double az = 0, el = 0;
    p.angles(n, az, el);
    el_min = std::min(el_min, el);
    el_max = std::max(el_max, el);
    ASSERT_GE(az, 0.0);
    ASSERT_LT(az, 2 * M_PI);
    az_bins.insert(static_cast<int>(az / kDeg));
    const Eigen::Vector3d d = p.direction(n);
    ASSERT_NEAR(d.norm(), 1.0, 1e-12);
    ASSERT_NEAR(std::asin(d.z()), el, 1e-9);
  }
  EXPECT_GE(el_min, -7.0 * kDeg - 1e-12);
  EXPECT_LE(el_max, 52.0 * kDeg + 1e-12);
  EXPECT_LT(el_min, -6.9 * kDeg);
  EXPECT_GT(el_max, 51.9 * kDeg);
  EXPECT_EQ(az_bins.size(), 360u);
  EXPECT_EQ(ScanPattern::line(4001), 1);
  EXPECT_DOUBLE_EQ(p.time_s(200000), 1.0);
}

TEST(ScanPattern, NonRepetitiveCoverageGrowsWithIntegrationTime) {
  ScanPattern p;
  const double frame = coverage(p, 0, 20000);     // 0.1 s
  const double half_s = coverage(p, 0, 100000);   // 0.5 s
  const double one_s = coverage(p, 0, 200000);    // 1 s
  const double next_frame = coverage(p, 20000, 20000);
  // 20,000 points over 21,240 one-degree cells cover part of them; later frames fill the gaps.
  EXPECT_GT(frame, 0.6);
  EXPECT_NEAR(next_frame, frame, 0.05);
  EXPECT_GT(half_s, frame + 0.2);
  EXPECT_GT(one_s, 0.99);
  // The pattern does not repeat frame to frame: the same index one frame later points elsewhere.
  int same = 0;
  for (std::uint64_t n = 0; n < 20000; n += 7) {
    if ((p.direction(n) - p.direction(n + 20000)).norm() < 0.2 * kDeg) ++same;
  }
  EXPECT_LT(same, 20000 / 7 / 50);
  ::testing::Test::RecordProperty("coverage_0.1s", std::to_string(frame));
  ::testing::Test::RecordProperty("coverage_1s", std::to_string(one_s));
}

TEST(RayScene, WorldHitsMatchTheSceneRayCaster) {
  const Scene scene = load_scene(test::config_path("scenes/forest.yaml"));
  RaySceneParams params;
  params.ground_plane = false;
  RayScene rays(params);
  rays.set_obstacles(scene.obstacles);
  ASSERT_TRUE(rays.ok()) << rays.error();
  const SceneRayCaster reference(scene);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> ux(scene.bounds_W.min().x(), scene.bounds_W.max().x());
  std::uniform_real_distribution<double> uy(scene.bounds_W.min().y(), scene.bounds_W.max().y());
  std::uniform_real_distribution<double> uz(0.2, 2.0);
  std::normal_distribution<double> g(0.0, 1.0);
  int n = 0, both = 0, disagree = 0;
  double worst = 0.0;
  for (int i = 0; i < 20000; ++i) {
    const Eigen::Vector3d o(ux(rng), uy(rng), uz(rng));
    bool inside = false;
    for (const auto& ob : scene.obstacles) inside = inside || shape_contains(ob, o);
    if (inside) continue;
    const Eigen::Vector3d d = Eigen::Vector3d(g(rng), g(rng), 0.3 * g(rng)).normalized();
    const SceneRayHit ref = reference.cast(o, d, 40.0);
    const RayHit hit = rays.cast_world(o.cast<float>(), d.cast<float>(), 0.0f, 40.0f);
    ++n;
    if (hit.hit()) {
      // Every Embree hit lies on the true surface of the obstacle it names, within the
      // tessellation tolerance (0.5 mm) and single precision.
      const Eigen::Vector3d p = o + static_cast<double>(hit.distance_m) * d;
      const double off = std::fabs(shape_signed_distance(scene.obstacles[hit.index], p));
      worst = std::max(worst, off - 2e-6 * (o.norm() + hit.distance_m));
    }
    if (ref.hit() != hit.hit() || (ref.hit() && ref.obstacle_index != hit.index)) {
      ++disagree;  // a ray grazing a cylinder within the tolerance
      continue;
    }
    if (ref.hit()) ++both;
  }
  RecordProperty("both", both);
  RecordProperty("disagree", disagree);
  RecordProperty("rays", n);
  RecordProperty("worst_off_surface_um", static_cast<int>(worst * 1e6));
  EXPECT_GT(both, n / 4);
  EXPECT_LE(disagree, n / 500) << disagree << " of " << n;
  EXPECT_LT(worst, 0.0005 + 2e-5);  // tolerance + single precision
}

TEST(RayScene, RobotAndPayloadHitsMatchPosedShapes) {
  const RobotModel robot = test::robot_with("t_bar");
  RaySceneParams params;
  params.ground_plane = false;
  RayScene rays(params);
  rays.set_obstacles({});
  rays.set_robot(robot);
  ASSERT_TRUE(rays.ok()) << rays.error();
  KinematicsWorkspace ws;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int robot_hits = 0, payload_hits = 0, disagree = 0, n = 0;
  double worst = 0.0;
  for (int pose = 0; pose < 20; ++pose) {
    RobotConfiguration c = test::start_configuration(u(rng), u(rng), M_PI * u(rng));
    for (int j = 0; j < 6; ++j) {
      c.q_rad[j] = 0.5 * (robot.joints[j].lower_rad + robot.joints[j].upper_rad) +
                   0.4 * u(rng) * (robot.joints[j].upper_rad - robot.joints[j].lower_rad);
    }
    forward_kinematics(robot, c, ws);
    rays.set_link_poses(ws.T_W_L);
    const Eigen::Vector3d o = c.base.T_W_B() * Eigen::Vector3d(-0.22, 0.0, 0.5325);
    for (int i = 0; i < 2000; ++i) {
      // Rays towards random points of the arm's reach.
      const Eigen::Vector3d target = ws.T_W_L[3].translation() + 0.8 * Eigen::Vector3d(u(rng), u(rng), u(rng));
      const Eigen::Vector3d d = (target - o).normalized();
      // Reference: every posed shape of every link, exact (core's shape_ray_cast).
      // A ray whose first surface lies in the blind zone (the mast under the sensor) is skipped:
      // solids stop it there, the surface model sees what lies behind.
      double best = 40.0;
      int best_link = -1;
      for (int j = 0; j < kNumLinks; ++j) {
        const Eigen::Isometry3d T_L_W = ws.T_W_L[j].inverse();
        for (const auto& s : robot.links[j].shapes) {
          const Eigen::Vector3d o_L = T_L_W * o;
          if (shape_contains(s, o_L)) continue;  // the sensor housing
          const double t = shape_ray_cast(s, o_L, T_L_W.linear() * d, best);
          if (t >= 0.0 && t < best) {
            best = t;
            best_link = j;
          }
        }
      }
      if (best < 0.1) continue;
      const RayHit hit = rays.cast(o.cast<float>(), d.cast<float>(), 0.1f, 40.0f);
      ++n;
      if (hit.hit()) {
        // The hit lies on a true surface of the link it names (tolerance 0.5 mm).
        const Eigen::Vector3d p_L =
            ws.T_W_L[hit.index].inverse() * (o + static_cast<double>(hit.distance_m) * d);
        double off = 1e9;
        bool on_payload = false;
        for (const auto& s : robot.links[hit.index].shapes) {
          const double sd = std::fabs(shape_signed_distance(s, p_L));
          if (sd < off) {
            off = sd;
            on_payload = s.name.rfind("payload '", 0) == 0;
          }
        }
        worst = std::max(worst, off);
        EXPECT_EQ(hit.kind, on_payload ? HitKind::payload : HitKind::robot);
        (hit.kind == HitKind::payload ? payload_hits : robot_hits)++;
      }
      const bool ref_hit = best_link >= 0;
      // Overlapping links (the wrist's 4 and 5) may both be first; compare distances only.
      if (ref_hit != hit.hit() || (ref_hit && std::fabs(hit.distance_m - best) > 0.02)) ++disagree;
    }
  }
  RecordProperty("robot_hits", robot_hits);
  RecordProperty("payload_hits", payload_hits);
  RecordProperty("disagree", disagree);
  RecordProperty("rays", n);
  RecordProperty("worst_off_surface_um", static_cast<int>(worst * 1e6));
  EXPECT_GT(robot_hits, 2000);
  EXPECT_GT(payload_hits, 100);
  EXPECT_LE(disagree, n / 200) << disagree << " of " << n;
  EXPECT_LT(worst, 0.0005 + 2e-5);  // tolerance + single precision
}

TEST(RayScene, GroundPlaneSpheresAndReplacedObstacles) {
  RayScene rays;
  const Eigen::Vector3f o(0.0f, 0.0f, 1.0f);
  const Eigen::Vector3f down = Eigen::Vector3f(1.0f, 0.0f, -1.0f).normalized();
  RayHit h = rays.cast(o, down, 0.1f, 40.0f);
  ASSERT_EQ(h.kind, HitKind::ground);
  EXPECT_NEAR(h.distance_m, std::sqrt(2.0f), 1e-5f);
  EXPECT_NEAR(h.cos_incidence, std::sqrt(0.5f), 1e-5f);
  CollisionShape ball;
  ball.geometry = Sphere{0.25};
  ball.T_parent_shape.translation() = Eigen::Vector3d(0.5, 0.0, 0.5);
  rays.set_obstacles({ball});
  h = rays.cast(o, down, 0.1f, 40.0f);
  ASSERT_EQ(h.kind, HitKind::obstacle);
  EXPECT_EQ(h.index, 0);
  EXPECT_NEAR(h.distance_m, std::sqrt(0.5f) - 0.25f, 1e-5f);  // an exact sphere
  rays.set_obstacles({});
  EXPECT_EQ(rays.cast(o, down, 0.1f, 40.0f).kind, HitKind::ground);
  // Nothing within [t_near, t_far]: no hit.
  EXPECT_FALSE(rays.cast(o, down, 0.1f, 1.0f).hit());
  EXPECT_FALSE(rays.cast(o, Eigen::Vector3f::UnitZ(), 0.1f, 40.0f).hit());
}

// A ray Embree would call invalid (non-finite origin or direction, negative near distance) is no
// return, not an abort: the robot's pose can go non-finite upstream (a scripted drive that leaves
// the scene's lanes did) and the simulator must go on.
TEST(RayScene, InvalidRaysGiveNoReturnInsteadOfAborting) {
  const RobotModel robot = test::robot_with("t_bar");
  RayScene rays;
  CollisionShape ball;
  ball.geometry = Sphere{0.25};
  ball.T_parent_shape.translation() = Eigen::Vector3d(0.5, 0.0, 0.5);
  rays.set_obstacles({ball});
  rays.set_robot(robot);
  ASSERT_TRUE(rays.ok()) << rays.error();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  const Eigen::Vector3f o(0.0f, 0.0f, 1.0f);
  const Eigen::Vector3f down = Eigen::Vector3f(1.0f, 0.0f, -1.0f).normalized();
  ASSERT_TRUE(rays.cast(o, down, 0.1f, 40.0f).hit());
  EXPECT_FALSE(rays.cast(Eigen::Vector3f(nan, 0.0f, 1.0f), down, 0.1f, 40.0f).hit());
  EXPECT_FALSE(rays.cast(Eigen::Vector3f(inf, 0.0f, 1.0f), down, 0.1f, 40.0f).hit());
  EXPECT_FALSE(rays.cast(o, Eigen::Vector3f(nan, nan, nan), 0.1f, 40.0f).hit());
  EXPECT_FALSE(rays.cast(o, down, -1.0f, 40.0f).hit());
  EXPECT_FALSE(rays.cast(o, down, nan, 40.0f).hit());
  EXPECT_FALSE(rays.cast_world(Eigen::Vector3f(nan, nan, nan), down, 0.1f, 40.0f).hit());
}

}  // namespace
}  // namespace porter::livox::sim
