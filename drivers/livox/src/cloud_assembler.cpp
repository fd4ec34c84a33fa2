#include "porter/livox/cloud_assembler.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace porter::livox {

void Cloud::clear() {
  start_ns = 0;
  period_index = 0;
  scan_id = 0;
  time_type = 0;
  x_m.clear();
  y_m.clear();
  z_m.clear();
  intensity.clear();
  time_offset_ns.clear();
  line.clear();
  tag.clear();
}

std::int64_t period_index(std::int64_t t_ns, std::int64_t period_ns) {
  std::int64_t q = t_ns / period_ns;
  if (t_ns % period_ns != 0 && t_ns < 0) --q;
  return q;
}

CloudAssembler::CloudAssembler(const CloudAssemblerParams& params)
    : params_(params),
      // A packet spans at most 6.5535 ms (time_interval is 16 bits of 0.1 us), so with periods of
      // 10 ms or more no packet touches more than two clouds.
      period_ns_(std::max<std::int64_t>(10000000, std::llround(params.period_s * 1e9))),
      R_(params.T_out_sensor.linear().cast<float>()),
      t_(params.T_out_sensor.translation().cast<float>()) {
  params_.max_points = std::max<std::size_t>(1, params_.max_points);
}

std::int64_t CloudAssembler::current_end_ns() const {
  return (current_.period_index + 1) * period_ns_;
}

bool CloudAssembler::complete(std::vector<Cloud>& completed) {
  if (current_.size() == 0) return false;
  current_.scan_id = static_cast<std::int64_t>(completed_count_++);
  completed.push_back(std::move(current_));
  current_.clear();
  return true;
}

bool CloudAssembler::flush(std::vector<Cloud>& completed) { return complete(completed); }

std::size_t CloudAssembler::add(const DecodedPacket& packet, std::int64_t first_sample_ns,
                                std::vector<Cloud>& completed) {
  std::size_t done = 0;
  for (std::size_t i = 0; i < packet.num_points; ++i) {
    const Point& p = packet.points[i];
    if (p.is_no_return() && !params_.keep_no_return) {
      ++no_return_;
      continue;
    }
    const std::int64_t t = first_sample_ns + packet.sample_offset_ns(i);
    const std::int64_t k = period_index(t, period_ns_);
    if (current_.size() > 0 && (k != current_.period_index || t < current_.start_ns)) {
      if (k < current_.period_index || t < current_.start_ns) ++time_steps_;
      if (complete(completed)) ++done;
    }
    if (current_.size() == 0) {
      current_.start_ns = t;
      current_.period_index = k;
      current_.time_type = packet.header.time_type;
    }
    if (current_.size() >= params_.max_points) {
      ++over_capacity_;
      continue;
    }
    const Eigen::Vector3f p_out = R_ * Eigen::Vector3f(p.x_m, p.y_m, p.z_m) + t_;
    current_.x_m.push_back(p_out.x());
    current_.y_m.push_back(p_out.y());
    current_.z_m.push_back(p_out.z());
    current_.intensity.push_back(static_cast<float>(p.reflectivity));
    current_.time_offset_ns.push_back(static_cast<std::int32_t>(
        std::min<std::int64_t>(t - current_.start_ns, period_ns_)));
    current_.line.push_back(static_cast<std::uint8_t>(i % 4));
    current_.tag.push_back(p.tag);
  }
  return done;
}

}  // namespace porter::livox
