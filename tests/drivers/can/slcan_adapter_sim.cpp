#include "slcan_adapter_sim.hpp"

#include <cerrno>
#include <chrono>

#include <fcntl.h>
#include <poll.h>
#include <pty.h>
#include <termios.h>
#include <unistd.h>

#include "porter/can/slcan_protocol.hpp"

namespace porter::can::test {

SimulatedSlcanAdapter::SimulatedSlcanAdapter(Options options) : options_(std::move(options)) {
  termios raw{};
  ::cfmakeraw(&raw);
  char name[128] = {0};
  if (::openpty(&master_, &slave_, name, &raw, nullptr) != 0) return;
  path_ = name;
  ::fcntl(master_, F_SETFL, ::fcntl(master_, F_GETFL) | O_NONBLOCK);
  thread_ = std::thread([this] { run(); });
}

SimulatedSlcanAdapter::~SimulatedSlcanAdapter() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  if (thread_.joinable()) thread_.join();
  if (master_ >= 0) ::close(master_);
  if (slave_ >= 0) ::close(slave_);
}

void SimulatedSlcanAdapter::run() {
  std::string line;
  char buffer[256];
  for (;;) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (stop_) return;
    }
    const int fd = master_;
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, 10) <= 0 || (p.revents & POLLIN) == 0) {
      if (p.revents & (POLLHUP | POLLERR)) ::usleep(2000);
      continue;
    }
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n <= 0) {
      ::usleep(2000);  // EIO while no slave is open
      continue;
    }
    for (ssize_t i = 0; i < n; ++i) {
      if (buffer[i] == '\r') {
        handle(line);
        line.clear();
      } else {
        line += buffer[i];
      }
    }
  }
}

void SimulatedSlcanAdapter::handle(const std::string& line) {
  std::string answer;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    commands_.push_back(line);
    const char c = line.empty() ? '\0' : line[0];
    if (c == 'S' && line.size() == 2 && line[1] >= '0' && line[1] <= '8') {
      answer = (open_ || options_.refused_bitrates.count(line[1] - '0') != 0) ? "\a" : "\r";
    } else if (line == "O") {
      answer = open_ ? "\a" : "\r";
      open_ = true;
    } else if (line == "C") {
      answer = open_ ? "\r" : "\a";
      open_ = false;
    } else if (c == 't' || c == 'T' || c == 'r' || c == 'R') {
      const slcan::Item item = slcan::parse_line(line);
      if (!open_ || refuse_next_ || item.kind != slcan::ItemKind::frame) {
        answer = "\a";
        refuse_next_ = false;
      } else {
        transmitted_.push_back(item.frame);
        answer = (c == 'T' || c == 'R') ? "Z\r" : "z\r";
      }
    } else {
      answer = "\a";
    }
  }
  changed_.notify_all();
  if (!options_.silent) reply(answer);
}

void SimulatedSlcanAdapter::reply(const std::string& bytes) {
  std::lock_guard<std::mutex> lock(write_mutex_);
  if (master_ < 0) return;
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(master_, bytes.data() + done, bytes.size() - done);
    if (n > 0) {
      done += static_cast<std::size_t>(n);
    } else if (n < 0 && errno == EAGAIN) {
      ::usleep(500);
    } else {
      return;
    }
  }
}

void SimulatedSlcanAdapter::inject(const std::string& bytes, std::size_t chunk, int gap_ms) {
  if (chunk == 0) chunk = bytes.size();
  for (std::size_t at = 0; at < bytes.size(); at += chunk) {
    reply(bytes.substr(at, chunk));
    if (gap_ms > 0 && at + chunk < bytes.size()) {
      std::this_thread::sleep_for(std::chrono::milliseconds(gap_ms));
    }
  }
}

std::vector<std::string> SimulatedSlcanAdapter::commands() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return commands_;
}

std::vector<CanFrame> SimulatedSlcanAdapter::transmitted() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return transmitted_;
}

bool SimulatedSlcanAdapter::channel_open() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return open_;
}

std::size_t SimulatedSlcanAdapter::wait_transmitted(std::size_t count, int timeout_ms) const {
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait_for(lock, std::chrono::milliseconds(timeout_ms),
                    [&] { return transmitted_.size() >= count; });
  return transmitted_.size();
}

std::size_t SimulatedSlcanAdapter::wait_commands(std::size_t count, int timeout_ms) const {
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait_for(lock, std::chrono::milliseconds(timeout_ms),
                    [&] { return commands_.size() >= count; });
  return commands_.size();
}

void SimulatedSlcanAdapter::refuse_next_frame() {
  std::lock_guard<std::mutex> lock(mutex_);
  refuse_next_ = true;
}

void SimulatedSlcanAdapter::hang_up() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  if (thread_.joinable()) thread_.join();
  std::lock_guard<std::mutex> lock(write_mutex_);
  if (master_ >= 0) ::close(master_);
  master_ = -1;
  if (slave_ >= 0) ::close(slave_);
  slave_ = -1;
}

}  // namespace porter::can::test
