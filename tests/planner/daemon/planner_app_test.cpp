// porter-planner's adapter: the strict config, the message conversions (goal, state, OctoMap
// stream and planning grid, status) including a bounded random-input test of the OctoMap
// decoder, and the node over memq:// (a goal planned from ROBOT_STATE on MAP_OCTOMAP; a stale
// map refused; LCM handling answers while a plan runs).
#include <octomap/OcTree.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>
#include <thread>

#include <gtest/gtest.h>

#include "planner_config.hpp"
#include "planner_messages.hpp"
#include "planner_node.hpp"
#include "porter/core/load_error.hpp"
#include "porter/lcm_bus.hpp"
#include "porter/runtime/clock.hpp"
#include "hostile_config.hpp"

namespace porter::planner_app {
namespace {

std::string shipped() { return std::string(PORTER_SOURCE_DIR) + "/config/planner/porter_planner.yaml"; }

std::string read(const std::string& path) {
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

/// The shipped config with `from` replaced by `to`, written beside it (relative paths hold).
std::string variant(const std::string& from, const std::string& to) {
  std::string text = read(shipped());
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  text.replace(at, from.size(), to);
  const std::string path = std::string(PORTER_SOURCE_DIR) + "/config/planner/.test_porter_planner_" +
                           std::to_string(::getpid()) + ".yaml";
  std::ofstream(path) << text;
  return path;
}

std::string load_error(const std::string& path) {
  try {
    load_planner_config(path);
  } catch (const LoadError& e) {
    std::remove(path.c_str());
    return e.what();
  }
  std::remove(path.c_str());
  return "";
}

TEST(PlannerConfig, ShippedFileLoads) {
  const PlannerConfig c = load_planner_config(shipped());
  EXPECT_EQ(c.payload_id, "t_bar");
  EXPECT_EQ(c.payloads.size(), 3u);
  EXPECT_DOUBLE_EQ(c.settings.kernels.kernels.resolution_m, c.map.resolution_m);
  EXPECT_GT(c.loop.handoff.lead_s, worst_case_plan_s(c.settings));
}

TEST(PlannerConfig, StrictAboutKeysAndRanges) {
  EXPECT_NE(load_error(variant("  max_age_s: 3.0", "  max_age_s: 3.0\n  extra: 1")).find("extra"), std::string::npos);
  EXPECT_NE(load_error(variant("tick_hz: 10", "")).find("tick_hz"), std::string::npos);
  EXPECT_NE(load_error(variant("payload: t_bar", "payload: piano")).find("payload"), std::string::npos);
  const std::string lead = load_error(variant("lead_s: 2.5", "lead_s: 0.5"));
  EXPECT_NE(lead.find("lead_s"), std::string::npos) << lead;
  EXPECT_NE(lead.find("longest plan"), std::string::npos) << lead;
  EXPECT_NE(load_error(variant("max_attempts: 10", "max_attempts: 0")).find("max_attempts"), std::string::npos);
}

octomap_t map_msg(const octomap::OcTree& tree, std::int64_t utime) {
  std::ostringstream s;
  tree.writeBinaryData(s);
  const std::string bytes = s.str();
  octomap_t m;
  m.utime = utime;
  m.frame_id = "world";
  m.map_id = 1;
  m.resolution_m = tree.getResolution();
  m.binary = true;
  m.tree_type = "OcTree";
  m.data.assign(bytes.begin(), bytes.end());
  m.num_bytes = static_cast<std::int32_t>(m.data.size());
  return m;
}

/// A tree with a 0.3 m column at (x, y) up to 1 m.
octomap::OcTree column_tree(double x, double y) {
  octomap::OcTree tree(0.05);
  for (double dx = -0.15; dx < 0.15; dx += 0.05)
    for (double dy = -0.15; dy < 0.15; dy += 0.05)
      for (double z = 0.025; z < 1.0; z += 0.05) tree.updateNode(octomap::point3d(x + dx + 0.025, y + dy + 0.025, z), true);
  return tree;
}

TEST(PlannerMessages, OctomapRoundTripMarksTheColumnInAGridCoveringRobotAndGoal) {
  MapParams p;
  const auto tree = column_tree(3.0, 0.5);
  const TreeConversion t = decode_octomap(map_msg(tree, 1), "world", p);
  ASSERT_TRUE(t.tree) << t.error;
  const GridConversion g = to_grid(*t.tree, {{0.0, 0.0}, {8.0, 0.0}}, p);
  ASSERT_TRUE(g.grid) << g.error;
  const auto b = g.grid->bounds_W();
  EXPECT_LE(b.min().x(), -2.0);
  EXPECT_GE(b.max().x(), 10.0);
  EXPECT_NEAR(b.min().z(), 0.0, 1e-9);
  EXPECT_GE(b.max().z(), p.min_height_m);
  Eigen::Vector3i idx;
  ASSERT_TRUE(g.grid->world_to_index_checked(Eigen::Vector3d(3.0, 0.5, 0.5), &idx));
  EXPECT_TRUE(g.grid->occupied(idx));
  ASSERT_TRUE(g.grid->world_to_index_checked(Eigen::Vector3d(5.0, 0.5, 0.5), &idx));
  EXPECT_FALSE(g.grid->occupied(idx));
}

/// The slow, obviously right answer: a voxel is filled when the tree does not know it, it is no
/// gap, and walking up its column through unknown voxels that are no gaps either, the first
/// known voxel is occupied (tree lookup per voxel at its centre). A gap: a voxel known free
/// within kFillGapVoxels on both sides along x or along y.
OccupancyGrid fill_reference(const octomap::OcTree& tree, const OccupancyGrid& grid) {
  OccupancyGrid out = grid;
  const auto& n = grid.dims();
  auto known = [&](int x, int y, int z, bool* occupied) {
    if (grid.occupied(x, y, z)) return *occupied = true;
    if (!grid.in_bounds(x, y, z)) return false;
    const Eigen::Vector3d c = grid.voxel_center_W(x, y, z);
    const octomap::OcTreeNode* node = tree.search(c.x(), c.y(), c.z());
    if (node == nullptr) return false;
    *occupied = tree.isNodeOccupied(node);
    return true;
  };
  auto free_at = [&](int x, int y, int z) {
    bool occ = true;
    return known(x, y, z, &occ) && !occ;
  };
  auto gap = [&](int x, int y, int z) {
    bool s[4] = {false, false, false, false};
    for (int k = 1; k <= kFillGapVoxels; ++k) {
      s[0] = s[0] || free_at(x + k, y, z);
      s[1] = s[1] || free_at(x - k, y, z);
      s[2] = s[2] || free_at(x, y + k, z);
      s[3] = s[3] || free_at(x, y - k, z);
    }
    return (s[0] && s[1]) || (s[2] && s[3]);
  };
  for (int z = 0; z < n.z(); ++z)
    for (int y = 0; y < n.y(); ++y)
      for (int x = 0; x < n.x(); ++x) {
        bool occ = false;
        if (known(x, y, z, &occ) || gap(x, y, z)) continue;
        for (int k = z + 1; k < n.z(); ++k) {
          if (known(x, y, k, &occ)) {
            if (occ) out.set(x, y, z);
            break;
          }
          if (gap(x, y, k)) break;
        }
      }
  return out;
}

TEST(PlannerMessages, UnknownBelowOccupiedIsFilledDownToSpaceSeenFree) {
  // A wall seen from z = 1 m up, unknown below; a deck over an opening seen free beneath it.
  octomap::OcTree tree(0.05);
  for (double y = 0.025; y < 0.5; y += 0.05)
    for (double z = 1.025; z < 2.0; z += 0.05) tree.updateNode(octomap::point3d(1.025, y, z), true);
  for (double y = 1.025; y < 1.5; y += 0.05) {
    for (double z = 1.025; z < 1.2; z += 0.05) tree.updateNode(octomap::point3d(1.025, y, z), true);
    // Seen free beneath the deck but for a 0.1 m strip (a shadow) at y in [1.2, 1.3).
    if (y > 1.2 && y < 1.3) continue;
    for (double z = 0.525; z < 1.0; z += 0.05) tree.updateNode(octomap::point3d(1.025, y, z), false);
  }
  MapParams p;
  p.fill_unknown_below = false;
  const GridConversion plain = to_grid(tree, {{0.0, 0.0}}, p);
  p.fill_unknown_below = true;
  const GridConversion filled = to_grid(tree, {{0.0, 0.0}}, p);
  ASSERT_TRUE(plain.grid && filled.grid);
  auto at = [](const OccupancyGrid& g, double x, double y, double z) { return g.occupied_at(Eigen::Vector3d(x, y, z)); };
  EXPECT_FALSE(at(*plain.grid, 1.025, 0.225, 0.525));
  EXPECT_TRUE(at(*filled.grid, 1.025, 0.225, 0.525));   // the wall continues down...
  EXPECT_TRUE(at(*filled.grid, 1.025, 0.225, 0.025));   // ...to the floor
  EXPECT_FALSE(at(*filled.grid, 1.025, 1.125, 0.725));  // the opening seen free stays free
  EXPECT_FALSE(at(*filled.grid, 1.025, 1.225, 0.725));  // the shadow strip inside it is a gap
  EXPECT_FALSE(at(*filled.grid, 1.025, 1.125, 0.225));  // and below it (not adjacent to the deck)
  EXPECT_FALSE(at(*filled.grid, 2.025, 0.225, 0.525));  // nothing above: stays as it was
  // Near the robot the columns stay as they are (its own body hides them).
  const Eigen::Vector2d robot(1.0, 0.0);
  p.fill_clear_radius_m = 0.5;
  const GridConversion near = to_grid(tree, {{0.0, 0.0}}, p, &robot);
  ASSERT_TRUE(near.grid);
  EXPECT_FALSE(at(*near.grid, 1.025, 0.225, 0.525));
  EXPECT_TRUE(at(*near.grid, 1.025, 0.225, 1.525));
}

TEST(PlannerMessages, FillUnknownBelowOccupiedEqualsTheColumnWalkOnRandomTrees) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 6; ++trial) {
    octomap::OcTree tree(0.05);
    std::uniform_real_distribution<double> xy(-1.0, 1.0), z(0.0, 2.0);
    for (int i = 0; i < 3000; ++i) {
      const octomap::point3d q(static_cast<float>(xy(rng)), static_cast<float>(xy(rng)), static_cast<float>(z(rng)));
      tree.updateNode(q, rng() % 3 == 0);
    }
    if (trial % 2 == 0) tree.prune();  // leaves larger than a voxel
    MapParams p;
    p.fill_unknown_below = false;
    p.block_m = 0.5;
    p.margin_m = 0.5;
    const GridConversion g = to_grid(tree, {{0.0, 0.0}}, p);
    ASSERT_TRUE(g.grid) << g.error;
    const OccupancyGrid expected = fill_reference(tree, *g.grid);
    OccupancyGrid fast = *g.grid;
    const std::int64_t marked = fill_unknown_below_occupied(tree, fast);
    EXPECT_EQ(marked, expected.count() - g.grid->count());
    EXPECT_GT(marked, 0);
    EXPECT_EQ(fast.words(), expected.words()) << "trial " << trial;
  }
}

TEST(PlannerMessages, OctomapRefusals) {
  MapParams p;
  const octomap_t good = map_msg(column_tree(1.0, 1.0), 1);
  octomap_t m = good;
  m.frame_id = "odom";
  EXPECT_NE(decode_octomap(m, "world", p).error.find("frame_id"), std::string::npos);
  m = good;
  m.resolution_m = 0.1;
  EXPECT_NE(decode_octomap(m, "world", p).error.find("resolution"), std::string::npos);
  m = good;
  m.num_bytes += 1;
  EXPECT_NE(decode_octomap(m, "world", p).error.find("num_bytes"), std::string::npos);
  m = good;
  m.tree_type = "ColorOcTree";
  EXPECT_NE(decode_octomap(m, "world", p).error.find("tree_type"), std::string::npos);
  p.max_bytes = 10;
  EXPECT_NE(decode_octomap(good, "world", p).error.find("limit"), std::string::npos);
  // A grid far too large for the limit.
  MapParams small;
  small.max_voxels = 1000;
  const auto t = decode_octomap(good, "world", MapParams{});
  ASSERT_TRUE(t.tree);
  EXPECT_NE(to_grid(*t.tree, {{0.0, 0.0}}, small).error.find("voxels"), std::string::npos);
}

TEST(PlannerMessages, TheTreeStreamIsCheckedBeforeOctomapReadsIt) {
  const octomap_t good = map_msg(column_tree(1.0, 1.0), 1);
  const std::vector<std::uint8_t>& d = good.data;
  EXPECT_EQ(octree_binary_problem(d.data(), d.size()), "");
  // Every truncation ends inside a node (OctoMap's reader would go on with bytes it never read).
  for (std::size_t n = 0; n < d.size(); ++n) {
    const std::string why = octree_binary_problem(d.data(), n);
    ASSERT_NE(why.find("ends inside a node"), std::string::npos) << n << ": " << why;
  }
  std::vector<std::uint8_t> longer = d;
  longer.push_back(0);
  EXPECT_NE(octree_binary_problem(longer.data(), longer.size()).find("1 bytes after"), std::string::npos);
  // Inner nodes all the way down: deeper than an OcTree can be.
  const std::vector<std::uint8_t> deep(64, 0xff);
  EXPECT_NE(octree_binary_problem(deep.data(), deep.size()).find("deeper than 16 levels"), std::string::npos);
  // The message: a truncated stream and the full format are refused before OctoMap reads them.
  octomap_t m = good;
  m.data.resize(m.data.size() - 3);
  m.num_bytes = static_cast<std::int32_t>(m.data.size());
  EXPECT_NE(decode_octomap(m, "world", MapParams{}).error.find("ends inside a node"), std::string::npos);
  m = good;
  m.binary = false;
  EXPECT_NE(decode_octomap(m, "world", MapParams{}).error.find("binary"), std::string::npos);
  EXPECT_TRUE(decode_octomap(good, "world", MapParams{}).tree);
}

TEST(PlannerMessages, StreamsTheCheckPassesAreReadByOctomapToTheirLastByte) {
  // The check against OctoMap's own reader: a mutated stream the check accepts is one OctoMap
  // reads exactly to its end (no byte short, none left), giving a tree.
  std::mt19937 rng(23);
  const octomap_t good = map_msg(column_tree(1.0, 1.0), 1);
  int accepted = 0;
  for (int i = 0; i < 2000; ++i) {
    std::vector<std::uint8_t> d = good.data;
    for (int k = 0; k < 1 + i % 4; ++k) d[rng() % d.size()] = static_cast<std::uint8_t>(rng());
    if (i % 5 == 0) d.resize(rng() % (d.size() + 1));
    if (!octree_binary_problem(d.data(), d.size()).empty()) continue;
    ++accepted;
    std::istringstream in(std::string(reinterpret_cast<const char*>(d.data()), d.size()));
    octomap::OcTree tree(0.05);
    tree.readBinaryData(in);
    ASSERT_FALSE(in.fail()) << "mutation " << i;
    EXPECT_EQ(in.peek(), std::char_traits<char>::eof()) << "mutation " << i;
  }
  EXPECT_GT(accepted, 100);
}

TEST(PlannerMessages, RandomOctomapStreamsAreDecodedOrRefusedNeverCrash) {
  std::mt19937 rng(5);
  MapParams p;
  p.max_voxels = 2e6;
  const octomap_t good = map_msg(column_tree(1.0, 1.0), 1);
  int decoded = 0;
  for (int i = 0; i < 300; ++i) {
    octomap_t m = good;
    if (i % 3 == 0) {  // random bytes
      m.data.resize(rng() % 512);
      for (auto& b : m.data) b = static_cast<std::uint8_t>(rng());
    } else {  // a valid stream with bytes flipped or cut
      for (int k = 0; k < 1 + i % 5; ++k) m.data[rng() % m.data.size()] = static_cast<std::uint8_t>(rng());
      if (i % 3 == 2) m.data.resize(rng() % m.data.size());
    }
    m.binary = i % 7 != 0;
    m.num_bytes = static_cast<std::int32_t>(m.data.size());
    const TreeConversion t = decode_octomap(m, "world", p);
    if (!t.tree) {
      EXPECT_FALSE(t.error.empty());
      continue;
    }
    ++decoded;
    const GridConversion g = to_grid(*t.tree, {{0.0, 0.0}}, p);
    EXPECT_TRUE(g.grid.has_value() || !g.error.empty());
  }
  EXPECT_GT(decoded, 0);
}

TEST(PlannerMessages, GoalAndStateChecks) {
  plan_goal_t g{};
  g.frame_id = "world";
  g.goal_id = 3;
  g.x_m = 8.0;
  g.has_arm = true;
  g.num_joints = 6;
  g.q_rad = {0.0, 0.6, -0.9, 0.0, 0.5, 0.0};
  GoalConversion c = to_goal(g, "world");
  ASSERT_TRUE(c.goal) << c.error;
  EXPECT_TRUE(c.goal->spec.arm_q_rad.has_value());
  EXPECT_LT(c.goal->spec.position_tolerance_m, 0.0);  // planner default
  g.num_joints = 5;
  EXPECT_FALSE(to_goal(g, "world").goal);
  g.num_joints = 6;
  g.x_m = std::nan("");
  EXPECT_FALSE(to_goal(g, "world").goal);
  g.x_m = 1.0;
  g.frame_id = "odom";
  EXPECT_NE(to_goal(g, "world").error.find("frame_id"), std::string::npos);

  robot_state_t s{};
  s.frame_id = "world";
  s.num_joints = 6;
  s.q_rad.assign(6, 0.1);
  s.qd_radps.assign(6, 0.0);
  s.pose_valid = s.arm_valid = true;
  StateConversion st = to_measured_state(s, "world", 42);
  ASSERT_TRUE(st.state);
  EXPECT_TRUE(st.state->valid);
  EXPECT_EQ(st.state->utime, 42);
  s.arm_valid = false;
  EXPECT_FALSE(to_measured_state(s, "world", 42).state->valid);
  s.qd_radps.resize(2);
  EXPECT_FALSE(to_measured_state(s, "world", 42).state);
}

/// The node on memq://: everything it publishes is collected by handling the same bus.
class NodeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    config_ = load_planner_config(shipped());
    config_.payload_id = "t_bar";
    bus_.subscribe(channels::kTrajectory, [this](const minco_trajectory_t& m) { trajectories_.push_back(m); });
    bus_.subscribe(channels::kPlannerStatus, [this](const planner_status_t& m) { statuses_.push_back(m); });
    node_ = std::make_unique<PlannerNode>(bus_, config_, runtime::wall_utime);
    node_->start();
  }
  void TearDown() override { node_->stop(); }
  void publish_state() {
    robot_state_t s{};
    s.utime = runtime::wall_utime();
    s.frame_id = "world";
    s.num_joints = 6;
    s.q_rad = {0.0, 0.6, -0.9, 0.0, 0.5, 0.0};
    s.qd_radps.assign(6, 0.0);
    s.pose_valid = s.arm_valid = s.base_valid = true;
    bus_.publish(channels::kRobotState, s);
  }
  void publish_goal(std::int64_t id) {
    plan_goal_t g{};
    g.utime = runtime::wall_utime();
    g.goal_id = id;
    g.frame_id = "world";
    g.x_m = 6.0;
    bus_.publish(channels::kPlanGoal, g);
  }
  /// Handles the bus until `done` or timeout_s; returns done().
  template <class F>
  bool spin_until(F done, double timeout_s) {
    const double end = runtime::mono_s() + timeout_s;
    while (runtime::mono_s() < end) {
      bus_.handle_timeout(20);
      if (done()) return true;
    }
    return false;
  }
  PlannerConfig config_;
  LcmBus bus_{"memq://"};
  std::unique_ptr<PlannerNode> node_;
  std::vector<minco_trajectory_t> trajectories_;
  std::vector<planner_status_t> statuses_;
};

