// The dense rolling window against stock OctoMap: the same voxels, the same log-odds, the same
// binary stream; window sliding; the planner's reader on the published stream.
#include <random>
#include <set>
#include <tuple>
#include <sstream>

#include <gtest/gtest.h>
#include <octomap/OcTree.h>

#include "porter/mapping/octomap_binary.hpp"
#include "porter/mapping/rolling_map.hpp"
#include "porter/planner/collision/octomap_grid.hpp"

namespace porter::mapping {
namespace {

octomap::Pointcloud to_octomap(const std::vector<Eigen::Vector3f>& pts) {
  octomap::Pointcloud pc;
  for (const auto& p : pts) pc.push_back(p.x(), p.y(), p.z());
  return pc;
}

/// Points that each fall in a voxel of their own (so per-endpoint deduplication changes nothing)
/// around `origin`, within `radius`.
std::vector<Eigen::Vector3f> sparse_points(std::mt19937& rng, const Eigen::Vector3f& origin, double res, int n,
                                           double radius, double z_lo, double z_hi) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), uz(static_cast<float>(z_lo), static_cast<float>(z_hi));
  std::vector<Eigen::Vector3f> pts;
  std::set<std::tuple<int, int, int>> used;
  while (static_cast<int>(pts.size()) < n) {
    const Eigen::Vector3f p(origin.x() + static_cast<float>(radius) * u(rng), origin.y() + static_cast<float>(radius) * u(rng), uz(rng));
    const auto key = std::make_tuple(static_cast<int>(std::floor(p.x() / res)), static_cast<int>(std::floor(p.y() / res)),
                                     static_cast<int>(std::floor(p.z() / res)));
    if (used.insert(key).second) pts.push_back(p);
  }
  return pts;
}

/// Every voxel of the window: the same state and log-odds as the tree (unknown = not in tree).
void expect_equal_in_window(const RollingMap& map, const octomap::OcTree& tree, std::int64_t* known = nullptr) {
  std::int64_t mismatches = 0, n_known = 0;
  const Eigen::Vector3i lo = map.window_min_key(), n = map.dims();
  for (int z = 0; z < n.z(); ++z)
    for (int y = 0; y < n.y(); ++y)
      for (int x = 0; x < n.x(); ++x) {
        const Eigen::Vector3i key = lo + Eigen::Vector3i(x, y, z);
        const octomap::OcTreeKey ok(static_cast<octomap::key_type>(key.x()), static_cast<octomap::key_type>(key.y()),
                                    static_cast<octomap::key_type>(key.z()));
        const octomap::OcTreeNode* node = tree.search(ok);
        const float v = map.log_odds(key);
        if (node == nullptr) {
          mismatches += v == v;
          continue;
        }
        ++n_known;
        if (!(v == v) || std::abs(v - node->getLogOdds()) > 1e-5f) ++mismatches;
      }
  EXPECT_EQ(mismatches, 0);
  if (known) *known = n_known;
}

TEST(RollingMap, KeysAreOctomapKeys) {
  RollingMapParams p;
  RollingMap map(p);
  octomap::OcTree tree(p.resolution_m);
  for (double c : {0.0, 0.049999, 0.05, -0.0001, -0.05, 3.1415, -12.34, 1e-9}) {
    EXPECT_EQ(map.key_of(c), tree.coordToKey(c)) << c;
  }
}

TEST(RollingMap, MatchesStockInsertPointCloudVoxelForVoxel) {
  for (double res : {0.1, 0.05}) {
    RollingMapParams p;
    p.resolution_m = res;
    p.dims = {128, 128, 48};
    p.z_min_m = -0.5;
    RollingMap map(p);
    octomap::OcTree tree(res);
    std::mt19937 rng(7);
    Eigen::Vector3f origin(0.3f, -0.2f, 0.53f);
    const double half = 0.5 * 128 * res - 0.01;
    map.center_on(origin.x(), origin.y());
    std::int64_t known = 0;
    for (int cloud = 0; cloud < 6; ++cloud) {
      origin += Eigen::Vector3f(0.07f, 0.03f, 0.0f);
      const auto pts = sparse_points(rng, origin, res, 3000, half - 0.6, -0.4, 1.8);
      const IntegrateStats st = map.integrate(origin, pts, {});
      tree.insertPointCloud(to_octomap(pts), octomap::point3d(origin.x(), origin.y(), origin.z()));
      EXPECT_EQ(st.hits, pts.size());
      EXPECT_EQ(st.outside_window, 0u);
      EXPECT_FALSE(st.origin_outside);
    }
    expect_equal_in_window(map, tree, &known);
    EXPECT_GT(known, 20000) << res;
  }
}

