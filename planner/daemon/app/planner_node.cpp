#include "planner_node.hpp"

#include <octomap/OcTree.h>

#include <utility>

#include "porter/channels.hpp"
#include "porter/core/payload.hpp"
#include "porter/core/payload_loader.hpp"
#include "porter/core/robot_loader.hpp"
#include "porter/payload_t.hpp"
#include "porter/runtime/clock.hpp"
#include "porter/runtime/log.hpp"

namespace porter::planner_app {

namespace rt = porter::runtime;
using planner_daemon::GoalLoopState;

std::unique_ptr<pipeline::Planner> make_planner(const PlannerConfig& config, const std::string& payload_id) {
  const RobotModel bare = load_robot_model(config.robot_file);
  const RobotModel model =
      payload_id == "none" ? bare : attach_payload(bare, load_payload(config.payloads.at(payload_id)));
  auto planner = std::make_unique<pipeline::Planner>(model, config.settings);
  // The back-end's robot side (per-link SDFs, ~1 s) is built now, not inside the first plan that
  // needs the back-end: a re-plan must finish before its hand-off time.
  planner->prepare_backend();
  return planner;
}

PlannerNode::PlannerNode(LcmBus& bus, PlannerConfig config, std::function<std::int64_t()> clock)
    : bus_(bus), config_(std::move(config)), clock_(std::move(clock)) {
  planner_daemon::GoalLoopParams params = config_.loop;
  params.cancel = &cancel_;
  const double t0 = rt::mono_s();
  loop_ = std::make_unique<planner_daemon::GoalLoop>(make_planner(config_, config_.payload_id), params, clock_);
  payload_id_ = config_.payload_id;
  rt::log_info("planner built for payload " + payload_id_ + " in " + rt::format_ms(rt::mono_s() - t0));

  bus_.subscribe(channels::kRobotState, [this](const robot_state_t& msg) {
    auto c = to_measured_state(msg, config_.frame_id, clock_());
    std::lock_guard<std::mutex> lock(mutex_);
    if (c.state) {
      state_ = c.state;
    } else if (++stats_.states_refused == 1) {
      rt::log_warn("ignored: " + c.error);
    }
  });
  bus_.subscribe(channels::kMapOctomap, [this](const octomap_t& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    ++stats_.maps_received;
    if (map_msg_) ++stats_.maps_dropped;
    map_msg_ = msg;
    wake_.notify_one();
  }, 2);
  bus_.subscribe(channels::kPlanGoal, [this](const plan_goal_t& msg) {
    GoalConversion c = to_goal(msg, config_.frame_id);
    if (!c.goal) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        ++stats_.goals_refused;
      }
      rt::log_warn("goal " + std::to_string(msg.goal_id) + " refused: " + c.error);
      return status(GoalLoopState::kFailed, msg.goal_id, "goal refused: " + c.error);
    }
    std::lock_guard<std::mutex> lock(mutex_);
    ++stats_.goals_received;
    goal_ = std::move(c);
    cancel_.request();  // a new goal supersedes the plan that is running
    wake_.notify_one();
  });
  bus_.subscribe(channels::kPayload, [this](const payload_t& msg) {
    const std::string id = msg.attached ? msg.payload_id : "none";
    if (id != "none" && config_.payloads.count(id) == 0) {
      rt::log_warn("PAYLOAD '" + id + "' refused: not a configured payload (inline meshes are not planned with)");
      return status(GoalLoopState::kFailed, -1, "payload '" + id + "' is not configured");
    }
    std::lock_guard<std::mutex> lock(mutex_);
    payload_request_ = id;
    wake_.notify_one();
  });
}

PlannerNode::~PlannerNode() { stop(); }

void PlannerNode::start() {
  if (!worker_.joinable()) worker_ = std::thread([this] { run(); });
}

void PlannerNode::stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
    cancel_.request();
    wake_.notify_one();
  }
  if (worker_.joinable()) worker_.join();
}

NodeStats PlannerNode::stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return stats_;
}

bool PlannerNode::idle() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return !busy_ && !map_msg_ && !goal_ && !payload_request_;
}

void PlannerNode::status(GoalLoopState state, std::int64_t goal_id, const std::string& reason) {
  planner_daemon::Report r;
  r.state = state;
  r.goal_id = goal_id;
  r.reason = reason;
  bus_.publish(channels::kPlannerStatus, make_status(r, clock_()));
  std::lock_guard<std::mutex> lock(mutex_);
  ++stats_.statuses;
}

void PlannerNode::emit(const planner_daemon::Outcome& o) {
  for (const auto& line : o.log) rt::log_info(line);
  std::uint64_t traj = 0, stat = 0;
  if (o.publication) {
    bus_.publish(channels::kTrajectory, make_trajectory(*o.publication, config_.frame_id,
                                                        payload_id_ == "none" ? "" : payload_id_, clock_()));
    ++traj;
  }
  for (const auto& r : o.reports) {
    bus_.publish(channels::kPlannerStatus, make_status(r, clock_()));
    ++stat;
  }
  std::lock_guard<std::mutex> lock(mutex_);
  stats_.trajectories += traj;
  stats_.statuses += stat;
}

