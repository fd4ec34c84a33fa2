#pragma once
// porter-planner's node: the LCM subscriptions and the planning worker thread around a
// planner_daemon::GoalLoop. The handling thread (the one that calls LcmBus::handle*) only
// converts messages and puts them in a mailbox; the worker takes them, decodes maps, plans and
// publishes, so LCM handling never waits for a plan. A new goal or a shutdown cancels the plan
// that is running.
//
//   PlannerNode node(bus, config, wall_clock);   // subscribes; builds the Planner (seconds)
//   node.start();                                // the worker thread
//   while (running) bus.handle_timeout(100);
//   node.stop();
//
// Inputs: MAP_OCTOMAP (latest kept; older unprocessed maps are dropped), ROBOT_STATE (latest),
// PLAN_GOAL, PAYLOAD (a configured payload id, or none). Outputs: TRAJECTORY, PLANNER_STATUS.
// Logs every plan, map and refusal with timings (porter::runtime log: this is process code).
//
// Thread-safety: construct, start(), stop() and the bus's handling on one thread; stats() from
// any thread. Failure: the constructor throws porter::LoadError (robot, payload) or
// std::invalid_argument (settings); nothing throws afterwards.

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "planner_config.hpp"
#include "planner_messages.hpp"
#include "porter/lcm_bus.hpp"
#include "porter/planner/deadline.hpp"
#include "porter/planner_daemon/goal_loop.hpp"

namespace porter::planner_app {

/// A Planner for the robot of `config` carrying `payload_id` ("none" = empty gripper). Throws
/// LoadError / std::invalid_argument.
std::unique_ptr<pipeline::Planner> make_planner(const PlannerConfig& config, const std::string& payload_id);

struct NodeStats {
  std::uint64_t maps_received = 0;
  std::uint64_t maps_dropped = 0;    ///< replaced in the mailbox by a newer one before the worker took it
  std::uint64_t maps_refused = 0;    ///< undecodable, wrong frame or resolution, too large
  std::uint64_t goals_received = 0;
  std::uint64_t goals_refused = 0;   ///< malformed (the loop's refusals are in its reports)
  std::uint64_t states_refused = 0;
  std::uint64_t trajectories = 0;    ///< published
  std::uint64_t statuses = 0;        ///< published
};

class PlannerNode {
 public:
  PlannerNode(LcmBus& bus, PlannerConfig config, std::function<std::int64_t()> clock);
  ~PlannerNode();
  PlannerNode(const PlannerNode&) = delete;
  PlannerNode& operator=(const PlannerNode&) = delete;

  void start();
  /// Cancels a running plan and joins the worker. Idempotent.
  void stop();

  NodeStats stats() const;
  /// The worker is idle: no message waiting and no plan running.
  bool idle() const;
  const std::string& payload_id() const { return payload_id_; }

 private:
  void run();
  void emit(const planner_daemon::Outcome& outcome);
  void status(planner_daemon::GoalLoopState state, std::int64_t goal_id, const std::string& reason);
  void set_payload(const std::string& payload_id);
  bool regrid(const std::optional<planner_daemon::Goal>& goal);
  std::optional<planner_daemon::MeasuredState> latest_state() const;

  LcmBus& bus_;
  const PlannerConfig config_;
  std::function<std::int64_t()> clock_;
  planner::CancelFlag cancel_;
  std::unique_ptr<planner_daemon::GoalLoop> loop_;
  std::string payload_id_;

  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::optional<octomap_t> map_msg_;
  std::optional<GoalConversion> goal_;
  std::optional<std::string> payload_request_;
  std::optional<planner_daemon::MeasuredState> state_;
  bool stop_ = false;
  bool busy_ = false;
  NodeStats stats_;

  // Worker-only.
  std::shared_ptr<const octomap::OcTree> tree_;
  std::int64_t tree_utime_ = 0;
  std::optional<Eigen::AlignedBox3d> grid_bounds_;
  std::optional<Eigen::Vector2d> goal_xy_;
  std::thread worker_;
};

}  // namespace porter::planner_app