TEST(RollingMap, RangeLimitMatchesStockMaxrange) {
  RollingMapParams p;
  p.dims = {200, 200, 60};
  p.z_min_m = -1.0;
  RollingMap map(p);
  map.center_on(0.0, 0.0);
  octomap::OcTree tree(p.resolution_m);
  std::mt19937 rng(3);
  const Eigen::Vector3f origin(0.01f, 0.02f, 0.5f);
  // Beyond the range limit rays end on the limit's sphere; keep one point per end voxel there
  // too (the window deduplicates rays per end voxel, stock casts each).
  std::vector<Eigen::Vector3f> pts;
  std::set<std::tuple<int, int, int>> ends;
  for (const Eigen::Vector3f& q : sparse_points(rng, origin, p.resolution_m, 4000, 4.9, -0.9, 1.9)) {
    const Eigen::Vector3f d = q - origin;
    const Eigen::Vector3f e = d.norm() > 3.0f ? Eigen::Vector3f(origin + d.normalized() * 3.0f) : q;
    if (ends.insert({map.key_of(e.x()), map.key_of(e.y()), map.key_of(e.z())}).second) pts.push_back(q);
  }
  IntegrateOptions opt;
  opt.max_range_m = 3.0;
  const IntegrateStats st = map.integrate(origin, pts, opt);
  tree.insertPointCloud(to_octomap(pts), octomap::point3d(origin.x(), origin.y(), origin.z()), 3.0);
  EXPECT_GT(st.beyond_range, 1000u);
  expect_equal_in_window(map, tree);
}

TEST(RollingMap, GroundPointsClearButDoNotMark) {
  RollingMapParams p;
  p.dims = {100, 100, 40};
  RollingMap map(p);
  map.center_on(0, 0);
  const Eigen::Vector3f origin(0.0f, 0.0f, 1.0f);
  IntegrateOptions opt;
  opt.ground_height_m = 0.05;
  const std::vector<Eigen::Vector3f> pts = {{1.0f, 0.0f, 0.02f}, {0.0f, 1.0f, 0.5f}};
  const IntegrateStats st = map.integrate(origin, pts, opt);
  EXPECT_EQ(st.ground, 1u);
  EXPECT_EQ(st.hits, 1u);
  EXPECT_EQ(map.state(map.key_of(Eigen::Vector3d(1.0, 0.0, 0.02))), VoxelState::unknown);
  EXPECT_EQ(map.state(map.key_of(Eigen::Vector3d(0.5, 0.0, 0.51))), VoxelState::free);
  EXPECT_EQ(map.state(map.key_of(Eigen::Vector3d(0.0, 1.0, 0.5))), VoxelState::occupied);
}

TEST(RollingMap, DuplicateEndpointsUpdateOnce) {
  RollingMapParams p;
  p.dims = {64, 64, 32};
  RollingMap map(p);
  map.center_on(0, 0);
  const Eigen::Vector3f origin(0.0f, 0.0f, 0.5f);
  std::vector<Eigen::Vector3f> pts(50, Eigen::Vector3f(1.01f, 0.51f, 0.51f));
  pts.emplace_back(1.02f, 0.52f, 0.52f);
  const IntegrateStats st = map.integrate(origin, pts, {});
  EXPECT_EQ(st.hits, 51u);
  EXPECT_EQ(st.rays, 1u);
  EXPECT_EQ(st.occupied_updates, 1u);
  EXPECT_FLOAT_EQ(map.log_odds(map.key_of(Eigen::Vector3d(1.01, 0.51, 0.51))), map.hit_log());
}

