// porter-mission: sends a scene's goal on PLAN_GOAL to a running stack and follows it to arrival
// or failure, then reports what happened: per-stage planning times of every plan, re-plans and
// brakes, arrival, tracking error of the simulated robot (SIM_TRUTH) against the trajectory being
// executed, the clearance of the executed path itself (every SIM_TRUTH base pose and arm angles
// from the goal on) and of every executed trajectory against the scene's exact geometry
// (planner/validation, FCL). scripts/demo and the integration tests run it.
//
// usage: porter-mission --scene FILE [--lcm-url URL] [--timeout-s T] [--out JSON] [--goal-id N]
//                       [--arrive-m D] [--add-box NAME,CX,CY,CZ,SX,SY,SZ,YAW --add-after-s T]
//   --timeout-s T  give up after T s from the goal (default 120)
//   --out JSON     summary and the recorded paths (executed, planned) for plotting
//   --arrive-m D   arrived when the true base is within D m of the goal after the last
//                  trajectory's end (default 0.3)
//   --add-box      a box (centre, full sizes in m, yaw in rad) that porter-sim adds to the world
//                  (SIM_COMMAND ADD_BOX) T s after the first trajectory has started; it counts as
//                  an obstacle of the scene for every clearance reported
// Each trajectory's clearance is judged over the part that was executed: from its start to the
// next trajectory's start (or its end).
// exit codes: 0 arrived without collision, 1 failed / timed out / collided, 2 bad arguments,
// 3 bad scene, 4 LCM unavailable.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "flat_trajectory.hpp"
#include "porter/channels.hpp"
#include "porter/core/payload_loader.hpp"
#include "porter/core/robot_loader.hpp"
#include "porter/core/scene_loader.hpp"
#include "porter/lcm_bus.hpp"
#include "porter/msg/trajectory_msg.hpp"
#include "porter/pipeline/config_dir.hpp"
#include "porter/runtime/clock.hpp"
#include "porter/runtime/log.hpp"
#include "porter/runtime/stop.hpp"
#include "porter/validation/validator.hpp"

namespace rt = porter::runtime;
using nlohmann::json;

namespace {

struct Executed {
  porter::StampedTrajectory t;
  std::int64_t received_utime = 0;
};

}  // namespace

