// Voxelization (scene_voxelizer.hpp): the fast voxelizer against the per-voxel exact
// reference, volumes against analytic values, and interior coverage.

#include <cmath>
#include <memory>
#include <random>

#include <gtest/gtest.h>

#include "porter/core/scene_loader.hpp"
#include "porter/core/scene_voxelizer.hpp"
#include "test_geometry_helpers.hpp"

namespace porter {
namespace {

struct Case {
  const char* name;
  CollisionShape shape;
  double volume_m3;
  double area_m2;
};

CollisionShape place(ShapeGeometry g, const Eigen::Isometry3d& T) {
  CollisionShape s;
  s.geometry = std::move(g);
  s.T_parent_shape = T;
  return s;
}

std::vector<Case> cases() {
  std::mt19937_64 rng(31);
  const Eigen::Isometry3d T = test::random_pose(rng, 0.2);
  Eigen::Isometry3d yawed = Eigen::Isometry3d::Identity();
  yawed.linear() = Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  yawed.translation() = Eigen::Vector3d(0.013, -0.021, 0.6);
  const double a = 0.9, b = 0.5, c = 0.35, r = 0.37, L = 0.8;
  std::vector<Case> out;
  out.push_back({"yawed box", place(Box{Eigen::Vector3d(a, b, c)}, yawed), a * b * c, 2 * (a * b + b * c + a * c)});
  out.push_back({"rotated box", place(Box{Eigen::Vector3d(a, b, c)}, T), a * b * c, 2 * (a * b + b * c + a * c)});
  out.push_back({"sphere", place(Sphere{r}, T), 4.0 / 3.0 * M_PI * r * r * r, 4 * M_PI * r * r});
  out.push_back({"vertical cylinder", place(Cylinder{r, L}, yawed), M_PI * r * r * L, 2 * M_PI * r * (r + L)});
  out.push_back({"tilted cylinder", place(Cylinder{r, L}, T), M_PI * r * r * L, 2 * M_PI * r * (r + L)});
  Eigen::Isometry3d T_l = T;
  T_l.translation() -= T.linear() * Eigen::Vector3d(1.0, 1.0, 0.5);  // centre the L near the origin
  // L prism: volume 3, area 2 * 3 (caps) + perimeter 8 * height 1.
  out.push_back({"L mesh", place(MeshShape{test::l_prism()}, T_l), 3.0, 14.0});
  return out;
}

OccupancyGrid test_grid(double res) {
  return OccupancyGrid(Eigen::Vector3d(-2.0, -1.9, -1.8), res, Eigen::Vector3i::Constant(static_cast<int>(std::lround(4.0 / res))));
}

TEST(SceneVoxelizer, MatchesPerVoxelExactReference) {
  for (const Case& c : cases()) {
    OccupancyGrid fast = test_grid(0.05);
    voxelize_shape(c.shape, fast);
    OccupancyGrid ref = test_grid(0.05);
    const Eigen::Vector3i n = ref.dims();
    for (int iz = 0; iz < n.z(); ++iz)
      for (int iy = 0; iy < n.y(); ++iy)
        for (int ix = 0; ix < n.x(); ++ix)
          if (shape_intersects_aabb(c.shape, voxelization_box_W(ref, ix, iy, iz))) ref.set(ix, iy, iz);
    EXPECT_GT(ref.count(), 0) << c.name;
    EXPECT_EQ(fast.words(), ref.words()) << c.name << ": fast " << fast.count() << " vs reference " << ref.count();
  }
}

TEST(SceneVoxelizer, VolumeWithinOneVoxelOfExact) {
  for (const double res : {0.05, 0.1}) {
    const double diag = res * std::sqrt(3.0);
    for (const Case& c : cases()) {
      OccupancyGrid g = test_grid(res);
      voxelize_shape(c.shape, g);
      const double v = static_cast<double>(g.count()) * res * res * res;
      // Every point of the shape lies in an occupied voxel, and every occupied voxel lies within
      // one voxel diagonal of the surface.
      EXPECT_GE(v, c.volume_m3 - 1e-9) << c.name << " at " << res;
      EXPECT_LE(v - c.volume_m3, c.area_m2 * diag) << c.name << " at " << res;
    }
  }
}

TEST(SceneVoxelizer, EveryVoxelCentreInsideIsOccupied) {
  for (const Case& c : cases()) {
    OccupancyGrid g = test_grid(0.05);
    voxelize_shape(c.shape, g);
    const Eigen::Vector3i n = g.dims();
    int inside = 0;
    for (int iz = 0; iz < n.z(); ++iz)
      for (int iy = 0; iy < n.y(); ++iy)
        for (int ix = 0; ix < n.x(); ++ix)
          if (shape_contains(c.shape, g.voxel_center_W(ix, iy, iz))) {
            ++inside;
            ASSERT_TRUE(g.occupied(ix, iy, iz)) << c.name << " " << ix << " " << iy << " " << iz;
          }
    EXPECT_GT(inside, 100) << c.name;
  }
}

TEST(SceneVoxelizer, ShapesPartlyOrWhollyOutsideTheGrid) {
  OccupancyGrid g = test_grid(0.1);
  CollisionShape far = place(Sphere{0.5}, Eigen::Isometry3d(Eigen::Translation3d(10, 0, 0)));
  voxelize_shape(far, g);
  EXPECT_EQ(g.count(), 0);
  // A slab crossing the whole grid: exactly the voxels that z in [-0.05, 0.05] reaches into.
  CollisionShape slab = place(Box{Eigen::Vector3d(100, 100, 0.1)}, Eigen::Isometry3d::Identity());
  voxelize_shape(slab, g);
  OccupancyGrid ref = test_grid(0.1);
  for (int iz = 0; iz < ref.dims().z(); ++iz)
    for (int iy = 0; iy < ref.dims().y(); ++iy)
      for (int ix = 0; ix < ref.dims().x(); ++ix)
        if (shape_intersects_aabb(slab, voxelization_box_W(ref, ix, iy, iz))) ref.set(ix, iy, iz);
  EXPECT_EQ(g.words(), ref.words());
  EXPECT_GE(g.count(), 40 * 40);
  EXPECT_LE(g.count(), 3 * 40 * 40);
}

TEST(SceneVoxelizer, GridAlignedBoxOccupiesExactlyItsVoxels) {
  // Faces on voxel faces: the voxels beyond them stay free, so aligned openings keep their width.
  OccupancyGrid g = test_grid(0.1);
  const CollisionShape box = place(Box{Eigen::Vector3d(0.4, 0.3, 0.2)},
                                   Eigen::Isometry3d(Eigen::Translation3d(-0.8, -0.75, -0.7)));
  voxelize_shape(box, g);
  EXPECT_EQ(g.count(), 4 * 3 * 2);
  EXPECT_TRUE(g.occupied_at(Eigen::Vector3d(-0.95, -0.85, -0.75)));
  EXPECT_FALSE(g.occupied_at(Eigen::Vector3d(-1.05, -0.85, -0.75)));  // just beyond the -x face
  EXPECT_FALSE(g.occupied_at(Eigen::Vector3d(-0.95, -0.85, -0.55)));  // just above the top face
  // Reaching 1 mm past a face occupies the next layer.
  OccupancyGrid h = test_grid(0.1);
  voxelize_shape(place(Box{Eigen::Vector3d(0.4, 0.3, 0.202)}, Eigen::Isometry3d(Eigen::Translation3d(-0.8, -0.75, -0.7))), h);
  EXPECT_EQ(h.count(), 4 * 3 * 4);
}

TEST(SceneVoxelizer, OpenMeshGivesOnlySurfaceVoxels) {
  auto open = test::l_prism();
  open->triangles.pop_back();
  open->closed = false;
  const CollisionShape s = place(MeshShape{open}, Eigen::Isometry3d(Eigen::Translation3d(-1, -1, -0.5)));
  OccupancyGrid g = test_grid(0.05);
  voxelize_shape(s, g);
  EXPECT_FALSE(g.occupied_at(Eigen::Vector3d(-0.5, -0.5, 0.0)));  // interior stays free
  EXPECT_TRUE(g.occupied_at(Eigen::Vector3d(-0.5, -0.5, 0.5 - 1e-3)));  // on the top cap
}

TEST(SceneVoxelizer, ShippedForestAgreesWithReferenceAtRandomVoxels) {
  const Scene s = load_scene(std::string(PORTER_SOURCE_DIR) + "/config/scenes/forest.yaml");
  const OccupancyGrid g = voxelize(s);
  EXPECT_EQ(g.resolution_m(), 0.05);
  std::mt19937_64 rng(32);
  int occupied = 0;
  for (int k = 0; k < 20000; ++k) {
    const Eigen::Vector3i i(rng() % g.dims().x(), rng() % g.dims().y(), rng() % g.dims().z());
    const Eigen::AlignedBox3d box = voxelization_box_W(g, i.x(), i.y(), i.z());
    bool ref = false;
    for (const auto& o : s.obstacles) ref = ref || shape_intersects_aabb(o, box);
    ASSERT_EQ(g.occupied(i), ref) << i.transpose();
    occupied += ref;
  }
  EXPECT_GT(occupied, 200);
}

}  // namespace
}  // namespace porter