TEST(RollingMap, SlidingForgetsWhatLeavesAndKeepsTheRest) {
  RollingMapParams p;
  p.dims = {40, 30, 10};
  RollingMap map(p);
  map.center_on(0, 0);
  const Eigen::Vector3f origin(0.0f, 0.0f, 0.2f);
  // Voxel centres, so float and double give the same keys.
  const Eigen::Vector3d a(-0.875, 0.025, 0.225), b(0.875, 0.575, 0.225);
  map.integrate(origin, {a.cast<float>(), b.cast<float>()}, {});
  ASSERT_EQ(map.state(map.key_of(a)), VoxelState::occupied);
  ASSERT_EQ(map.state(map.key_of(b)), VoxelState::occupied);
  const std::int64_t known = map.count(VoxelState::free) + map.count(VoxelState::occupied);
  EXPECT_TRUE(map.center_on(0.5, 0.3));  // a (x = -0.875) leaves: the window starts at -0.5
  EXPECT_EQ(map.state(map.key_of(a)), VoxelState::unknown);
  EXPECT_EQ(map.state(map.key_of(b)), VoxelState::occupied);
  EXPECT_LT(map.count(VoxelState::free) + map.count(VoxelState::occupied), known);
  // Coming back does not bring a back: its slots were cleared when it left.
  map.center_on(0.0, 0.0);
  EXPECT_EQ(map.state(map.key_of(a)), VoxelState::unknown);
  EXPECT_EQ(map.state(map.key_of(b)), VoxelState::occupied);
  // A jump farther than the window clears everything.
  map.center_on(100.0, 100.0);
  EXPECT_EQ(map.count(VoxelState::unknown), static_cast<std::int64_t>(40 * 30 * 10));
}

TEST(RollingMap, OriginOutsideTheWindowIntegratesNothing) {
  RollingMap map(RollingMapParams{});
  const IntegrateStats st = map.integrate(Eigen::Vector3f(500.0f, 0.0f, 0.5f), {Eigen::Vector3f(501.0f, 0.0f, 0.5f)}, {});
  EXPECT_TRUE(st.origin_outside);
  EXPECT_EQ(map.count(VoxelState::unknown), map.dims().prod());
}

// Shadow of a new surface. The scene seen from (0, 0, 0.5): a back wall at x = 3 (y in
// [-0.8, 0.8], z in [0.1, 0.9]), then a box face at x = 1.5 (y in [-0.2, 0.2), z in [0.3, 0.7)) that
// appears in the space the wall's rays had cleared.
namespace shadow {
const Eigen::Vector3f kOrigin(0.0f, 0.0f, 0.5f);
std::vector<Eigen::Vector3f> plane_x(float x, float y0, float y1, float z0, float z1) {
  std::vector<Eigen::Vector3f> pts;
  for (float y = y0 + 0.0125f; y < y1; y += 0.025f)
    for (float z = z0 + 0.0125f; z < z1; z += 0.025f) pts.emplace_back(x, y, z);
  return pts;
}
std::vector<Eigen::Vector3f> wall() { return plane_x(3.0125f, -0.8f, 0.8f, 0.1f, 0.9f); }
/// The wall's points the box hides, replaced by the box's face.
std::vector<Eigen::Vector3f> wall_and_box() {
  std::vector<Eigen::Vector3f> pts = plane_x(1.5125f, -0.2f, 0.2f, 0.3f, 0.7f);
  for (const Eigen::Vector3f& w : wall()) {
    const Eigen::Vector3f at_face = kOrigin + (w - kOrigin) * (1.5125f / 3.0125f);
    if (!(std::abs(at_face.y()) < 0.2f && at_face.z() >= 0.3f && at_face.z() < 0.7f)) pts.push_back(w);
  }
  return pts;
}
RollingMap make(double depth_m) {
  RollingMapParams p;
  p.dims = {100, 60, 30};
  p.new_surface_shadow_m = depth_m;
  RollingMap map(p);
  map.center_on(1.5, 0.0);
  return map;
}
/// States of the voxels on the ray through the face's middle, from x = 1.55 to x_end.
std::vector<VoxelState> behind(const RollingMap& map, double x_end = 2.95) {
  std::vector<VoxelState> s;
  for (double x = 1.575; x < x_end; x += 0.05) s.push_back(map.state(map.key_of(Eigen::Vector3d(x, 0.0125, 0.5125))));
  return s;
}
}  // namespace shadow

