#include "planner_messages.hpp"

#include <octomap/AbstractOcTree.h>
#include <octomap/OcTree.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>

#include "porter/msg/trajectory_msg.hpp"
#include "porter/planner/collision/octomap_grid.hpp"

namespace porter::planner_app {
namespace {

bool finite(double v) { return std::isfinite(v); }

double floor_to(double v, double block) { return std::floor(v / block) * block; }
double ceil_to(double v, double block) { return std::ceil(v / block) * block; }

}  // namespace

GoalConversion to_goal(const plan_goal_t& msg, const std::string& frame_id) {
  GoalConversion c;
  if (msg.frame_id != frame_id) {
    c.error = "frame_id '" + msg.frame_id + "', expected '" + frame_id + "'";
    return c;
  }
  if (!finite(msg.x_m) || !finite(msg.y_m) || !finite(msg.yaw_rad)) {
    c.error = "x_m, y_m, yaw_rad must be finite";
    return c;
  }
  if (msg.num_joints < 0 || static_cast<std::size_t>(msg.num_joints) != msg.q_rad.size()) {
    c.error = "num_joints " + std::to_string(msg.num_joints) + " disagrees with q_rad's length " +
              std::to_string(msg.q_rad.size());
    return c;
  }
  if (!finite(msg.position_tolerance_m) || !finite(msg.yaw_tolerance_rad)) {
    c.error = "position_tolerance_m and yaw_tolerance_rad must be finite";
    return c;
  }
  planner_daemon::Goal g;
  g.goal_id = msg.goal_id;
  g.spec.base.x_m = msg.x_m;
  g.spec.base.y_m = msg.y_m;
  g.spec.base.yaw_rad = std::remainder(msg.yaw_rad, 2.0 * M_PI);
  g.spec.position_tolerance_m = msg.position_tolerance_m > 0.0 ? msg.position_tolerance_m : -1.0;
  g.spec.yaw_tolerance_rad = msg.yaw_tolerance_rad > 0.0 ? msg.yaw_tolerance_rad : -1.0;
  if (msg.has_arm) {
    if (msg.num_joints != kNumArmJoints) {
      c.error = "has_arm with num_joints " + std::to_string(msg.num_joints) + ", expected " +
                std::to_string(kNumArmJoints);
      return c;
    }
    JointVector q;
    for (int j = 0; j < kNumArmJoints; ++j) {
      if (!finite(msg.q_rad[static_cast<std::size_t>(j)])) {
        c.error = "q_rad[" + std::to_string(j) + "] is not finite";
        return c;
      }
      q[j] = msg.q_rad[static_cast<std::size_t>(j)];
    }
    g.spec.arm_q_rad = q;
  }
  c.goal = g;
  c.payload_id = msg.payload_id;
  return c;
}

StateConversion to_measured_state(const robot_state_t& msg, const std::string& frame_id, std::int64_t receive_utime) {
  StateConversion c;
  if (msg.frame_id != frame_id) {
    c.error = "ROBOT_STATE frame_id '" + msg.frame_id + "', expected '" + frame_id + "'";
    return c;
  }
  if (msg.num_joints < 0 || static_cast<std::size_t>(msg.num_joints) != msg.q_rad.size() ||
      msg.q_rad.size() != msg.qd_radps.size()) {
    c.error = "ROBOT_STATE num_joints " + std::to_string(msg.num_joints) + " disagrees with q_rad/qd_radps";
    return c;
  }
  if (!finite(msg.x_m) || !finite(msg.y_m) || !finite(msg.yaw_rad)) {
    c.error = "ROBOT_STATE pose is not finite";
    return c;
  }
  planner_daemon::MeasuredState s;
  s.utime = receive_utime;
  s.config.base.x_m = msg.x_m;
  s.config.base.y_m = msg.y_m;
  s.config.base.yaw_rad = msg.yaw_rad;
  bool joints_ok = msg.num_joints == kNumArmJoints;
  for (int j = 0; joints_ok && j < kNumArmJoints; ++j) {
    const double q = msg.q_rad[static_cast<std::size_t>(j)];
    joints_ok = finite(q);
    s.config.q_rad[j] = q;
  }
  s.valid = msg.pose_valid && msg.arm_valid && joints_ok;
  c.state = s;
  return c;
}

TreeConversion decode_octomap(const octomap_t& msg, const std::string& frame_id, const MapParams& params) {
  TreeConversion c;
  if (msg.frame_id != frame_id) {
    c.error = "MAP_OCTOMAP frame_id '" + msg.frame_id + "', expected '" + frame_id + "'";
    return c;
  }
  if (!finite(msg.resolution_m) || std::abs(msg.resolution_m - params.resolution_m) > 1e-9) {
    c.error = "MAP_OCTOMAP resolution " + std::to_string(msg.resolution_m) + " m, the planner is built for " +
              std::to_string(params.resolution_m) + " m";
    return c;
  }
  if (msg.tree_type != "OcTree") {
    c.error = "MAP_OCTOMAP tree_type '" + msg.tree_type + "', expected 'OcTree'";
    return c;
  }
  if (msg.num_bytes < 0 || static_cast<std::size_t>(msg.num_bytes) != msg.data.size()) {
    c.error = "MAP_OCTOMAP num_bytes " + std::to_string(msg.num_bytes) + " disagrees with data's length " +
              std::to_string(msg.data.size());
    return c;
  }
  if (msg.data.size() > params.max_bytes) {
    c.error = "MAP_OCTOMAP of " + std::to_string(msg.data.size()) + " bytes exceeds the limit of " +
              std::to_string(params.max_bytes);
    return c;
  }
  if (!msg.binary) {
    // OctoMap's full-format reader trusts the stream as its binary reader does (below);
    // porter-mapper and porter-scene-map publish the binary format only.
    c.error = "MAP_OCTOMAP binary = false (full format) is not accepted; send OctoMap's binary format";
    return c;
  }
  if (std::string why = octree_binary_problem(msg.data.data(), msg.data.size()); !why.empty()) {
    c.error = "MAP_OCTOMAP data: " + why;
    return c;
  }
  std::istringstream stream(std::string(reinterpret_cast<const char*>(msg.data.data()), msg.data.size()));
  std::shared_ptr<octomap::OcTree> tree;
  if (msg.binary) {
    tree = std::make_shared<octomap::OcTree>(msg.resolution_m);
    tree->readBinaryData(stream);
    if (stream.bad()) tree.reset();
  } else {
    std::unique_ptr<octomap::AbstractOcTree> any(octomap::AbstractOcTree::read(stream));
    auto* t = dynamic_cast<octomap::OcTree*>(any.get());
    if (t != nullptr && std::abs(t->getResolution() - params.resolution_m) <= 1e-9) {
      any.release();
      tree.reset(t);
    }
  }
  if (!tree) {
    c.error = "MAP_OCTOMAP data is not a readable OcTree stream of the stated resolution";
    return c;
  }
  c.tree = tree;
  return c;
}

std::string octree_binary_problem(const std::uint8_t* data, std::size_t size) {
  // Each inner node is two bytes of child codes, 2 bits per child (children 1-4, then 5-8):
  // 00 none, 01 occupied leaf, 10 free leaf, 11 inner node whose own two bytes follow, depth
  // first. The walk keeps the number of inner children still to read per depth.
  std::vector<int> pending{1};  // the root
  std::size_t pos = 0;
  while (!pending.empty()) {
    if (pending.back() == 0) {
      pending.pop_back();
      continue;
    }
    --pending.back();
    if (pending.size() > static_cast<std::size_t>(kOctreeMaxDepth)) {
      return "an inner node deeper than " + std::to_string(kOctreeMaxDepth) + " levels at byte " + std::to_string(pos);
    }
    if (size - pos < 2) return "the tree stream ends inside a node at byte " + std::to_string(pos) + " of " + std::to_string(size);
    int inner = 0;
    for (int b = 0; b < 2; ++b)
      for (int child = 0; child < 4; ++child) inner += ((data[pos + b] >> (2 * child)) & 3u) == 3u;
    pos += 2;
    pending.push_back(inner);
  }
  if (pos != size) return std::to_string(size - pos) + " bytes after the end of the tree stream";
  return "";
}

GridConversion to_grid(const octomap::OcTree& tree, const std::vector<Eigen::Vector2d>& keep_W, const MapParams& params,
                       const Eigen::Vector2d* robot_W) {
  GridConversion c;
  Eigen::AlignedBox3d box;
  if (tree.size() > 0) {
    double x0, y0, z0, x1, y1, z1;
    tree.getMetricMin(x0, y0, z0);
    tree.getMetricMax(x1, y1, z1);
    box.extend(Eigen::Vector3d(x0, y0, 0.0));
    box.extend(Eigen::Vector3d(x1, y1, z1));
  }
  for (const auto& p : keep_W) {
    box.extend(Eigen::Vector3d(p.x() - params.margin_m, p.y() - params.margin_m, 0.0));
    box.extend(Eigen::Vector3d(p.x() + params.margin_m, p.y() + params.margin_m, params.min_height_m));
  }
  if (box.isEmpty() || !box.min().allFinite() || !box.max().allFinite()) {
    c.error = "an empty map and nothing to cover";
    return c;
  }
  Eigen::Vector3d lo = box.min(), hi = box.max();
  lo.z() = 0.0;
  hi.z() = std::max(hi.z(), params.min_height_m);
  for (int a = 0; a < 2; ++a) {
    lo[a] = floor_to(lo[a], params.block_m);
    hi[a] = ceil_to(hi[a], params.block_m);
  }
  hi.z() = ceil_to(hi.z(), params.block_m);
  const Eigen::Vector3d cells = (hi - lo) / params.resolution_m;
  const double voxels = cells.x() * cells.y() * cells.z();
  if (!(voxels <= params.max_voxels)) {
    c.error = "the map needs a grid of " + std::to_string(voxels) + " voxels, limit " +
              std::to_string(params.max_voxels);
    return c;
  }
  c.grid = planner::occupancy_from_octomap(tree, Eigen::AlignedBox3d(lo, hi));
  if (params.fill_unknown_below) fill_unknown_below_occupied(tree, *c.grid, robot_W, params.fill_clear_radius_m);
  return c;
}

std::int64_t fill_unknown_below_occupied(const octomap::OcTree& tree, OccupancyGrid& grid, const Eigen::Vector2d* robot_W,
                                         double clear_radius_m) {
  // The voxels the tree knows as free, on the grid (leaves may be larger than a voxel).
  const double res = grid.resolution_m();
  const Eigen::Vector3i& n = grid.dims();
  const Eigen::Vector3d& lo = grid.origin_W();
  OccupancyGrid free_W(lo, res, n);
  planner::mark_octomap_leaves(tree, /*occupied=*/false, free_W);
  // Known free within kFillGapVoxels on both sides along x, or along y.
  auto gap = [&](int x, int y, int z) {
    auto side = [&](int dx, int dy) {
      for (int k = 1; k <= kFillGapVoxels; ++k)
        if (free_W.occupied(x + k * dx, y + k * dy, z)) return true;
      return false;
    };
    return (side(1, 0) && side(-1, 0)) || (side(0, 1) && side(0, -1));
  };
  // Columns holding an occupied voxel (x + nx * y): the OR of the grid's z layers, a word at a
  // time. Only those can be filled; most columns of a map hold none (the walk below cost ~0.2 s
  // on a 480 x 480 x 80 grid when it visited every voxel).
  const std::int64_t layer_bits = static_cast<std::int64_t>(n.x()) * n.y();
  std::vector<std::uint64_t> column((static_cast<std::size_t>(layer_bits) + 63) / 64, 0);
  const std::vector<std::uint64_t>& words = grid.words();
  for (int z = 0; z < n.z(); ++z) {
    const std::int64_t first = layer_bits * z;
    const int shift = static_cast<int>(first & 63);
    const std::size_t w0 = static_cast<std::size_t>(first >> 6);
    for (std::size_t k = 0; k < column.size(); ++k) {
      // Bits [first + 64 k, first + 64 k + 64) of the grid; past the layer's end they belong to
      // the next layer and are masked off below.
      std::uint64_t v = words[w0 + k] >> shift;
      if (shift != 0 && w0 + k + 1 < words.size()) v |= words[w0 + k + 1] << (64 - shift);
      column[k] |= v;
    }
  }
  if (layer_bits % 64 != 0) column.back() &= (std::uint64_t{1} << (layer_bits % 64)) - 1;
  std::int64_t marked = 0;
  for (int y = 0; y < n.y(); ++y)
    for (int x = 0; x < n.x(); ++x) {
      const std::int64_t c = x + static_cast<std::int64_t>(n.x()) * y;
      if (((column[static_cast<std::size_t>(c >> 6)] >> (c & 63)) & 1u) == 0) continue;
      if (robot_W != nullptr && (grid.voxel_center_W(x, y, 0).head<2>() - *robot_W).norm() < clear_radius_m) continue;
      bool below_obstacle = false;
      for (int z = n.z() - 1; z >= 0; --z) {
        if (grid.occupied(x, y, z)) {
          below_obstacle = true;
        } else if (free_W.occupied(x, y, z) || (below_obstacle && gap(x, y, z))) {
          below_obstacle = false;
        } else if (below_obstacle) {
          grid.set(x, y, z);
          ++marked;
        }
      }
    }
  return marked;
}

planner_status_t make_status(const planner_daemon::Report& r, std::int64_t utime) {
  planner_status_t m;
  m.utime = utime;
  m.goal_id = r.goal_id;
  m.plan_id = r.plan_id;
  m.state = static_cast<std::int8_t>(r.state);
  // The message keeps the cause for the states that need one (FAILED, NO_MAP, NO_STATE,
  // REPLANNING); a success's note goes only to the log.
  const bool cause = r.state == planner_daemon::GoalLoopState::kFailed || r.state == planner_daemon::GoalLoopState::kNoMap ||
                     r.state == planner_daemon::GoalLoopState::kNoState ||
                     r.state == planner_daemon::GoalLoopState::kReplanning;
  m.failure_reason = cause ? r.reason : "";
  m.num_stages = static_cast<std::int32_t>(r.stages.size());
  for (const auto& s : r.stages) {
    m.stage_name.push_back(s.name);
    m.stage_status.push_back(s.status);
    m.stage_time_s.push_back(s.time_s);
    m.stage_iterations.push_back(s.iterations);
  }
  m.total_time_s = r.total_s;
  m.trajectory_duration_s = r.duration_s;
  m.min_clearance_m = -1.0;
  return m;
}

minco_trajectory_t make_trajectory(const planner_daemon::Publication& p, const std::string& frame_id,
                                   const std::string& payload_id, std::int64_t utime) {
  minco_trajectory_t m = to_msg(p.trajectory, p.start_utime, p.plan_id, frame_id, payload_id);
  m.utime = utime;
  return m;
}

}  // namespace porter::planner_app
