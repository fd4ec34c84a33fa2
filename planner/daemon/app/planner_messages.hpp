#pragma once
// porter-planner's adapter between LCM messages and the daemon's types: PLAN_GOAL, ROBOT_STATE
// and MAP_OCTOMAP in (validated: they come from the network), PLANNER_STATUS and TRAJECTORY out.
//
// Thread-safety: reentrant. Failure: the conversions never throw; they return the value or a
// reason naming the field.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "planner_config.hpp"
#include "porter/core/occupancy_grid.hpp"
#include "porter/minco_trajectory_t.hpp"
#include "porter/octomap_t.hpp"
#include "porter/plan_goal_t.hpp"
#include "porter/planner_daemon/goal_loop.hpp"
#include "porter/planner_status_t.hpp"
#include "porter/robot_state_t.hpp"

namespace octomap {
class OcTree;
}

namespace porter::planner_app {

inline constexpr const char* kProcessName = "porter-planner";

struct GoalConversion {
  std::optional<planner_daemon::Goal> goal;
  std::string payload_id;  ///< the message's payload_id ("" = keep the current payload)
  std::string error;
};
/// Checks frame_id, finiteness, the arm's joint count (has_arm) and the tolerances (<= 0: the
/// planner's defaults).
GoalConversion to_goal(const plan_goal_t& msg, const std::string& frame_id);

struct StateConversion {
  std::optional<planner_daemon::MeasuredState> state;
  std::string error;
};
/// Checks frame_id, array lengths and finiteness; valid = pose_valid && arm_valid && 6 joints.
/// utime = receive_utime (staleness on the planner's clock).
StateConversion to_measured_state(const robot_state_t& msg, const std::string& frame_id, std::int64_t receive_utime);

struct TreeConversion {
  std::shared_ptr<const octomap::OcTree> tree;
  std::string error;
};
/// Decodes the OctoMap stream of a MAP_OCTOMAP message: frame, resolution (must equal
/// `params.resolution_m`), tree type "OcTree", num_bytes, size limit, binary format, the
/// stream's structure (octree_binary_problem), then the stream itself.
TreeConversion decode_octomap(const octomap_t& msg, const std::string& frame_id, const MapParams& params);

/// Levels of an OcTree below its root (OctoMap's 16-bit keys).
inline constexpr int kOctreeMaxDepth = 16;

/// "" when data[0, size) is exactly one OcTree in OctoMap's binary node format (the stream
/// OcTree::readBinaryData reads) of at most kOctreeMaxDepth levels; otherwise why not. OctoMap's
/// reader checks none of this: on a stream that ends inside a node it goes on with child codes it
/// never read (uninitialised), and an ASan build of porter-planner then built subtrees until it
/// was stopped.
std::string octree_binary_problem(const std::uint8_t* data, std::size_t size);

struct GridConversion {
  std::optional<OccupancyGrid> grid;
  std::string error;
};
/// The planning grid of a tree: its bounding box, grown to hold every point of `keep_W` (robot,
/// goal) with params.margin_m, from z = 0 to at least min_height_m, rounded outwards to
/// block_m; refused when it needs more than max_voxels. Occupied: the tree's occupied voxels,
/// and with params.fill_unknown_below the unknown voxels below them (fill_unknown_below_occupied),
/// outside params.fill_clear_radius_m of robot_W (the robot's base position, when known).
GridConversion to_grid(const octomap::OcTree& tree, const std::vector<Eigen::Vector2d>& keep_W, const MapParams& params,
                       const Eigen::Vector2d* robot_W = nullptr);

/// An unknown voxel with space known free within this many voxels on both sides along x, or on
/// both sides along y, is a gap in seen space (e.g. the shadow of the payload's stem), not the
/// unseen part of an obstacle: the fill stops there.
inline constexpr int kFillGapVoxels = 3;

/// Marks as occupied every voxel of `grid` that the tree does not know (neither occupied nor
/// free) and that lies directly below an occupied voxel of the grid, through a run of unknown
/// voxels: in each column, from an occupied voxel down to the first voxel the tree knows as free
/// or that is a gap (kFillGapVoxels), or to the grid's floor. Why: the MID-360 sees -7..52 degrees of elevation and the robot's own
/// arm blocks part of its view, so the lower parts of walls, posts and a deck's front near the
/// robot are often unseen while their upper parts are mapped; an obstacle is taken to continue
/// downwards into what was not seen, never into space seen free (an opening under a deck that
/// rays crossed stays open). Columns within clear_radius_m of robot_W (when given) are left as
/// they are: the robot's own body hides the space it stands in. Returns the number of voxels
/// marked.
std::int64_t fill_unknown_below_occupied(const octomap::OcTree& tree, OccupancyGrid& grid,
                                         const Eigen::Vector2d* robot_W = nullptr, double clear_radius_m = 0.0);

/// PLANNER_STATUS for a report.
planner_status_t make_status(const planner_daemon::Report& report, std::int64_t utime);

/// TRAJECTORY for a publication (utime = publish time).
minco_trajectory_t make_trajectory(const planner_daemon::Publication& p, const std::string& frame_id,
                                   const std::string& payload_id, std::int64_t utime);

}  // namespace porter::planner_app