TEST(RollingMapShadow, TheUnseenDepthOfANewObstacleIsOccupiedUpToTheShadowDepth) {
  using namespace shadow;
  for (const double depth : {0.0, 0.6}) {
    RollingMap map = make(depth);
    for (int i = 0; i < 10; ++i) map.integrate(kOrigin, wall(), {});  // the space is seen free, clamped
    ASSERT_EQ(map.state(map.key_of(Eigen::Vector3d(1.5125, 0.0125, 0.5125))), VoxelState::free);
    std::uint64_t newly = 0, shadowed = 0;
    for (int i = 0; i < 4; ++i) {  // three hits turn a clamped free voxel occupied
      const IntegrateStats st = map.integrate(kOrigin, wall_and_box(), {});
      newly += st.new_surfaces;
      shadowed += st.shadowed;
    }
    EXPECT_EQ(map.state(map.key_of(Eigen::Vector3d(1.5125, 0.0125, 0.5125))), VoxelState::occupied);
    EXPECT_EQ(newly, 64u);  // the face: 8 x 8 voxels of 0.05 m
    const std::vector<VoxelState> b = behind(map);
    // 0.6 m behind the face (x up to 2.1125) occupied, farther still free (stale, as OctoMap).
    for (std::size_t i = 0; i < b.size(); ++i) {
      const double x = 1.575 + 0.05 * static_cast<double>(i);
      const VoxelState want = depth > 0.0 && x < 1.5125 + 0.6 - 0.03 ? VoxelState::occupied : VoxelState::free;
      if (depth > 0.0 && std::abs(x - (1.5125 + 0.6)) < 0.05) continue;  // the sample at the end
      EXPECT_EQ(b[i], want) << "depth " << depth << ", x " << x;
    }
    if (depth == 0.0) {
      EXPECT_EQ(shadowed, 0u);
    } else {
      EXPECT_GT(shadowed, 64u * 10u);
      EXPECT_LT(shadowed, 64u * 16u);  // 12-15 voxels behind each face voxel, each set once
      // The space beside the box, crossed by the wall's rays, stays free.
      EXPECT_EQ(map.state(map.key_of(Eigen::Vector3d(1.8125, 0.3125, 0.5125))), VoxelState::free);
    }
  }
}

TEST(RollingMapShadow, OneRayThroughAShadowMakesItFreeAgain) {
  using namespace shadow;
  RollingMap map = make(0.6);
  for (int i = 0; i < 10; ++i) map.integrate(kOrigin, wall(), {});
  for (int i = 0; i < 4; ++i) map.integrate(kOrigin, wall_and_box(), {});
  const Eigen::Vector3i k = map.key_of(Eigen::Vector3d(1.8125, 0.0125, 0.5125));
  ASSERT_EQ(map.state(k), VoxelState::occupied);
  EXPECT_FLOAT_EQ(map.log_odds(k), map.shadow_log_odds());
  // The box goes: the wall's rays cross the shadow once, and it is free.
  const IntegrateStats st = map.integrate(kOrigin, wall(), {});
  EXPECT_EQ(st.shadowed, 0u);
  EXPECT_EQ(map.state(k), VoxelState::free);
  // The face itself (hit four times, then one miss) is still occupied.
  EXPECT_EQ(map.state(map.key_of(Eigen::Vector3d(1.5125, 0.0125, 0.5125))), VoxelState::occupied);
}

