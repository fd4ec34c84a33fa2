#include "porter/livox_sim/scripted_motion.hpp"

#include <algorithm>
#include <cmath>

#include "porter/livox_sim/state_history.hpp"

namespace porter::livox::sim {

ScriptedMotion::ScriptedMotion(std::vector<Waypoint> waypoints, bool loop)
    : waypoints_(std::move(waypoints)), loop_(loop) {}

double ScriptedMotion::duration_s() const {
  return waypoints_.empty() ? 0.0 : waypoints_.back().t_s - waypoints_.front().t_s;
}

RobotConfiguration ScriptedMotion::at(double t_s) const {
  if (waypoints_.empty()) return {};
  const double t0 = waypoints_.front().t_s;
  const double span = duration_s();
  if (loop_ && span > 0.0 && t_s > t0) t_s = t0 + std::fmod(t_s - t0, span);
  if (t_s <= t0) return waypoints_.front().config;
  if (t_s >= waypoints_.back().t_s) return waypoints_.back().config;
  const auto it = std::upper_bound(waypoints_.begin(), waypoints_.end(), t_s,
                                   [](double t, const Waypoint& w) { return t < w.t_s; });
  const Waypoint& b = *it;
  const Waypoint& a = *(it - 1);
  return interpolate(a.config, b.config, (t_s - a.t_s) / (b.t_s - a.t_s));
}

}  // namespace porter::livox::sim
