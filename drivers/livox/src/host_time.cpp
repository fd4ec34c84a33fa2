#include "porter/livox/host_time.hpp"

#include <algorithm>
#include <cmath>

namespace porter::livox {

HostTimeMapper::HostTimeMapper(HostTimeParams params)
    : params_(params),
      window_ns_(static_cast<std::int64_t>(std::max(0.0, params.window_s) * 1e9)),
      reset_ns_(static_cast<std::int64_t>(std::max(1e-6, params.reset_threshold_s) * 1e9)),
      max_clamp_ns_(static_cast<std::int64_t>(std::max(0.0, params.max_clamp_s) * 1e9)) {}

std::int64_t HostTimeMapper::map(std::uint64_t sensor_first_ns, std::int64_t span_ns,
                                 std::int64_t receive_ns, int stream) {
  const int k = stream == 1 ? 1 : 0;
  const std::int64_t sensor_ns = static_cast<std::int64_t>(sensor_first_ns);
  const std::int64_t sample_offset = receive_ns - (sensor_ns + span_ns);
  // A rebooted sensor restarts its clock near 0: the offset jumps by its uptime.
  const bool jumped = started_ && std::llabs(sample_offset - offset_ns_) > reset_ns_;
  if (!started_ || jumped) {
    if (started_) ++resets_;
    started_ = true;
    bucket_start_ns_ = receive_ns;
    current_min_ = sample_offset;
    have_previous_ = false;
    offset_ns_ = sample_offset;
    have_end_[0] = have_end_[1] = false;  // no clamp across a restart
  } else if (window_ns_ == 0) {
    offset_ns_ = sample_offset;
  } else {
    if (receive_ns - bucket_start_ns_ >= window_ns_) {
      previous_min_ = current_min_;
      have_previous_ = true;
      current_min_ = sample_offset;
      bucket_start_ns_ = receive_ns;
    } else {
      current_min_ = std::min(current_min_, sample_offset);
    }
    offset_ns_ = have_previous_ ? std::min(previous_min_, current_min_) : current_min_;
  }
  std::int64_t first = sensor_ns + offset_ns_;
  if (have_end_[k] && first < last_end_ns_[k]) {
    if (last_end_ns_[k] - first <= max_clamp_ns_) {
      first = last_end_ns_[k];
      ++clamped_;
    } else {
      ++steps_back_;
    }
  }
  have_end_[k] = true;
  last_end_ns_[k] = first + span_ns;
  return first;
}

}  // namespace porter::livox