TEST(RollingMapShadow, ASurfaceSeenForTheFirstTimeCastsNoShadowIntoUnknownSpace) {
  using namespace shadow;
  RollingMap map = make(1.0);
  const IntegrateStats st = map.integrate(kOrigin, plane_x(1.5125f, -0.2f, 0.2f, 0.3f, 0.7f), {});
  EXPECT_EQ(st.occupied_updates, 64u);
  EXPECT_EQ(st.new_surfaces, 0u);
  EXPECT_EQ(st.shadowed, 0u);
  for (const VoxelState s : behind(map)) EXPECT_EQ(s, VoxelState::unknown);
}

// A voxel whose hits alternate with misses (rays grazing a surface) is no new surface, even
// when it ends up occupied.
TEST(RollingMapShadow, AVoxelWhoseHitsAlternateWithMissesCastsNoShadow) {
  using namespace shadow;
  RollingMap map = make(1.0);
  for (int i = 0; i < 10; ++i) map.integrate(kOrigin, wall(), {});
  const std::vector<Eigen::Vector3f> box = wall_and_box();
  std::uint64_t new_surfaces = 0, shadowed = 0;
  // hit, hit, miss, hit, hit, hit: occupied at the end, never by hits alone from the clamp.
  for (const bool hit : {true, true, false, true, true, true}) {
    const IntegrateStats st = map.integrate(kOrigin, hit ? box : wall(), {});
    new_surfaces += st.new_surfaces;
    shadowed += st.shadowed;
  }
  EXPECT_EQ(map.state(map.key_of(Eigen::Vector3d(1.5125, 0.0125, 0.5125))), VoxelState::occupied);
  EXPECT_EQ(new_surfaces, 0u);
  EXPECT_EQ(shadowed, 0u);
}

// New obstacles stand on the floor: the free voxels below a new surface (and below its shadow)
// turn occupied down to the first unknown one; below a voxel a ray of the same cloud crossed,
// they stay free.
TEST(RollingMapShadow, TheSpaceBelowANewSurfaceIsShadowedDownToWhatWasNeverSeen) {
  using namespace shadow;
  // A wall down to the floor: its lowest rays cross the column x [1.5, 1.55) down to z 0.249,
  // so there the voxels z [0.2, 0.3) below the face are seen free and the ones below never are.
  const std::vector<Eigen::Vector3f> low_wall = plane_x(3.0125f, -0.8f, 0.8f, 0.0f, 0.9f);
  const auto at_face = [](const Eigen::Vector3f& p) { return kOrigin + (p - kOrigin) * (1.5125f / p.x()); };
  const Eigen::Vector3d under(1.5125, 0.0125, 0.2625);
  for (const bool lower_rays : {true, false}) {
    SCOPED_TRACE(lower_rays ? "the wall's rays below the face still come" : "they are hidden too");
    RollingMap map = make(0.6);
    for (int i = 0; i < 10; ++i) map.integrate(kOrigin, low_wall, {});
    ASSERT_EQ(map.state(map.key_of(under)), VoxelState::free);
    ASSERT_EQ(map.state(map.key_of(Eigen::Vector3d(1.5125, 0.0125, 0.2125))), VoxelState::free);
    ASSERT_EQ(map.state(map.key_of(Eigen::Vector3d(1.5125, 0.0125, 0.1625))), VoxelState::unknown);
    std::vector<Eigen::Vector3f> cloud = plane_x(1.5125f, -0.2f, 0.2f, 0.3f, 0.7f);
    for (const Eigen::Vector3f& w : low_wall) {
      const Eigen::Vector3f f = at_face(w);
      const bool behind_face = std::abs(f.y()) < 0.2f && f.z() >= 0.3f && f.z() < 0.7f;
      const bool below_face = std::abs(f.y()) < 0.2f && f.z() < 0.3f;
      if (!behind_face && (lower_rays || !below_face)) cloud.push_back(w);
    }
    std::uint64_t shadowed = 0;
    for (int i = 0; i < 3; ++i) shadowed += map.integrate(kOrigin, cloud, {}).shadowed;
    EXPECT_GT(shadowed, 0u);
    // Crossed by rays of the same clouds: free; not crossed: shadowed, down to the unknown.
    EXPECT_EQ(map.state(map.key_of(under)), lower_rays ? VoxelState::free : VoxelState::occupied);
    EXPECT_EQ(map.state(map.key_of(Eigen::Vector3d(1.5125, 0.0125, 0.2125))),
              lower_rays ? VoxelState::free : VoxelState::occupied);
    EXPECT_EQ(map.state(map.key_of(Eigen::Vector3d(1.5125, 0.0125, 0.1625))), VoxelState::unknown);
    // Below the shadow behind the face: seen free by the wall's low rays before, hidden now.
    if (!lower_rays) {
      EXPECT_EQ(map.state(map.key_of(Eigen::Vector3d(1.8125, 0.0125, 0.2125))), VoxelState::occupied);
    }
  }
}

