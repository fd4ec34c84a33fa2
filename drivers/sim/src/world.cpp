#include "porter/sim/world.hpp"

#include <algorithm>
#include <cmath>

namespace porter::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;

double wrap_angle(double a) {
  a = std::fmod(a + kPi, 2.0 * kPi);
  if (a < 0) a += 2.0 * kPi;
  return a - kPi;
}

RobotSample interpolate(const RobotSample& a, const RobotSample& b, double t) {
  const double span = b.t_s - a.t_s;
  const double s = span > 0 ? std::clamp((t - a.t_s) / span, 0.0, 1.0) : 1.0;
  RobotSample out;
  out.t_s = t;
  out.config.base.x_m = a.config.base.x_m + s * (b.config.base.x_m - a.config.base.x_m);
  out.config.base.y_m = a.config.base.y_m + s * (b.config.base.y_m - a.config.base.y_m);
  const double dyaw = wrap_angle(b.config.base.yaw_rad - a.config.base.yaw_rad);
  out.config.base.yaw_rad = wrap_angle(a.config.base.yaw_rad + s * dyaw);
  out.config.q_rad = a.config.q_rad + s * (b.config.q_rad - a.config.q_rad);
  out.v_mps = a.v_mps + s * (b.v_mps - a.v_mps);
  out.omega_radps = a.omega_radps + s * (b.omega_radps - a.omega_radps);
  out.qd_radps = a.qd_radps + s * (b.qd_radps - a.qd_radps);
  return out;
}

}  // namespace

const char* to_string(ObstacleStatus status) {
  switch (status) {
    case ObstacleStatus::ok: return "ok";
    case ObstacleStatus::duplicate_name: return "an obstacle with that name exists";
    case ObstacleStatus::not_found: return "no obstacle with that name";
    case ObstacleStatus::invalid: return "invalid box (sizes must be positive and finite, "
                                         "centre and yaw finite, name not empty)";
  }
  return "unknown";
}

World::World(Scene scene, RobotModel robot, double history_s)
    : scene_(std::move(scene)),
      robot_(std::move(robot)),
      history_s_(history_s > 0 ? history_s : 2.0),
      obstacles_(scene_.obstacles) {
  empty_.config = scene_.start;
}

ObstacleStatus World::add_box(const std::string& name, const Eigen::Vector3d& center_W,
                              const Eigen::Vector3d& size_m, double yaw_rad) {
  if (name.empty() || !center_W.allFinite() || !size_m.allFinite() || !std::isfinite(yaw_rad) ||
      (size_m.array() <= 0.0).any()) {
    return ObstacleStatus::invalid;
  }
  for (const CollisionShape& s : obstacles_) {
    if (s.name == name) return ObstacleStatus::duplicate_name;
  }
  CollisionShape box;
  box.geometry = Box{size_m};
  box.T_parent_shape = Eigen::Isometry3d::Identity();
  box.T_parent_shape.linear() =
      Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  box.T_parent_shape.translation() = center_W;
  box.name = name;
  obstacles_.push_back(std::move(box));
  ++version_;
  return ObstacleStatus::ok;
}

ObstacleStatus World::remove_obstacle(const std::string& name) {
  const auto it = std::find_if(obstacles_.begin(), obstacles_.end(),
                               [&](const CollisionShape& s) { return s.name == name; });
  if (name.empty() || it == obstacles_.end()) return ObstacleStatus::not_found;
  obstacles_.erase(it);
  ++version_;
  return ObstacleStatus::ok;
}

void World::record(const RobotSample& sample) {
  if (!history_.empty() && sample.t_s <= history_.back().t_s) {
    history_.back() = sample;
  } else {
    history_.push_back(sample);
  }
  // Keep one sample at or before the window's start so robot_at() interpolates across it.
  const double keep_from = history_.back().t_s - history_s_;
  while (history_.size() > 2 && history_[1].t_s <= keep_from) history_.pop_front();
}

const RobotSample& World::latest() const { return history_.empty() ? empty_ : history_.back(); }

double World::history_start_s() const { return history_.empty() ? 0.0 : history_.front().t_s; }

RobotSample World::robot_at(double t_s) const {
  if (history_.empty()) return empty_;
  if (!(t_s > history_.front().t_s)) {
    RobotSample s = history_.front();
    return s;
  }
  if (t_s >= history_.back().t_s) return history_.back();
  // First sample later than t.
  const auto it = std::upper_bound(history_.begin(), history_.end(), t_s,
                                   [](double t, const RobotSample& s) { return t < s.t_s; });
  return interpolate(*(it - 1), *it, t_s);
}

std::int64_t World::utime_at(double t_s) const {
  return utime_origin_ + static_cast<std::int64_t>(std::llround(t_s * 1e6));
}

}  // namespace porter::sim
