#include "porter/validation/validator.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

#include "fcl_world.hpp"

namespace porter::validation {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

double wrap(double a) {
  a = std::remainder(a, 2.0 * M_PI);
  return a <= -M_PI ? a + 2.0 * M_PI : a;
}

std::string fmt(double v, int precision = 3) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(precision);
  s << v;
  return s.str();
}

void note_limit(LimitCheck& check, double value, double limit, double t_s, const std::string& where) {
  if (!(limit > 0.0)) return;
  const double ratio = std::abs(value) / limit;
  if (ratio > check.worst_ratio || std::isnan(ratio)) {
    check.worst_ratio = std::isnan(ratio) ? kInf : ratio;
    check.t_s = t_s;
    check.where = where;
    check.value = value;
    check.limit = limit;
  }
}

PoseCheck check_pose(const WholeBodyConfig& c, const RobotConfiguration& want, const ValidationSettings& s) {
  PoseCheck p;
  p.position_error_m = std::hypot(c.x_m - want.base.x_m, c.y_m - want.base.y_m);
  p.yaw_error_rad = std::abs(wrap(c.yaw_rad - want.base.yaw_rad));
  for (int j = 0; j < kNumArmJoints; ++j)
    p.joint_error_rad = std::max(p.joint_error_rad, std::abs(c.q_rad[j] - want.q_rad[j]));
  p.ok = p.position_error_m <= s.pose_tolerance_m && p.yaw_error_rad <= s.pose_tolerance_rad &&
         p.joint_error_rad <= s.pose_tolerance_rad;
  return p;
}

std::string pose_text(const PoseCheck& p) {
  return "position " + fmt(p.position_error_m) + " m, yaw " + fmt(p.yaw_error_rad) + " rad, joints " +
         fmt(p.joint_error_rad) + " rad";
}

// Exact clearance of the placed robot to every obstacle (and the ground) at time t, folded into
// report.clearances (obstacles in order, then the ground) and report.collision. Pairs whose boxes
// are farther apart than the obstacle's best so far are pruned. Returns whether t collides.
template <typename NameOf>
bool check_environment(FclWorld& world, const BodyPoses& poses, double t, const ValidationSettings& settings,
                       const NameOf& name_of, ValidationReport& report) {
  auto& robot = world.robot();
  auto& obstacles = world.obstacles();
  const size_t n_obs = obstacles.size();
  const size_t ground = n_obs;
  bool collided = false;
  for (auto& s : robot) {
    for (size_t j = 0; j < n_obs; ++j) {
      ObstacleClearance& cl = report.clearances[j];
      const double gap = aabb_gap(s.aabb_W, obstacles[j].aabb_W);
      if (gap > 0.0 && gap >= cl.min_m) continue;
      if (gap >= settings.clearance_horizon_m) {
        // A lower bound only where nothing exact is known yet.
        if (!cl.exact || !std::isfinite(cl.min_m)) cl = {cl.obstacle, gap, t, name_of(s.body), false};
        continue;
      }
      const double d = FclWorld::signed_distance(s, obstacles[j]);
      if (d < cl.min_m) cl = {cl.obstacle, d, t, name_of(s.body), true};
      if (d < 0.0) {
        collided = true;
        if (!report.collision.found || (report.collision.t_s == t && -d > report.collision.depth_m))
          report.collision = {true, t, name_of(s.body), s.name, obstacles[j].name, -d, report.collision.samples};
      }
    }
    if (settings.check_ground && s.body != 0) {
      const double z = world.lowest_z_W(s, poses);
      ObstacleClearance& cl = report.clearances[ground];
      if (z < cl.min_m) cl = {cl.obstacle, z, t, name_of(s.body), true};
      if (z < 0.0) {
        collided = true;
        if (!report.collision.found || (report.collision.t_s == t && -z > report.collision.depth_m))
          report.collision = {true, t, name_of(s.body), s.name, "ground", -z, report.collision.samples};
      }
    }
  }
  return collided;
}

}  // namespace