// The stream equals stock writeBinaryData of a tree holding the same voxels, and reads back.
TEST(OctomapBinary, EqualsStockWriteBinaryDataOfTheSameVoxels) {
  for (int trial = 0; trial < 4; ++trial) {
    RollingMapParams p;
    p.dims = {70, 50, 24};
    RollingMap map(p);
    map.center_on(trial * 1.37, -trial * 0.71);
    std::mt19937 rng(100 + trial);
    const Eigen::Vector3f origin(static_cast<float>(trial * 1.37), static_cast<float>(-trial * 0.71), 0.4f);
    for (int c = 0; c < 3; ++c) map.integrate(origin, sparse_points(rng, origin, p.resolution_m, 800, 1.6, 0.0, 1.1), {});
    octomap::OcTree tree(p.resolution_m);
    std::int64_t n_known = 0;
    map.for_each_known([&](const Eigen::Vector3i& k, float v) {
      tree.setNodeValue(octomap::OcTreeKey(static_cast<octomap::key_type>(k.x()), static_cast<octomap::key_type>(k.y()),
                                           static_cast<octomap::key_type>(k.z())),
                        v);
      ++n_known;
    });
    ASSERT_GT(n_known, 1000);
    tree.toMaxLikelihood();
    tree.prune();
    std::ostringstream stock;
    tree.writeBinaryData(stock);
    std::vector<std::uint8_t> ours;
    write_octomap_binary(map, ours);
    const std::string s = stock.str();
    ASSERT_EQ(ours.size(), s.size()) << trial;
    EXPECT_TRUE(std::equal(ours.begin(), ours.end(), reinterpret_cast<const std::uint8_t*>(s.data()))) << trial;

    // Read back as the planner does: the same occupied voxels.
    octomap::OcTree back(p.resolution_m);
    std::istringstream in(std::string(ours.begin(), ours.end()));
    back.readBinaryData(in);
    const Eigen::Vector3d lo = (map.window_min_key().cast<double>().array() - RollingMap::kKeyOffset) * p.resolution_m;
    const Eigen::Vector3d hi = lo + map.dims().cast<double>() * p.resolution_m;
    const OccupancyGrid grid = planner::occupancy_from_octomap(back, Eigen::AlignedBox3d(lo, hi));
    std::int64_t disagree = 0;
    map.for_each_known([&](const Eigen::Vector3i& k, float v) {
      const Eigen::Vector3d c(map.key_to_coord(k.x()), map.key_to_coord(k.y()), map.key_to_coord(k.z()));
      disagree += grid.occupied_at(c) != map.occupied(v);
    });
    EXPECT_EQ(disagree, 0);
    EXPECT_EQ(grid.count(), map.count(VoxelState::occupied));
  }
}

TEST(OctomapBinary, EmptyMapIsAnEmptyStream) {
  RollingMap map(RollingMapParams{});
  std::vector<std::uint8_t> out{1, 2, 3};
  write_octomap_binary(map, out);
  EXPECT_TRUE(out.empty());
}

