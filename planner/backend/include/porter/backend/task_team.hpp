#pragma once
// A fixed team of threads for the safety term's per-evaluation fork-join (obstacle-point prefilter,
// then the point queries): run(f) calls f(0) on the caller's thread and f(1) .. f(size - 1) on the
// team's helpers, and returns when all have returned. The helpers live as long as the team, so an
// evaluation pays a wake-up instead of a thread start (std::thread start + join measured at
// ~0.1-0.4 ms on the 2-core development VM, against ~3 ms for a whole J_s evaluation on the bridge,
// which starts two such phases).
//
// Waiting: a helper spins for up to spin_us after its last task (the next phase usually follows
// within that), then sleeps on a condition variable; run() spins on the completion count.
// Exceptions must not escape f (the safety term's work does not throw).
//
// Thread-safety: run() is called from one thread at a time; the team is neither copyable nor
// movable.

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace porter::backend {

class TaskTeam {
 public:
  /// size >= 1 participants (the caller included); spin_us >= 0.
  explicit TaskTeam(int size, int spin_us = 200);
  ~TaskTeam();
  TaskTeam(const TaskTeam&) = delete;
  TaskTeam& operator=(const TaskTeam&) = delete;

  int size() const { return static_cast<int>(helpers_.size()) + 1; }
  /// f(i) for i = 0 .. size() - 1, f(0) here; returns when every call has returned.
  void run(const std::function<void(int)>& f);

 private:
  void helper_loop(int index);

  std::vector<std::thread> helpers_;
  std::mutex mutex_;
  std::condition_variable wake_;
  const std::function<void(int)>* task_ = nullptr;
  std::atomic<std::uint64_t> generation_{0};  ///< bumped by run(); helpers wait for a new value
  std::atomic<int> pending_{0};               ///< helpers still working on the current task
  std::atomic<bool> stop_{false};
  int spin_us_ = 200;
};

}  // namespace porter::backend