ValidationReport validate_trajectory(const RobotModel& model, const Payload& payload, const Scene& scene,
                                     const FlatTrajectory& trajectory, const ValidationSettings& settings) {
  const auto wall0 = std::chrono::steady_clock::now();
  ValidationReport report;
  report.duration_s = trajectory.duration_s();
  const std::vector<double> times = sample_times(model, payload, trajectory, settings, &report.max_step_m);
  report.samples = static_cast<int>(times.size());

  FclWorld world(model, payload, scene);
  auto& robot = world.robot();
  for (const auto& o : world.obstacles()) report.clearances.push_back({o.name, kInf, 0.0, "", true});
  if (settings.check_ground) report.clearances.push_back({"ground", kInf, 0.0, "", true});

  // Shape pairs checked for self-collision.
  std::vector<std::pair<size_t, size_t>> self_pairs;
  for (size_t a = 0; a < robot.size(); ++a)
    for (size_t b = a + 1; b < robot.size(); ++b)
      if (self_pair_checked(model, robot[a].body, robot[b].body)) self_pairs.emplace_back(a, b);

  const std::string payload_name = payload.name;
  auto name_of = [&](int body) { return body_name(model, payload_name, body); };

  auto named = [](const char* quantity) {
    LimitCheck c;
    c.quantity = quantity;
    return c;
  };
  LimitCheck q_pos = named("joint_position"), q_vel = named("joint_velocity"),
             q_acc = named("joint_acceleration"), w_vel = named("wheel_speed"),
             w_acc = named("wheel_acceleration");
  const BaseLimits& base = model.base;

  for (const double t : times) {
    const WholeBodyConfig config = config_at(trajectory, t);
    const BodyPoses poses = body_poses(model, config);
    world.place(poses);

    const bool collided = check_environment(world, poses, t, settings, name_of, report);
    if (collided) ++report.collision.samples;

    // Self-collision.
    bool self_hit = false;
    for (const auto& [a, b] : self_pairs) {
      if (aabb_gap(robot[a].aabb_W, robot[b].aabb_W) > 0.0) continue;
      const double depth = FclWorld::contact_depth(robot[a], robot[b]);
      if (depth < 0.0) continue;
      self_hit = true;
      auto& sc = report.self_collision;
      if (!sc.found || (sc.t_s == t && depth > sc.depth_m))
        sc = {true, t, name_of(robot[a].body), name_of(robot[b].body), depth, sc.samples};
    }
    if (self_hit) ++report.self_collision.samples;

    // Joint limits.
    const FlatVector zd = trajectory.derivative(t, 1), zdd = trajectory.derivative(t, 2);
    for (int j = 0; j < kNumArmJoints; ++j) {
      const ArmJoint& joint = model.joints[static_cast<size_t>(j)];
      const double mid = 0.5 * (joint.lower_rad + joint.upper_rad);
      const double half = 0.5 * (joint.upper_rad - joint.lower_rad);
      note_limit(q_pos, config.q_rad[j] - mid, half, t, joint.name);
      note_limit(q_vel, zd[2 + j], joint.velocity_max_radps, t, joint.name);
      note_limit(q_acc, zdd[2 + j], joint.acceleration_max_radps2, t, joint.name);
    }
    // Wheel limits, where the heading rate is well defined.
    const PlanarRates r = trajectory.planar_rates(t);
    if (r.speed_mps >= settings.wheel_rates_min_speed_mps && base.wheel_radius_m > 0.0) {
      const double half_track = 0.5 * base.track_width_m;
      const double wl = (r.v_mps - half_track * r.omega_radps) / base.wheel_radius_m;
      const double wr = (r.v_mps + half_track * r.omega_radps) / base.wheel_radius_m;
      const double al = (r.a_mps2 - half_track * r.alpha_radps2) / base.wheel_radius_m;
      const double ar = (r.a_mps2 + half_track * r.alpha_radps2) / base.wheel_radius_m;
      note_limit(w_vel, wl, base.wheel_omega_max_radps, t, "left wheel");
      note_limit(w_vel, wr, base.wheel_omega_max_radps, t, "right wheel");
      note_limit(w_acc, al, base.wheel_alpha_max_radps2, t, "left wheel");
      note_limit(w_acc, ar, base.wheel_alpha_max_radps2, t, "right wheel");
    }
  }

  for (LimitCheck* c : {&q_pos, &q_vel, &q_acc, &w_vel, &w_acc}) {
    c->kept = c->worst_ratio <= 1.0 + settings.limit_tolerance;
    report.limits.push_back(*c);
  }
  report.start = check_pose(config_at(trajectory, 0.0), scene.start, settings);
  report.goal = check_pose(config_at(trajectory, trajectory.duration_s()), scene.goal, settings);

  // Verdict.
  auto& f = report.failures;
  if (report.collision.found)
    f.push_back("collision at t=" + fmt(report.collision.t_s) + " s: " + report.collision.body + " with " +
                report.collision.obstacle + ", depth " + fmt(report.collision.depth_m * 1000.0, 1) + " mm");
  if (report.self_collision.found)
    f.push_back("self-collision at t=" + fmt(report.self_collision.t_s) + " s: " + report.self_collision.body_a +
                " with " + report.self_collision.body_b + ", depth " +
                fmt(report.self_collision.depth_m * 1000.0, 1) + " mm");
  for (const LimitCheck& c : report.limits)
    if (!c.kept)
      f.push_back(c.quantity + " limit exceeded: " + c.where + " at t=" + fmt(c.t_s) + " s, ratio " +
                  fmt(c.worst_ratio));
  if (!report.start.ok) f.push_back("start pose not kept: " + pose_text(report.start));
  if (!report.goal.ok) f.push_back("goal missed: " + pose_text(report.goal));
  if (report.max_step_m > 2.0 * settings.max_step_m)
    f.push_back("trajectory jumps: " + fmt(report.max_step_m) + " m between samples");
  report.valid = f.empty();
  report.time_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wall0).count();
  return report;
}

ValidationReport check_configurations(const RobotModel& model, const Payload& payload, const Scene& scene,
                                      const std::vector<double>& times_s,
                                      const std::vector<WholeBodyConfig>& configs,
                                      const ValidationSettings& settings) {
  const auto wall0 = std::chrono::steady_clock::now();
  ValidationReport report;
  const size_t n = std::min(times_s.size(), configs.size());
  report.samples = static_cast<int>(n);
  report.duration_s = n ? times_s[n - 1] - times_s[0] : 0.0;
  FclWorld world(model, payload, scene);
  for (const auto& o : world.obstacles()) report.clearances.push_back({o.name, kInf, 0.0, "", true});
  if (settings.check_ground) report.clearances.push_back({"ground", kInf, 0.0, "", true});
  const std::string payload_name = payload.name;
  auto name_of = [&](int body) { return body_name(model, payload_name, body); };
  for (size_t i = 0; i < n; ++i) {
    const BodyPoses poses = body_poses(model, configs[i]);
    world.place(poses);
    if (check_environment(world, poses, times_s[i], settings, name_of, report)) ++report.collision.samples;
  }
  if (report.collision.found)
    report.failures.push_back("collision at t=" + fmt(report.collision.t_s) + " s: " + report.collision.body +
                              " with " + report.collision.obstacle + ", depth " +
                              fmt(report.collision.depth_m * 1000.0, 1) + " mm");
  report.valid = report.failures.empty();
  report.time_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wall0).count();
  return report;
}

}  // namespace porter::validation