/// One random change to the map: a cloud (hits, some beyond a range limit, some ground), a move
/// of a few voxels, a long move or a jump past the window, or (rarely) clear().
/// Returns the voxels set occupied as shadows of new surfaces.
std::uint64_t random_change(std::mt19937& rng, RollingMap& map, Eigen::Vector2d& at) {
  const double res = map.resolution_m();
  std::uniform_int_distribution<int> pick(0, 99);
  const int what = pick(rng);
  if (what < 55) {
    std::uniform_real_distribution<float> jitter(-0.3f, 0.3f);
    const Eigen::Vector3f origin(static_cast<float>(at.x()) + jitter(rng), static_cast<float>(at.y()) + jitter(rng), 0.45f);
    IntegrateOptions opt;
    opt.max_range_m = pick(rng) < 50 ? 1.2 : -1.0;
    opt.ground_height_m = 0.1;
    return map.integrate(origin, sparse_points(rng, origin, res, 150 + pick(rng) * 4, 1.6, -0.3, 1.4), opt).shadowed;
  } else if (what < 85) {
    std::uniform_int_distribution<int> step(-3, 3);
    at += Eigen::Vector2d(step(rng), step(rng)) * res;
    map.center_on(at.x(), at.y());
  } else if (what < 97) {
    std::uniform_real_distribution<double> far(-1.0, 1.0);
    at += Eigen::Vector2d(far(rng), far(rng)) * (what < 95 ? 0.4 : 6.0);
    map.center_on(at.x(), at.y());
  } else {
    map.clear();
  }
  return 0;
}

/// State of every slot (0 unknown, 1 free, 2 occupied).
std::vector<std::uint8_t> slot_states(const RollingMap& map) {
  std::vector<std::uint8_t> s(static_cast<std::size_t>(map.dims().prod()));
  for (std::size_t i = 0; i < s.size(); ++i) {
    const float v = map.raw_log_odds()[i];
    s[i] = v != v ? 0 : (map.occupied(v) ? 2 : 1);
  }
  return s;
}

// Every slot whose state changed since revision r lies in a block stamped after r, and the
// packed states equal the log-odds' (what the incremental writer relies on), over random
// clouds, moves and clears.
// With and without the shadow of new surfaces (which changes voxels no ray reaches).
class BlockStamps : public ::testing::TestWithParam<double> {};
INSTANTIATE_TEST_SUITE_P(RollingMap, BlockStamps, ::testing::Values(0.0, 0.6));
TEST_P(BlockStamps, CoverEveryStateChange) {
  RollingMapParams p;
  p.dims = {45, 38, 21};  // not multiples of 8: partial blocks at the ends
  p.z_min_m = -0.33;
  p.new_surface_shadow_m = GetParam();
  RollingMap map(p);
  std::mt19937 rng(11);
  Eigen::Vector2d at(0.2, -0.1);
  map.center_on(at.x(), at.y());
  std::int64_t changed_total = 0, missed = 0;
  std::uint64_t shadowed = 0;
  for (int round = 0; round < 60; ++round) {
    const std::vector<std::uint8_t> before = slot_states(map);
    const std::uint64_t r = map.revision();
    const int changes = 1 + round % 3;
    for (int c = 0; c < changes; ++c) shadowed += random_change(rng, map, at);
    const std::vector<std::uint8_t> after = slot_states(map);
    const Eigen::Vector3i& n = map.dims();
    for (std::size_t i = 0; i < after.size(); ++i) {
      if (after[i] == before[i]) continue;
      ++changed_total;
      const int sx = static_cast<int>(i % static_cast<std::size_t>(n.x()));
      const int sy = static_cast<int>((i / static_cast<std::size_t>(n.x())) % static_cast<std::size_t>(n.y()));
      const int sz = static_cast<int>(i / (static_cast<std::size_t>(n.x()) * static_cast<std::size_t>(n.y())));
      missed += map.block_revision(sx >> RollingMap::kBlockShift, sy >> RollingMap::kBlockShift,
                                   sz >> RollingMap::kBlockShift) <= r;
    }
    // The packed states equal the log-odds' states, slot for slot.
    std::int64_t packed_wrong = 0;
    for (std::size_t i = 0; i < after.size(); ++i) {
      const int sx = static_cast<int>(i % static_cast<std::size_t>(n.x()));
      const int sy = static_cast<int>((i / static_cast<std::size_t>(n.x())) % static_cast<std::size_t>(n.y()));
      const int sz = static_cast<int>(i / (static_cast<std::size_t>(n.x()) * static_cast<std::size_t>(n.y())));
      const std::uint64_t* w = map.block_states(sx >> 3, sy >> 3, sz >> 3);
      const int j = (sx & 7) + 8 * (sy & 7) + 64 * (sz & 7);
      packed_wrong += static_cast<int>((w[j >> 5] >> (2 * (j & 31))) & 3u) != after[i];
    }
    EXPECT_EQ(packed_wrong, 0) << "round " << round;
  }
  EXPECT_GT(changed_total, 10000);
  EXPECT_EQ(missed, 0);
  if (GetParam() > 0.0) {
    EXPECT_GT(shadowed, 100u);  // the shadows' changes were among them
  }
}

