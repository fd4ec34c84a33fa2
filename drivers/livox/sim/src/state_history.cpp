#include "porter/livox_sim/state_history.hpp"

#include <algorithm>
#include <cmath>

namespace porter::livox::sim {
namespace {
constexpr double kPi = 3.14159265358979323846;
double wrap_pi(double a) { return std::remainder(a, 2.0 * kPi); }
}  // namespace

RobotConfiguration interpolate(const RobotConfiguration& a, const RobotConfiguration& b, double s) {
  RobotConfiguration c;
  c.base.x_m = a.base.x_m + s * (b.base.x_m - a.base.x_m);
  c.base.y_m = a.base.y_m + s * (b.base.y_m - a.base.y_m);
  c.base.yaw_rad = a.base.yaw_rad + s * wrap_pi(b.base.yaw_rad - a.base.yaw_rad);
  c.q_rad = a.q_rad + s * (b.q_rad - a.q_rad);
  return c;
}

void StateHistory::add(std::int64_t t_ns, const RobotConfiguration& config) {
  if (!samples_.empty() && t_ns <= samples_.back().t_ns) return;
  samples_.push_back({t_ns, config});
  while (samples_.size() > 2 && samples_.front().t_ns < t_ns - keep_ns_) samples_.pop_front();
}

RobotConfiguration StateHistory::at(std::int64_t t_ns) const {
  if (samples_.empty()) return {};
  if (t_ns <= samples_.front().t_ns) return samples_.front().config;
  if (t_ns >= samples_.back().t_ns) return samples_.back().config;
  // Queries are near the newest samples: search from the back.
  std::size_t i = samples_.size() - 1;
  while (i > 0 && samples_[i - 1].t_ns > t_ns) --i;
  const Sample& a = samples_[i - 1];
  const Sample& b = samples_[i];
  const double s = static_cast<double>(t_ns - a.t_ns) / static_cast<double>(b.t_ns - a.t_ns);
  return interpolate(a.config, b.config, s);
}

}  // namespace porter::livox::sim
