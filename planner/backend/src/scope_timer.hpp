#pragma once
// Private to porter::backend: a scope's wall time added to a counter (SvsdfStats::search_time_s).

#include <chrono>

namespace porter::backend::detail {

/// Adds the scope's wall time to *sink when sink is non-null.
class ScopeTimer {
 public:
  explicit ScopeTimer(double* sink) : sink_(sink) {
    if (sink_) start_ = std::chrono::steady_clock::now();
  }
  ~ScopeTimer() {
    if (sink_) *sink_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }
  ScopeTimer(const ScopeTimer&) = delete;
  ScopeTimer& operator=(const ScopeTimer&) = delete;

 private:
  double* sink_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace porter::backend::detail
