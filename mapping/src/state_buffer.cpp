#include "porter/mapping/state_buffer.hpp"

#include <algorithm>
#include <cmath>

namespace porter::mapping {

namespace {
double wrap_angle(double a) {
  a = std::remainder(a, 2.0 * M_PI);
  return a <= -M_PI ? a + 2.0 * M_PI : a;
}

BasePose interpolate_base(const BasePose& a, const BasePose& b, double s) {
  BasePose c;
  c.x_m = a.x_m + s * (b.x_m - a.x_m);
  c.y_m = a.y_m + s * (b.y_m - a.y_m);
  c.yaw_rad = wrap_angle(a.yaw_rad + s * wrap_angle(b.yaw_rad - a.yaw_rad));
  return c;
}

using Lookup = StateBuffer::Lookup;

// Value of a track at t: the interpolation of its samples (Sample has t_us; get(sample) gives
// the value; lerp(a, b, s) interpolates).
template <class Track, class Value, class Get, class Lerp>
Lookup track_at(const Track& track, std::int64_t t_us, Value& out, Get get, Lerp lerp) {
  if (track.empty()) return Lookup::empty;
  if (t_us < track.front().t_us) {
    out = get(track.front());
    return Lookup::before_first;
  }
  if (t_us > track.back().t_us) {
    out = get(track.back());
    return Lookup::after_last;
  }
  // First sample at or after t.
  const auto it = std::lower_bound(track.begin(), track.end(), t_us,
                                   [](const auto& s, std::int64_t t) { return s.t_us < t; });
  if (it->t_us == t_us || it == track.begin()) {
    out = get(*it);
    return Lookup::inside;
  }
  const auto& a = *(it - 1);
  const auto& b = *it;
  const double s = static_cast<double>(t_us - a.t_us) / static_cast<double>(b.t_us - a.t_us);
  out = lerp(get(a), get(b), s);
  return Lookup::inside;
}

}  // namespace

RobotConfiguration interpolate_configuration(const RobotConfiguration& a, const RobotConfiguration& b,
                                             double s) {
  RobotConfiguration c;
  c.base = interpolate_base(a.base, b.base, s);
  c.q_rad = a.q_rad + s * (b.q_rad - a.q_rad);
  return c;
}

void StateBuffer::add(std::int64_t t_us, const RobotConfiguration& config) {
  add_base(t_us, config.base);
  add_arm(t_us, config.q_rad);
}

void StateBuffer::add_base(std::int64_t t_us, const BasePose& base) {
  if (!base_.empty() && t_us <= base_.back().t_us) {
    ++rejected_;
    return;
  }
  base_.push_back({t_us, base});
  while (base_.size() > 2 && base_.front().t_us < t_us - keep_us_) base_.pop_front();
}

bool StateBuffer::add_arm(std::int64_t t_us, const JointVector& q_rad, std::int64_t arrived_us) {
  if (!arm_.empty() && t_us <= arm_.back().t_us) return false;
  arm_.push_back({t_us, q_rad, arrived_us});
  while (arm_.size() > 2 && arm_.front().t_us < t_us - keep_us_) arm_.pop_front();
  return true;
}

StateBuffer::Lookup StateBuffer::at(std::int64_t t_us, RobotConfiguration& out) const {
  out = RobotConfiguration{};
  const Lookup b = track_at(base_, t_us, out.base, [](const BaseSample& s) { return s.base; }, interpolate_base);
  const Lookup a = track_at(
      arm_, t_us, out.q_rad, [](const ArmSample& s) -> JointVector { return s.q_rad; },
      [](const JointVector& x, const JointVector& y, double s) -> JointVector { return x + s * (y - x); });
  return static_cast<Lookup>(std::max(static_cast<int>(a), static_cast<int>(b)));
}

bool StateBuffer::covers(std::int64_t t0_us, std::int64_t t1_us) const {
  if (base_.empty() || arm_.empty()) return false;
  return base_.front().t_us <= t0_us && arm_.front().t_us <= t0_us && base_.back().t_us >= t1_us &&
         arm_.back().t_us >= t1_us;
}

StateBuffer::Cover StateBuffer::covers_by(std::int64_t t0_us, std::int64_t t1_us, std::int64_t deadline_us) const {
  const bool passed = !base_.empty() && base_.back().t_us > deadline_us;
  if (base_.empty() || arm_.empty()) return passed ? Cover::never : Cover::not_yet;
  if (base_.front().t_us > t0_us || arm_.front().t_us > t0_us) return Cover::never;
  const auto b = std::lower_bound(base_.begin(), base_.end(), t1_us,
                                  [](const BaseSample& s, std::int64_t t) { return s.t_us < t; });
  const auto a = std::lower_bound(arm_.begin(), arm_.end(), t1_us,
                                  [](const ArmSample& s, std::int64_t t) { return s.t_us < t; });
  // The base samples come in order: the first one at or after t1 decides for good.
  if (b != base_.end() && b->t_us > deadline_us) return Cover::never;
  if (a != arm_.end() && a->arrived_us > deadline_us) return Cover::never;
  if (b != base_.end() && a != arm_.end()) return Cover::yes;
  return passed ? Cover::never : Cover::not_yet;
}

std::int64_t StateBuffer::oldest_us() const {
  if (base_.empty() || arm_.empty()) return 0;
  return std::max(base_.front().t_us, arm_.front().t_us);
}

std::int64_t StateBuffer::newest_us() const {
  if (base_.empty() || arm_.empty()) return 0;
  return std::min(base_.back().t_us, arm_.back().t_us);
}

}  // namespace porter::mapping