TEST_F(NodeTest, PlansAGoalFromRobotStateOnTheLatestMap) {
  publish_state();
  bus_.publish(channels::kMapOctomap, map_msg(column_tree(3.0, 1.5), runtime::wall_utime()));
  ASSERT_TRUE(spin_until([&] { return node_->stats().maps_received == 1 && node_->idle(); }, 30.0));
  publish_state();
  publish_goal(11);
  // LCM handling goes on while the worker plans: ROBOT_STATE keeps being taken, maps arrive at
  // 2 Hz as from a mapper (the newest is kept, older ones are dropped).
  double next_map_s = runtime::mono_s();
  const bool done = spin_until(
      [&] {
        publish_state();
        if (runtime::mono_s() >= next_map_s) {
          bus_.publish(channels::kMapOctomap, map_msg(column_tree(3.0, 1.5), runtime::wall_utime()));
          next_map_s += 0.5;
        }
        return !trajectories_.empty() && !statuses_.empty() &&
               statuses_.back().state == planner_status_t::STATE_SUCCEEDED;
      },
      60.0);
  ASSERT_TRUE(done) << (statuses_.empty() ? "no status" : statuses_.back().failure_reason);
  const minco_trajectory_t& t = trajectories_.back();
  EXPECT_EQ(t.frame_id, "world");
  EXPECT_EQ(t.payload_id, "t_bar");
  EXPECT_GE(t.num_pieces, 1);
  const planner_status_t& s = statuses_.back();
  EXPECT_EQ(s.goal_id, 11);
  EXPECT_EQ(s.plan_id, t.plan_id);
  ASSERT_GE(s.num_stages, 3);
  EXPECT_EQ(s.stage_name[1], "front_end");
  EXPECT_GT(s.total_time_s, 0.0);
  EXPECT_GT(s.trajectory_duration_s, 1.0);
}

