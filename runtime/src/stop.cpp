#include "porter/runtime/stop.hpp"

#include <atomic>
#include <csignal>
#include <fcntl.h>
#include <unistd.h>

namespace porter::runtime {
namespace {

std::atomic<bool> g_stop{false};
int g_pipe[2] = {-1, -1};

void wake() {
  if (g_pipe[1] >= 0) {
    const char byte = 1;
    [[maybe_unused]] const ssize_t n = ::write(g_pipe[1], &byte, 1);
  }
}

extern "C" void on_stop_signal(int signo) {
  if (g_stop.exchange(true)) {
    // Second signal while stopping: let the default action end the process.
    std::signal(signo, SIG_DFL);
    std::raise(signo);
    return;
  }
  wake();
}

}  // namespace

bool install_stop_handlers() {
  if (g_pipe[0] < 0) {
    if (::pipe2(g_pipe, O_CLOEXEC | O_NONBLOCK) != 0) return false;
  }
  struct sigaction action {};
  action.sa_handler = on_stop_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;
  return ::sigaction(SIGINT, &action, nullptr) == 0 && ::sigaction(SIGTERM, &action, nullptr) == 0;
}

bool stop_requested() { return g_stop.load(); }

void request_stop() {
  if (!g_stop.exchange(true)) wake();
}

int stop_fd() { return g_pipe[0]; }

}  // namespace porter::runtime
