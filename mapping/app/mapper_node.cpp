#include "mapper_node.hpp"

#include <algorithm>
#include <chrono>

#include "mapper_conversions.hpp"

namespace porter::mapping::app {

MapperNode::MapperNode(const MapperConfig& config, const RobotModel& robot)
    : config_(config), mapper_(robot, config.mapper), states_(config.state_history_s) {}

void MapperNode::on_state(const porter::robot_state_t& msg) {
  StateSample c;
  std::string why;
  const bool ok = to_state_sample(msg, c, why);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!ok) {
      ++counters_.rejected;
      counters_.last_reject = "ROBOT_STATE: " + why;
      return;
    }
    ++counters_.states_received;
    states_.add_base(c.utime, c.base);
    // The arm sample is the newest ARM_STATE porter-state had: repeated until the next comes.
    if (c.has_arm) {
      states_.add_arm(c.arm_utime, c.q_rad, c.utime);
    } else {
      ++counters_.states_without_arm;
    }
  }
  cv_.notify_one();
}

void MapperNode::on_cloud(const porter::point_cloud_t& msg, std::int64_t now_ns) {
  Queued q;
  std::string why;
  bool ok = msg.frame_id == config_.cloud_frame_id;
  if (!ok) why = "frame '" + msg.frame_id + "', expected '" + config_.cloud_frame_id + "'";
  ok = ok && to_sensor_cloud(msg, q.cloud, why);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++counters_.clouds_received;
    if (!ok) {
      ++counters_.rejected;
      counters_.last_reject = "LIDAR_POINTS: " + why;
      return;
    }
    if (have_scan_id_ && msg.scan_id > last_scan_id_ + 1) counters_.lost_upstream += static_cast<std::uint64_t>(msg.scan_id - last_scan_id_ - 1);
    have_scan_id_ = true;
    last_scan_id_ = msg.scan_id;
    if (processing_ || !queue_.empty()) ++counters_.arrived_while_busy;
    q.scan_id = msg.scan_id;
    q.received_ns = now_ns;
    std::int32_t off_min = 0, off_max = 0;
    if (!q.cloud.time_offset_ns.empty()) {
      const auto [lo, hi] = std::minmax_element(q.cloud.time_offset_ns.begin(), q.cloud.time_offset_ns.end());
      off_min = *lo;
      off_max = *hi;
    }
    q.start_us = q.cloud.utime + off_min / 1000;
    q.end_us = q.cloud.utime + off_max / 1000;
    if (static_cast<int>(queue_.size()) >= config_.max_queued_clouds) {
      // The oldest waiting cloud goes: one the state covers was waiting for the worker, one it
      // does not yet cover was waiting for its state.
      const Queued& f = queue_.front();
      if (states_.covers_by(f.start_us, f.end_us, f.end_us + wait_us()) == StateBuffer::Cover::yes) {
        ++counters_.dropped_queue_full;
      } else {
        ++counters_.dropped_no_state;
      }
      queue_.pop_front();
    }
    queue_.push_back(std::move(q));
  }
  cv_.notify_one();
}

bool MapperNode::step(std::int64_t now_ns, std::int64_t wait_ns, StepResult& out) {
  Queued q;
  StateBuffer states;
  {
    std::unique_lock<std::mutex> lock(mutex_);
    // Drops the clouds at the front that the state will not cover; true when the front one is
    // covered. Decided on the states' own time (the state that covers a cloud must come before
    // the states pass its last point by state.wait_s), never on the time messages arrive or are
    // processed: the same messages in the same order give the same clouds integrated.
    const auto ready = [&] {
      while (!queue_.empty()) {
        const Queued& f = queue_.front();
        const StateBuffer::Cover c = states_.covers_by(f.start_us, f.end_us, f.end_us + wait_us());
        if (c == StateBuffer::Cover::yes) return true;
        if (c == StateBuffer::Cover::not_yet) return false;
        queue_.pop_front();
        ++counters_.dropped_no_state;
      }
      return false;
    };
    if (!ready() && wait_ns > 0) cv_.wait_for(lock, std::chrono::nanoseconds(wait_ns));
    if (!ready()) return false;
    q = std::move(queue_.front());
    queue_.pop_front();
    states = states_;
    processing_ = true;
  }
  out.report = mapper_.process(q.cloud, states);
  out.scan_id = q.scan_id;
  out.received_ns = q.received_ns;
  const std::int64_t period_ns = static_cast<std::int64_t>(1e9 / config_.publish_rate_hz);
  out.map_due = last_map_ns_ == 0 || now_ns - last_map_ns_ >= period_ns;
  std::lock_guard<std::mutex> lock(mutex_);
  processing_ = false;
  ++counters_.clouds_processed;
  counters_.points_state_outside += out.report.filter.state_outside;
  if (out.map_due) last_map_ns_ = now_ns;
  return true;
}

void MapperNode::make_map(porter::octomap_t& out) {
  to_map_message(mapper_.map(), mapper_.last(), config_.map_frame_id, ++map_id_, writer_, out);
  std::lock_guard<std::mutex> lock(mutex_);
  ++counters_.maps;
}

MapperCounters MapperNode::counters() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return counters_;
}

}  // namespace porter::mapping::app
