#include "porter/runtime/periodic.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <ctime>
#include <stdexcept>

#include "porter/runtime/clock.hpp"

namespace porter::runtime {

LatenessStats::LatenessStats(double histogram_range_s)
    : bins_(static_cast<std::size_t>(std::max(1.0, std::ceil(histogram_range_s * 1e6))) + 1, 0) {}

void LatenessStats::add(double lateness_s) {
  if (!(lateness_s >= 0.0)) lateness_s = 0.0;
  const double us = lateness_s * 1e6;
  const std::size_t last = bins_.size() - 1;
  const std::size_t bin = us >= static_cast<double>(last) ? last : static_cast<std::size_t>(us);
  ++bins_[bin];
  ++count_;
  sum_s_ += lateness_s;
  max_s_ = std::max(max_s_, lateness_s);
}

void LatenessStats::reset() {
  std::fill(bins_.begin(), bins_.end(), 0u);
  count_ = 0;
  sum_s_ = 0.0;
  max_s_ = 0.0;
}

double LatenessStats::quantile_s(double q) const {
  if (count_ == 0) return 0.0;
  q = std::clamp(q, 0.0, 1.0);
  const auto rank = static_cast<std::uint64_t>(std::ceil(q * static_cast<double>(count_)));
  std::uint64_t seen = 0;
  for (std::size_t i = 0; i < bins_.size(); ++i) {
    seen += bins_[i];
    if (seen >= std::max<std::uint64_t>(rank, 1)) {
      // The last bin holds everything beyond the range: report the true maximum there.
      return i + 1 == bins_.size() ? max_s_ : std::min(max_s_, static_cast<double>(i + 1) * 1e-6);
    }
  }
  return max_s_;
}

PeriodicLoop::PeriodicLoop(double period_s) : period_s_(period_s) {
  if (!(period_s > 0.0) || !std::isfinite(period_s)) {
    throw std::invalid_argument("PeriodicLoop: period must be a positive finite number of seconds");
  }
  period_ns_ = std::max<std::int64_t>(1, std::llround(period_s * 1e9));
}

double PeriodicLoop::wait() {
  std::int64_t now = mono_ns();
  if (cycles_ == 0 && next_ns_ == 0) {
    next_ns_ = now + period_ns_;
    rate_window_start_ns_ = now;
  } else {
    next_ns_ += period_ns_;
    if (now > next_ns_) {
      // The step ran past one or more deadlines: skip them, count them.
      const std::int64_t missed = (now - next_ns_) / period_ns_ + 1;
      overruns_ += static_cast<std::uint64_t>(missed);
      next_ns_ += missed * period_ns_;
    }
  }
  timespec deadline{};
  deadline.tv_sec = static_cast<time_t>(next_ns_ / 1000000000);
  deadline.tv_nsec = static_cast<long>(next_ns_ % 1000000000);
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &deadline, nullptr) == EINTR) {
  }
  now = mono_ns();
  const double late_s = static_cast<double>(std::max<std::int64_t>(0, now - next_ns_)) * 1e-9;
  lateness_.add(late_s);
  ++cycles_;
  ++rate_window_cycles_;
  if (now - rate_window_start_ns_ >= 1000000000) {
    rate_hz_ = static_cast<double>(rate_window_cycles_) * 1e9 /
               static_cast<double>(now - rate_window_start_ns_);
    rate_window_start_ns_ = now;
    rate_window_cycles_ = 0;
  }
  return late_s;
}

void PeriodicLoop::reset_stats() {
  lateness_.reset();
  overruns_ = 0;
}

}  // namespace porter::runtime