TEST_F(NodeTest, RefusesAStaleMapOnPlannerStatus) {
  publish_state();
  bus_.publish(channels::kMapOctomap, map_msg(column_tree(3.0, 1.5), runtime::wall_utime() - 10'000'000));
  ASSERT_TRUE(spin_until([&] { return node_->stats().maps_received == 1 && node_->idle(); }, 30.0));
  publish_state();
  publish_goal(12);
  ASSERT_TRUE(spin_until([&] { return !statuses_.empty() && statuses_.back().goal_id == 12; }, 30.0));
  EXPECT_EQ(statuses_.back().state, planner_status_t::STATE_NO_MAP);
  EXPECT_NE(statuses_.back().failure_reason.find("old"), std::string::npos) << statuses_.back().failure_reason;
  EXPECT_TRUE(trajectories_.empty());
}

TEST_F(NodeTest, AMalformedGoalIsRefusedAtOnce) {
  plan_goal_t g{};
  g.goal_id = 13;
  g.frame_id = "odom";
  bus_.publish(channels::kPlanGoal, g);
  ASSERT_TRUE(spin_until([&] { return !statuses_.empty(); }, 5.0));
  EXPECT_EQ(statuses_.back().state, planner_status_t::STATE_FAILED);
  EXPECT_NE(statuses_.back().failure_reason.find("frame_id"), std::string::npos);
  EXPECT_EQ(node_->stats().goals_refused, 1u);
}

}  // namespace
}  // namespace porter::planner_app

// Every number of the shipped file replaced by hostile values: NaN, infinities and 1e300 are
// refused naming the file; 0, -1, 1e-300, 1e9 load or are refused, never crash
// (tests/support/hostile_config.hpp).
TEST(PlannerConfigHostile, EveryNumberIsRangeChecked) {
  const int replaced = porter::test::check_hostile_numbers("planner/porter_planner.yaml", [](const std::string& f) { porter::planner_app::load_planner_config(f); });
  EXPECT_GE(replaced, 11 * 18);
}