// The incremental writer gives the full encode's bytes after every kind of change, with writes
// skipped between changes (several moves between two writes included), and re-encodes nothing
// when nothing changed.
TEST(OctomapBinaryWriter, EqualsTheFullEncodeOverRandomUpdatesAndMoves) {
  const Eigen::Vector3i sizes[] = {{70, 50, 24}, {64, 48, 16}, {41, 67, 27}};
  for (int trial = 0; trial < 3; ++trial) {
    RollingMapParams p;
    p.dims = sizes[trial];
    p.z_min_m = trial == 1 ? 0.0 : -0.27;
    RollingMap map(p);
    std::mt19937 rng(200 + trial);
    Eigen::Vector2d at(1.37 * trial, -0.71 * trial);
    map.center_on(at.x(), at.y());
    OctomapBinaryWriter writer;
    std::vector<std::uint8_t> full, inc;
    int writes = 0, partial = 0, mismatches = 0;
    std::size_t max_size = 0;
    std::uniform_int_distribution<int> pick(0, 99);
    for (int step = 0; step < 150; ++step) {
      random_change(rng, map, at);
      if (pick(rng) < 40) continue;  // no map this time
      write_octomap_binary(map, full);
      writer.write(map, inc);
      ++writes;
      mismatches += inc != full;
      max_size = std::max(max_size, full.size());
      partial += writer.last_stats().bricks_encoded < writer.last_stats().bricks;
    }
    EXPECT_EQ(mismatches, 0) << trial;
    EXPECT_GT(writes, 50);
    EXPECT_GT(max_size, 1000u) << trial;
    EXPECT_GT(partial, writes / 2) << trial;  // the cache is used
    // The last change may not have been written yet: write it, then once more with no change.
    write_octomap_binary(map, full);
    writer.write(map, inc);
    EXPECT_EQ(inc, full);
    writer.write(map, inc);
    EXPECT_EQ(writer.last_stats().bricks_encoded, 0) << trial;
    EXPECT_EQ(inc, full);

    // A second writer on the same map starts from nothing; a writer moved to another map starts
    // over.
    OctomapBinaryWriter other;
    other.write(map, inc);
    EXPECT_EQ(other.last_stats().bricks_encoded, other.last_stats().bricks);
    EXPECT_EQ(inc, full);
    RollingMap second(p);
    writer.write(second, inc);
    EXPECT_TRUE(inc.empty());

    // And the stream is stock OctoMap's for the same voxels.
    octomap::OcTree tree(p.resolution_m);
    map.for_each_known([&](const Eigen::Vector3i& k, float v) {
      tree.setNodeValue(octomap::OcTreeKey(static_cast<octomap::key_type>(k.x()), static_cast<octomap::key_type>(k.y()),
                                           static_cast<octomap::key_type>(k.z())),
                        v);
    });
    tree.toMaxLikelihood();
    tree.prune();
    std::ostringstream stock;
    tree.writeBinaryData(stock);
    writer.write(map, inc);
    EXPECT_EQ(std::string(inc.begin(), inc.end()), stock.str()) << trial;
  }
}

}  // namespace
}  // namespace porter::mapping
