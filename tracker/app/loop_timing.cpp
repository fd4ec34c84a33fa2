#include "loop_timing.hpp"

#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>
#include <sys/prctl.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>

namespace porter::tracker_app {

LoopTiming::LoopTiming(double nominal_period_s)
    : nominal_s_(nominal_period_s), jitter_(0.05), work_(0.05) {}

void LoopTiming::on_wake(std::int64_t mono_ns) {
  if (last_wake_ns_ != 0) {
    last_period_s_ = static_cast<double>(mono_ns - last_wake_ns_) * 1e-9;
    jitter_.add(std::abs(last_period_s_ - nominal_s_));
  }
  last_wake_ns_ = mono_ns;
}

void LoopTiming::on_work_done(std::int64_t mono_ns) {
  if (last_wake_ns_ != 0) work_.add(static_cast<double>(mono_ns - last_wake_ns_) * 1e-9);
}

namespace {
std::string us(double s) {
  char b[32];
  if (s < 1e-3) {
    std::snprintf(b, sizeof b, "%.0f us", s * 1e6);
  } else {
    std::snprintf(b, sizeof b, "%.2f ms", s * 1e3);
  }
  return b;
}
std::string triple(const runtime::LatenessStats& s) {
  return "p50 " + us(s.quantile_s(0.5)) + " p99 " + us(s.quantile_s(0.99)) + " max " +
         us(s.max_s());
}
}  // namespace

std::string describe(const LoopTiming& timing, const runtime::PeriodicLoop& loop) {
  return "period jitter " + triple(timing.period_jitter()) + " over " +
         std::to_string(timing.periods()) + " periods; wake-up lateness " +
         triple(loop.lateness()) + "; work " + triple(timing.work()) + "; overruns " +
         std::to_string(loop.overruns());
}

std::string describe_command_latency(const runtime::LatenessStats& command_latency) {
  return "command latency " + triple(command_latency) + " over " +
         std::to_string(command_latency.count()) + " periods";
}

std::string to_json(const LoopTiming& timing, const runtime::PeriodicLoop& loop,
                    const runtime::LatenessStats& command_latency, double duration_s,
                    bool sched_fifo) {
  char b[1280];
  const auto& p = command_latency;
  const auto& j = timing.period_jitter();
  const auto& l = loop.lateness();
  const auto& w = timing.work();
  std::snprintf(
      b, sizeof b,
      "{\"duration_s\": %.3f, \"nominal_period_s\": %.6f, \"periods\": %llu, \"overruns\": %llu, "
      "\"sched_fifo\": %s,\n"
      " \"period_jitter_us\": {\"p50\": %.1f, \"p99\": %.1f, \"p999\": %.1f, \"max\": %.1f, "
      "\"mean\": %.2f},\n"
      " \"wake_lateness_us\": {\"p50\": %.1f, \"p99\": %.1f, \"p999\": %.1f, \"max\": %.1f, "
      "\"mean\": %.2f},\n"
      " \"work_us\": {\"p50\": %.1f, \"p99\": %.1f, \"max\": %.1f},\n"
      " \"command_latency_us\": {\"p50\": %.1f, \"p99\": %.1f, \"p999\": %.1f, \"max\": %.1f}}\n",
      duration_s, loop.period_s(), static_cast<unsigned long long>(timing.periods()),
      static_cast<unsigned long long>(loop.overruns()), sched_fifo ? "true" : "false",
      j.quantile_s(0.5) * 1e6, j.quantile_s(0.99) * 1e6, j.quantile_s(0.999) * 1e6,
      j.max_s() * 1e6, j.mean_s() * 1e6, l.quantile_s(0.5) * 1e6, l.quantile_s(0.99) * 1e6,
      l.quantile_s(0.999) * 1e6, l.max_s() * 1e6, l.mean_s() * 1e6, w.quantile_s(0.5) * 1e6,
      w.quantile_s(0.99) * 1e6, w.max_s() * 1e6, p.quantile_s(0.5) * 1e6,
      p.quantile_s(0.99) * 1e6, p.quantile_s(0.999) * 1e6, p.max_s() * 1e6);
  return b;
}

std::string enable_sched_fifo(int priority) {
  sched_param param{};
  param.sched_priority = priority;
  if (sched_setscheduler(0, SCHED_FIFO, &param) != 0) {
    return std::string("sched_setscheduler(SCHED_FIFO, ") + std::to_string(priority) +
           "): " + std::strerror(errno);
  }
  if (mlockall(MCL_CURRENT | MCL_FUTURE) != 0) {
    return std::string("SCHED_FIFO set, but mlockall: ") + std::strerror(errno);
  }
  return {};
}

int io_priority(int timed_priority) { return std::max(1, timed_priority - 1); }

std::string set_thread_fifo(int priority) {
  sched_param param{};
  param.sched_priority = priority;
  const int err = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
  if (err != 0) {
    return std::string("pthread_setschedparam(SCHED_FIFO, ") + std::to_string(priority) +
           "): " + std::strerror(err);
  }
  return {};
}

namespace {
// Not inlined, so the compiler cannot drop the array; volatile, so it cannot drop the writes.
[[gnu::noinline]] void touch_stack() {
  volatile unsigned char stack[256 * 1024];
  for (std::size_t i = 0; i < sizeof stack; i += 4096) stack[i] = 0;
}
}  // namespace

void prepare_timed_thread() {
  ::prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
  touch_stack();
}

}  // namespace porter::tracker_app
