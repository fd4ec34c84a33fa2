#pragma once
// A wall-clock budget shared by the front-end stages (steady clock). Header-only, thread-safe
// to read.

#include <chrono>

namespace porter::frontend {

class Deadline {
 public:
  using Clock = std::chrono::steady_clock;

  /// A budget of `budget_s` seconds from now; <= 0 or non-finite means "already expired".
  explicit Deadline(double budget_s) : start_(Clock::now()) {
    const double b = budget_s > 0.0 && budget_s < 1e9 ? budget_s : 0.0;
    end_ = start_ + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(b));
  }

  bool expired() const { return Clock::now() >= end_; }
  double elapsed_s() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }
  double remaining_s() const {
    const double r = std::chrono::duration<double>(end_ - Clock::now()).count();
    return r > 0.0 ? r : 0.0;
  }

 private:
  Clock::time_point start_;
  Clock::time_point end_;
};

}  // namespace porter::frontend