int main(int argc, char** argv) {
  rt::init_log("porter-mission");
  std::string scene_path, url, out_path;
  double timeout_s = 120.0, arrive_m = 0.3, add_after_s = -1.0;
  std::int64_t goal_id = 1;
  std::string add_box;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i], v = argv[i + 1];
    if (a == "--scene") scene_path = v;
    else if (a == "--lcm-url") url = v;
    else if (a == "--out") out_path = v;
    else if (a == "--timeout-s") timeout_s = std::atof(v.c_str());
    else if (a == "--arrive-m") arrive_m = std::atof(v.c_str());
    else if (a == "--goal-id") goal_id = std::atoll(v.c_str());
    else if (a == "--add-box") add_box = v;
    else if (a == "--add-after-s") add_after_s = std::atof(v.c_str());
    else scene_path.clear(), i = argc;
  }
  porter::sim_command_t box_cmd{};
  if (!add_box.empty()) {
    std::vector<std::string> f;
    std::size_t at = 0;
    for (std::size_t c; (c = add_box.find(',', at)) != std::string::npos; at = c + 1) f.push_back(add_box.substr(at, c - at));
    f.push_back(add_box.substr(at));
    if (f.size() != 8 || !(add_after_s >= 0.0)) scene_path.clear();
    if (f.size() == 8) {
      box_cmd.command = porter::sim_command_t::ADD_BOX;
      box_cmd.target = f[0];
      double* v[] = {&box_cmd.center_x_m, &box_cmd.center_y_m, &box_cmd.center_z_m, &box_cmd.size_x_m,
                     &box_cmd.size_y_m, &box_cmd.size_z_m, &box_cmd.yaw_rad};
      for (int k = 0; k < 7; ++k) *v[k] = std::atof(f[static_cast<std::size_t>(k) + 1].c_str());
      if (!(box_cmd.size_x_m > 0 && box_cmd.size_y_m > 0 && box_cmd.size_z_m > 0)) scene_path.clear();
      box_cmd.source = "porter-mission";
    }
  }
  if (scene_path.empty() || argc % 2 == 0) {
    std::fprintf(stderr, "usage: porter-mission --scene FILE [--lcm-url URL] [--timeout-s T] [--out JSON] "
                         "[--goal-id N] [--arrive-m D] [--add-box NAME,CX,CY,CZ,SX,SY,SZ,YAW --add-after-s T]\n");
    return 2;
  }
  porter::Scene scene;
  porter::RobotModel robot;
  porter::Payload payload;
  try {
    scene = porter::load_scene(scene_path);
    const std::string config = porter::pipeline::find_config_dir();
    robot = porter::load_robot_model(config + "/robots/scout_mini_piper/robot.yaml");
    payload = porter::load_payload(scene.payload_file);
    if (!add_box.empty()) {
      porter::CollisionShape box;
      box.geometry = porter::Box{Eigen::Vector3d(box_cmd.size_x_m, box_cmd.size_y_m, box_cmd.size_z_m)};
      box.T_parent_shape = Eigen::Translation3d(box_cmd.center_x_m, box_cmd.center_y_m, box_cmd.center_z_m) *
                           Eigen::AngleAxisd(box_cmd.yaw_rad, Eigen::Vector3d::UnitZ());
      box.name = box_cmd.target;
      scene.obstacles.push_back(box);
    }
  } catch (const std::exception& e) {
    rt::log_error(e.what());
    return 3;
  }
  rt::install_stop_handlers();
  porter::LcmBus bus(url);
  if (!bus.good()) {
    rt::log_error("LCM unavailable");
    return 4;
  }
  std::vector<Executed> trajectories;
  std::vector<porter::planner_status_t> statuses;
  std::vector<porter::robot_state_t> truth;
  bool have_state = false;
  std::int64_t maps = 0;
  std::string tracker_state;
  bus.subscribe(porter::channels::kRobotState, [&](const porter::robot_state_t& m) {
    have_state = have_state || (m.pose_valid && m.arm_valid);
  });
  bus.subscribe(porter::channels::kMapOctomap, [&](const porter::octomap_t&) { ++maps; }, 2);
  // The planner listens for goals once its heartbeat runs; "idle" once it has taken in the maps.
  bool planner_idle = false;
  bus.subscribe(porter::channels::kHeartbeat, [&](const porter::process_heartbeat_t& m) {
    if (m.process == "porter-planner" && m.status == "idle" && maps > 0) planner_idle = true;
  });
  bus.subscribe(porter::channels::kSimTruth, [&](const porter::robot_state_t& m) { truth.push_back(m); }, 200);
  bus.subscribe(porter::channels::kPlannerStatus, [&](const porter::planner_status_t& m) {
    statuses.push_back(m);
    std::string line = "PLANNER_STATUS goal " + std::to_string(m.goal_id) + " state " + std::to_string(m.state) +
                       " plan " + std::to_string(m.plan_id);
    for (int i = 0; i < m.num_stages; ++i) {
      char b[96];
      std::snprintf(b, sizeof b, " %s %.1f ms (%s)", m.stage_name[i].c_str(), m.stage_time_s[i] * 1e3,
                    m.stage_status[i].c_str());
      line += b;
    }
    if (!m.failure_reason.empty()) line += ": " + m.failure_reason;
    rt::log_info(line);
  });
  bus.subscribe(porter::channels::kTrajectory, [&](const porter::minco_trajectory_t& m) {
    auto r = porter::from_msg(m);
    if (r.value) trajectories.push_back({*r.value, rt::wall_utime()});
  });
  bus.subscribe(porter::channels::kTrackerStatus, [&](const porter::tracker_status_t& m) {
    tracker_state = std::to_string(m.state);
  });

  const double t_wait = rt::mono_s();
  while (!rt::stop_requested() && (!have_state || maps == 0 || !planner_idle) && rt::mono_s() - t_wait < 60.0)
    bus.handle_timeout(50);
  if (!have_state || maps == 0 || !planner_idle) {
    rt::log_error(std::string("no ") +
                  (!have_state ? "valid " + std::string(porter::channels::kRobotState.name())
                   : maps == 0 ? std::string(porter::channels::kMapOctomap.name())
                               : "idle porter-planner " + std::string(porter::channels::kHeartbeat.name())) +
                  " within 60 s");
    return 1;
  }
  rt::log_info("stack ready after " + rt::format_ms(rt::mono_s() - t_wait) + "; sending goal " + std::to_string(goal_id));
  porter::plan_goal_t goal{};
  goal.utime = rt::wall_utime();
  goal.goal_id = goal_id;
  goal.frame_id = "world";
  goal.x_m = scene.goal.base.x_m;
  goal.y_m = scene.goal.base.y_m;
  goal.yaw_rad = scene.goal.base.yaw_rad;
  goal.has_arm = true;
  goal.num_joints = porter::kNumArmJoints;
  for (int j = 0; j < porter::kNumArmJoints; ++j) goal.q_rad.push_back(scene.goal.q_rad[j]);
  goal.payload_id = payload.name;
  bus.publish(porter::channels::kPlanGoal, goal);
  const std::int64_t goal_utime = goal.utime;
  // A planner still taking in its first map (or state) refuses the goal: send it again each second.
  double last_send = rt::mono_s();
  std::size_t refusals_seen = 0;
  int resent = 0;

  std::string outcome = "timeout";
  std::int64_t box_utime = 0;
  const double t0 = rt::mono_s();
  while (!rt::stop_requested() && rt::mono_s() - t0 < timeout_s) {
    bus.handle_timeout(50);
    if (!add_box.empty() && box_utime == 0 && !trajectories.empty() &&
        rt::wall_utime() >= trajectories.front().t.start_utime + static_cast<std::int64_t>(add_after_s * 1e6)) {
      box_cmd.utime = box_utime = rt::wall_utime();
      box_cmd.command_id = 1;
      bus.publish(porter::channels::kSimCommand, box_cmd);
      rt::log_info("SIM_COMMAND ADD_BOX " + box_cmd.target + " sent");
    }
    if (trajectories.empty() && rt::mono_s() - last_send > 1.0) {
      std::size_t refusals = 0;
      for (const auto& s : statuses)
        if (s.goal_id == goal_id && (s.state == porter::planner_status_t::STATE_NO_MAP ||
                                     s.state == porter::planner_status_t::STATE_NO_STATE))
          ++refusals;
      if (refusals > refusals_seen) {
        refusals_seen = refusals;
        goal.utime = rt::wall_utime();
        bus.publish(porter::channels::kPlanGoal, goal);
        last_send = rt::mono_s();
        ++resent;
      }
    }
    bool done = false;
    for (const auto& s : statuses) {
      if (s.goal_id != goal_id) continue;
      if (s.state == porter::planner_status_t::STATE_FAILED && trajectories.empty()) outcome = "failed: " + s.failure_reason, done = true;
      if (s.state == porter::planner_status_t::STATE_IDLE) done = true, outcome = "executed";
      if (s.state == porter::planner_status_t::STATE_FAILED && s.failure_reason.find("gave up") != std::string::npos)
        outcome = "failed: " + s.failure_reason, done = true;
    }
    if (done) break;
  }
  // Let the robot settle on its last command, then judge arrival on the ground truth.
  const double t_settle = rt::mono_s();
  while (rt::mono_s() - t_settle < 1.0) bus.handle_timeout(50);
  const double arrival_s = static_cast<double>(rt::wall_utime() - goal_utime) * 1e-6;
  if (resent > 0) rt::log_info("goal sent " + std::to_string(resent + 1) + " times (refused while the planner had no map or state)");

  // Tracking error: true base position against the trajectory executing at that time.
  double sum2 = 0.0, max_err = 0.0;
  int n_err = 0;
  for (const auto& s : truth) {
    const Executed* active = nullptr;
    for (const auto& e : trajectories)
      if (e.t.start_utime <= s.utime && e.received_utime <= s.utime) active = &e;
    if (!active) continue;
    const double t = static_cast<double>(s.utime - active->t.start_utime) * 1e-6;
    if (t > active->t.trajectory.total_duration_s() + 1.0) continue;
    const auto z = active->t.trajectory.position(t);
    const double e = std::hypot(z[0] - s.x_m, z[1] - s.y_m);
    sum2 += e * e;
    max_err = std::max(max_err, e);
    ++n_err;
  }
  const double rms = n_err ? std::sqrt(sum2 / n_err) : 0.0;
  bool arrived = false;
  double final_error = -1.0;
  if (!truth.empty()) {
    final_error = std::hypot(truth.back().x_m - scene.goal.base.x_m, truth.back().y_m - scene.goal.base.y_m);
    arrived = outcome == "executed" && final_error <= arrive_m;
  }
  // Exact-geometry clearance of each executed trajectory (the part that ran before the next).
  double min_clearance = 1e9;
  std::string closest;
  bool collided = false;
  json plans = json::array();
  for (std::size_t i = 0; i < trajectories.size(); ++i) {
    const auto& tr = trajectories[i].t.trajectory;
    // The executed part: up to the next trajectory's start (it took over there).
    double until = tr.total_duration_s();
    if (i + 1 < trajectories.size())
      until = std::clamp(static_cast<double>(trajectories[i + 1].t.start_utime - trajectories[i].t.start_utime) * 1e-6,
                         0.0, until);
    const auto ft = porter::planner_app::to_flat(tr);
    std::vector<double> ts;
    std::vector<porter::validation::WholeBodyConfig> cs;
    for (double t = 0.0;; t += 0.005) {
      ts.push_back(std::min(t, until));
      cs.push_back(porter::validation::config_at(ft, ts.back()));
      if (t >= until) break;
    }
    const auto report = porter::validation::check_configurations(robot, payload, scene, ts, cs);
    double c = 1e9;
    std::string who;
    for (const auto& o : report.clearances)
      if (o.min_m < c) c = o.min_m, who = o.obstacle;
    collided = collided || report.collision.found;
    if (c < min_clearance) min_clearance = c, closest = who;
    json samples = json::array();
    for (double t = 0.0; t <= tr.total_duration_s(); t += 0.1) {
      const auto z = tr.position(t);
      samples.push_back({z[0], z[1]});
    }
    plans.push_back({{"plan_id", trajectories[i].t.plan_id}, {"start_utime", trajectories[i].t.start_utime},
                     {"duration_s", tr.total_duration_s()}, {"executed_s", until}, {"min_clearance_m", c}, {"closest", who},
                     {"collision", report.collision.found}, {"xy", samples}});
  }
  // Exact-geometry clearance of what the simulated robot really did: every SIM_TRUTH sample from
  // the goal on, at most every 10 ms (base pose and arm angles, the scene's payload in the gripper).
  std::vector<double> truth_t;
  std::vector<porter::validation::WholeBodyConfig> truth_c;
  for (const auto& s : truth) {
    if (s.utime < goal_utime || s.num_joints != porter::kNumArmJoints) continue;
    if (!truth_t.empty() && static_cast<double>(s.utime - goal_utime) * 1e-6 - truth_t.back() < 0.01) continue;
    porter::validation::WholeBodyConfig c;
    c.x_m = s.x_m;
    c.y_m = s.y_m;
    c.yaw_rad = s.yaw_rad;
    for (int j = 0; j < porter::kNumArmJoints; ++j) c.q_rad[j] = s.q_rad[static_cast<std::size_t>(j)];
    truth_t.push_back(static_cast<double>(s.utime - goal_utime) * 1e-6);
    truth_c.push_back(c);
  }
  const auto executed = porter::validation::check_configurations(robot, payload, scene, truth_t, truth_c);
  double executed_clearance = 1e9;
  std::string executed_closest;
  for (const auto& o : executed.clearances)
    if (o.min_m < executed_clearance) executed_clearance = o.min_m, executed_closest = o.obstacle + " by " + o.body;
  collided = collided || executed.collision.found;

  json stat = json::array();
  int replans = 0, brakes = 0;
  for (const auto& s : statuses) {
    if (s.state == porter::planner_status_t::STATE_REPLANNING) {
      s.failure_reason.rfind("braking", 0) == 0 ? ++brakes : ++replans;
    }
    json stages = json::array();
    for (int i = 0; i < s.num_stages; ++i) stages.push_back({{"name", s.stage_name[i]}, {"status", s.stage_status[i]},
                                                              {"ms", s.stage_time_s[i] * 1e3}});
    stat.push_back({{"state", s.state}, {"goal_id", s.goal_id}, {"plan_id", s.plan_id}, {"reason", s.failure_reason},
                    {"total_ms", s.total_time_s * 1e3}, {"stages", stages}});
  }
  json path = json::array();
  for (std::size_t i = 0; i < truth.size(); i += 10) path.push_back({truth[i].x_m, truth[i].y_m, truth[i].yaw_rad});
  const bool ok = arrived && !collided;
  char line[600];
  std::snprintf(line, sizeof line,
                "%s: %s in %.1f s; %zu trajectories (%d re-plans, %d brakes); tracking error RMS %.3f m, max %.3f m "
                "over %d samples; final distance to goal %.3f m; executed path (%d SIM_TRUTH samples) min clearance "
                "%.3f m (%s)%s; planned trajectories min clearance %.3f m (%s)%s",
                ok ? "ARRIVED" : "NOT ARRIVED", outcome.c_str(), arrival_s, trajectories.size(), replans, brakes, rms,
                max_err, n_err, final_error, executed.samples, executed_clearance, executed_closest.c_str(),
                executed.collision.found ? (" COLLISION " + executed.failures.front()).c_str() : "",
                min_clearance, closest.c_str(), collided ? "; COLLISION" : "");
  std::printf("%s\n", line);
  if (!out_path.empty()) {
    json j = {{"scene", scene_path}, {"outcome", outcome}, {"arrived", arrived}, {"collided", collided},
              {"goal_to_end_s", arrival_s}, {"tracking_rms_m", rms}, {"tracking_max_m", max_err},
              {"final_distance_m", final_error}, {"min_clearance_m", min_clearance}, {"closest_obstacle", closest},
              {"executed_min_clearance_m", executed_clearance}, {"executed_closest", executed_closest},
              {"executed_collision", executed.collision.found}, {"executed_samples", executed.samples},
              {"replans", replans}, {"brakes", brakes}, {"box_added", box_utime != 0},
              {"box_added_s", box_utime ? static_cast<double>(box_utime - goal_utime) * 1e-6 : -1.0}, {"statuses", stat}, {"plans", plans}, {"truth_xy_yaw", path},
              {"start", {scene.start.base.x_m, scene.start.base.y_m}}, {"goal", {scene.goal.base.x_m, scene.goal.base.y_m}},
              {"summary", line}};
    std::ofstream(out_path) << j.dump(1);
  }
  return ok ? 0 : 1;
}
