#include "porter/backend/task_team.hpp"

#include <algorithm>
#include <chrono>

namespace porter::backend {

TaskTeam::TaskTeam(int size, int spin_us) : spin_us_(std::max(0, spin_us)) {
  for (int i = 1; i < std::max(1, size); ++i) helpers_.emplace_back([this, i] { helper_loop(i); });
}

TaskTeam::~TaskTeam() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_.store(true);
    generation_.fetch_add(1);
  }
  wake_.notify_all();
  for (std::thread& t : helpers_) t.join();
}

void TaskTeam::run(const std::function<void(int)>& f) {
  if (helpers_.empty()) {
    f(0);
    return;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    task_ = &f;
    pending_.store(static_cast<int>(helpers_.size()));
    generation_.fetch_add(1);
  }
  wake_.notify_all();
  f(0);
  while (pending_.load(std::memory_order_acquire) > 0) std::this_thread::yield();
}

void TaskTeam::helper_loop(int index) {
  std::uint64_t seen = 0;
  for (;;) {
    // Spin a little for the next phase, then sleep.
    const auto spin_end = std::chrono::steady_clock::now() + std::chrono::microseconds(spin_us_);
    while (generation_.load(std::memory_order_acquire) == seen && std::chrono::steady_clock::now() < spin_end) {
    }
    const std::function<void(int)>* task = nullptr;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return generation_.load() != seen; });
      seen = generation_.load();
      if (stop_.load()) return;
      task = task_;
    }
    (*task)(index);
    pending_.fetch_sub(1, std::memory_order_release);
  }
}

}  // namespace porter::backend