void PlannerNode::set_payload(const std::string& id) {
  if (id == payload_id_) return;
  const double t0 = rt::mono_s();
  try {
    loop_->replace_planner(make_planner(config_, id));
  } catch (const std::exception& e) {
    rt::log_error("payload " + id + ": planner not built: " + e.what());
    return status(GoalLoopState::kFailed, -1, "payload " + id + ": " + e.what());
  }
  payload_id_ = id;
  rt::log_info("planner rebuilt for payload " + id + " in " + rt::format_ms(rt::mono_s() - t0));
}

bool PlannerNode::regrid(const std::optional<planner_daemon::Goal>& goal) {
  if (!tree_) return false;
  std::vector<Eigen::Vector2d> keep;
  std::optional<planner_daemon::MeasuredState> state;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    state = state_;
  }
  if (state) keep.emplace_back(state->config.base.x_m, state->config.base.y_m);
  if (goal) goal_xy_ = Eigen::Vector2d(goal->spec.base.x_m, goal->spec.base.y_m);
  // The last goal stays in the grid: its geometry stays the same from map to map (incremental
  // updates) and a re-plan to that goal finds it inside.
  if (goal_xy_) keep.push_back(*goal_xy_);
  const double t0 = rt::mono_s();
  std::optional<Eigen::Vector2d> robot;
  if (state) robot = Eigen::Vector2d(state->config.base.x_m, state->config.base.y_m);
  GridConversion g = to_grid(*tree_, keep, config_.map, robot ? &*robot : nullptr);
  if (!g.grid) {
    rt::log_warn("map refused: " + g.error);
    status(GoalLoopState::kFailed, goal ? goal->goal_id : -1, "map refused: " + g.error);
    return false;
  }
  const double convert_s = rt::mono_s() - t0;
  grid_bounds_ = g.grid->bounds_W();
  const auto dims = g.grid->dims();
  rt::log_info("map " + std::to_string(dims.x()) + "x" + std::to_string(dims.y()) + "x" + std::to_string(dims.z()) +
               " voxels from " + std::to_string(tree_->size()) + " tree nodes in " + rt::format_ms(convert_s));
  emit(loop_->on_map(*g.grid, tree_utime_));
  return true;
}

std::optional<planner_daemon::MeasuredState> PlannerNode::latest_state() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return state_;
}

void PlannerNode::run() {
  const auto tick = std::chrono::duration<double>(1.0 / config_.tick_hz);
  for (;;) {
    std::optional<octomap_t> map;
    std::optional<GoalConversion> goal;
    std::optional<std::string> payload;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait_for(lock, tick, [this] { return stop_ || map_msg_ || goal_ || payload_request_; });
      if (stop_) return;
      map.swap(map_msg_);
      goal.swap(goal_);
      payload.swap(payload_request_);
      if (goal) cancel_.reset();
      busy_ = true;
    }
    if (payload) set_payload(*payload);
    if (goal && !goal->payload_id.empty()) {
      if (goal->payload_id == "none" || config_.payloads.count(goal->payload_id) > 0) {
        set_payload(goal->payload_id);
      } else {
        status(GoalLoopState::kFailed, goal->goal->goal_id, "payload '" + goal->payload_id + "' is not configured");
        goal.reset();
      }
    }
    if (map) {
      const double t0 = rt::mono_s();
      TreeConversion t = decode_octomap(*map, config_.frame_id, config_.map);
      if (!t.tree) {
        {
          std::lock_guard<std::mutex> lock(mutex_);
          ++stats_.maps_refused;
        }
        rt::log_warn("map " + std::to_string(map->map_id) + " refused: " + t.error);
        status(GoalLoopState::kFailed, -1, "map refused: " + t.error);
      } else {
        tree_ = t.tree;
        tree_utime_ = map->utime;
        rt::log_info("map " + std::to_string(map->map_id) + " decoded (" + std::to_string(map->data.size()) +
                     " bytes) in " + rt::format_ms(rt::mono_s() - t0));
        regrid(goal ? goal->goal : std::nullopt);
      }
    }
    if (goal) {
      // The grid must hold the goal (and the robot): grow it from the last tree when it does not.
      const auto& g = goal->goal->spec.base;
      const bool inside = grid_bounds_ && grid_bounds_->min().x() <= g.x_m - config_.map.margin_m &&
                          grid_bounds_->max().x() >= g.x_m + config_.map.margin_m &&
                          grid_bounds_->min().y() <= g.y_m - config_.map.margin_m &&
                          grid_bounds_->max().y() >= g.y_m + config_.map.margin_m;
      if (!inside && !map) regrid(goal->goal);
      emit(loop_->on_goal(*goal->goal, latest_state()));
    }
    emit(loop_->on_tick(latest_state()));
    std::lock_guard<std::mutex> lock(mutex_);
    busy_ = false;
  }
}

}  // namespace porter::planner_app
