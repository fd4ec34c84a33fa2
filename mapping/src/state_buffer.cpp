#include "porter/mapping/state_buffer.hpp"

#include <algorithm>
#include <cmath>

namespace porter::mapping {

namespace {
double wrap_angle(double a) {
  a = std::remainder(a, 2.0 * M_PI);
  return a <= -M_PI ? a + 2.0 * M_PI : a;
}
}  // namespace

RobotConfiguration interpolate_configuration(const RobotConfiguration& a, const RobotConfiguration& b,
                                             double s) {
  RobotConfiguration c;
  c.base.x_m = a.base.x_m + s * (b.base.x_m - a.base.x_m);
  c.base.y_m = a.base.y_m + s * (b.base.y_m - a.base.y_m);
  c.base.yaw_rad = wrap_angle(a.base.yaw_rad + s * wrap_angle(b.base.yaw_rad - a.base.yaw_rad));
  c.q_rad = a.q_rad + s * (b.q_rad - a.q_rad);
  return c;
}

void StateBuffer::add(std::int64_t t_us, const RobotConfiguration& config) {
  if (!samples_.empty() && t_us <= samples_.back().t_us) {
    ++rejected_;
    return;
  }
  samples_.push_back({t_us, config});
  while (samples_.size() > 2 && samples_.front().t_us < t_us - keep_us_) samples_.pop_front();
}

StateBuffer::Lookup StateBuffer::at(std::int64_t t_us, RobotConfiguration& out) const {
  if (samples_.empty()) {
    out = RobotConfiguration{};
    return Lookup::empty;
  }
  if (t_us < samples_.front().t_us) {
    out = samples_.front().config;
    return Lookup::before_first;
  }
  if (t_us > samples_.back().t_us) {
    out = samples_.back().config;
    return Lookup::after_last;
  }
  // First sample at or after t.
  const auto it = std::lower_bound(samples_.begin(), samples_.end(), t_us,
                                   [](const Sample& s, std::int64_t t) { return s.t_us < t; });
  if (it->t_us == t_us || it == samples_.begin()) {
    out = it->config;
    return Lookup::inside;
  }
  const Sample& a = *(it - 1);
  const Sample& b = *it;
  const double s = static_cast<double>(t_us - a.t_us) / static_cast<double>(b.t_us - a.t_us);
  out = interpolate_configuration(a.config, b.config, s);
  return Lookup::inside;
}

}  // namespace porter::mapping
