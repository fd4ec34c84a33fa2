#pragma once
// The time budget every planner stage runs under: a steady-clock end time plus an optional
// cancellation flag that another thread may set (a planner daemon cancels a running plan when a
// new goal or a shutdown arrives). Header-only.
//
//   CancelFlag cancel;                       // owned by the caller, outlives the plan
//   Deadline d(0.3, &cancel);                // 300 ms from now, or until cancel.request()
//   Deadline fe = d.within(0.08);            // a stage's share: the earlier end, same flag
//   while (!fe.expired()) { ... }
//
// Thread-safety: CancelFlag::request()/reset()/requested() may be called from any thread; a
// Deadline is immutable and may be read from several threads.

#include <atomic>
#include <chrono>

namespace porter::planner {

/// A cancellation request shared between the thread that plans and the one that may stop it.
class CancelFlag {
 public:
  void request() { flag_.store(true, std::memory_order_relaxed); }
  void reset() { flag_.store(false, std::memory_order_relaxed); }
  bool requested() const { return flag_.load(std::memory_order_relaxed); }

 private:
  std::atomic<bool> flag_{false};
};

class Deadline {
 public:
  using Clock = std::chrono::steady_clock;
  /// The longest budget a deadline holds, s (about 11.6 days: "no limit" for any plan).
  static constexpr double kMaxBudgetS = 1e6;

  /// A budget of `budget_s` seconds from now, cut short when `cancel` (optional; must outlive the
  /// deadline) is requested. A budget <= 0 or NaN is already expired; one above kMaxBudgetS
  /// (including +inf) is capped there, so a huge budget never wraps into an expired one.
  explicit Deadline(double budget_s, const CancelFlag* cancel = nullptr) : start_(Clock::now()), cancel_(cancel) {
    end_ = start_ + duration(budget_s);
  }

  /// A budget of `budget_s` from now that ends no later than this one, with the same flag.
  Deadline within(double budget_s) const {
    Deadline d(budget_s, cancel_);
    if (end_ < d.end_) d.end_ = end_;
    return d;
  }

  /// The same end and flag, with elapsed_s() counted from now (a stage timing its own part).
  Deadline from_now() const {
    Deadline d = *this;
    d.start_ = Clock::now();
    return d;
  }

  /// Time is up or cancellation was requested.
  bool expired() const { return canceled() || Clock::now() >= end_; }
  bool canceled() const { return cancel_ != nullptr && cancel_->requested(); }
  double elapsed_s() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }
  /// Seconds left (0 once expired or canceled).
  double remaining_s() const {
    if (canceled()) return 0.0;
    const double r = std::chrono::duration<double>(end_ - Clock::now()).count();
    return r > 0.0 ? r : 0.0;
  }
  /// The budget this deadline was made with, s (its end minus its start).
  double budget_s() const { return std::chrono::duration<double>(end_ - start_).count(); }
  const CancelFlag* cancel_flag() const { return cancel_; }

 private:
  static Clock::duration duration(double budget_s) {
    const double b = budget_s > 0.0 ? (budget_s < kMaxBudgetS ? budget_s : kMaxBudgetS) : 0.0;
    return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(b));
  }

  Clock::time_point start_;
  Clock::time_point end_;
  const CancelFlag* cancel_ = nullptr;
};

}  // namespace porter::planner
