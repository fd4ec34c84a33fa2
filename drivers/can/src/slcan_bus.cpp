#include "porter/can/slcan_bus.hpp"

#include <cerrno>
#include <chrono>
#include <cstring>
#include <optional>
#include <vector>

#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

namespace porter::can {
namespace {

constexpr std::size_t kQueueCapacity = 4096;

std::int64_t wall_utime() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

std::optional<speed_t> baud_constant(std::uint32_t baud) {
  switch (baud) {
    case 9600: return B9600;
    case 19200: return B19200;
    case 38400: return B38400;
    case 57600: return B57600;
    case 115200: return B115200;
    case 230400: return B230400;
    case 460800: return B460800;
    case 500000: return B500000;
    case 921600: return B921600;
    case 1000000: return B1000000;
    case 2000000: return B2000000;
    case 3000000: return B3000000;
    default: return std::nullopt;
  }
}

int ms_left(std::chrono::steady_clock::time_point deadline) {
  const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
                        deadline - std::chrono::steady_clock::now())
                        .count();
  return left < 0 ? 0 : static_cast<int>(left);
}

}  // namespace

bool parse_slcan_target(const std::string& target, SlcanOptions& options, std::string& error) {
  const auto at = target.rfind('@');
  if (at == std::string::npos || at == 0) {
    error = "expected DEVICE@BITRATE, e.g. /dev/ttyACM0@500000";
    return false;
  }
  options.device = target.substr(0, at);
  std::string rate = target.substr(at + 1);
  const auto query = rate.find('?');
  if (query != std::string::npos) {
    const std::string option = rate.substr(query + 1);
    rate = rate.substr(0, query);
    const std::string key = "baud=";
    if (option.rfind(key, 0) != 0 || option.size() == key.size() || option.size() > key.size() + 8 ||
        option.find_first_not_of("0123456789", key.size()) != std::string::npos) {
      error = "unknown option '" + option + "' (only baud=N)";
      return false;
    }
    const unsigned long baud = std::stoul(option.substr(key.size()));
    if (!baud_constant(static_cast<std::uint32_t>(baud))) {
      error = "serial baud " + option.substr(key.size()) + " is not a standard tty speed";
      return false;
    }
    options.serial_baud = static_cast<std::uint32_t>(baud);
  }
  if (rate.empty() || rate.size() > 8 || rate.find_first_not_of("0123456789") != std::string::npos) {
    error = "bitrate '" + rate + "' is not a number of bit/s";
    return false;
  }
  options.bitrate = static_cast<std::uint32_t>(std::stoul(rate));
  if (slcan::bitrate_code(options.bitrate) < 0) {
    error = "bitrate " + rate +
            " has no SLCAN code (10000, 20000, 50000, 100000, 125000, 250000, 500000, 800000, "
            "1000000)";
    return false;
  }
  return true;
}

SlcanBus::SlcanBus(SlcanOptions options, std::string describe)
    : options_(std::move(options)), describe_(std::move(describe)) {}

std::unique_ptr<SlcanBus> SlcanBus::open(const SlcanOptions& options, std::string describe) {
  std::unique_ptr<SlcanBus> bus(new SlcanBus(options, std::move(describe)));
  const std::string cmd = slcan::bitrate_command(options.bitrate);
  if (cmd.empty()) {
    bus->set_error(bus->describe_ + ": bitrate " + std::to_string(options.bitrate) +
                   " has no SLCAN code");
    return bus;
  }
  bus->fd_ = ::open(options.device.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (bus->fd_ < 0) {
    bus->set_error(bus->describe_ + ": cannot open '" + options.device + "': " +
                   std::strerror(errno));
    return bus;
  }
  auto fail = [&bus]() {
    ::close(bus->fd_);
    bus->fd_ = -1;
    return std::move(bus);
  };
  if (!bus->configure_tty()) return fail();
  // Close first: an adapter left open by a previous run refuses S. Its reply (CR, or BEL
  // when already closed) is not an error either way; only silence is.
  if (!bus->command("C\r", "close (C)")) {
    if (bus->last_error().find("no reply") != std::string::npos) return fail();
  }
  if (!bus->command(cmd, "bitrate") || !bus->command("O\r", "open (O)")) return fail();
  bus->set_error("");
  return bus;
}

SlcanBus::~SlcanBus() {
  if (fd_ < 0) return;
  if (!hung_up_.load()) write_all("C\r", 100);
  ::close(fd_);
}

bool SlcanBus::configure_tty() {
  termios tio{};
  if (::tcgetattr(fd_, &tio) != 0) {
    set_error(describe_ + ": '" + options_.device + "' is not a serial port: " +
              std::strerror(errno));
    return false;
  }
  ::cfmakeraw(&tio);
  tio.c_cflag |= CLOCAL | CREAD;
  tio.c_cflag &= ~CRTSCTS;
  tio.c_cc[VMIN] = 0;
  tio.c_cc[VTIME] = 0;
  const speed_t speed = baud_constant(options_.serial_baud).value_or(B115200);
  ::cfsetispeed(&tio, speed);
  ::cfsetospeed(&tio, speed);
  if (::tcsetattr(fd_, TCSANOW, &tio) != 0) {
    set_error(describe_ + ": configuring '" + options_.device + "' failed: " +
              std::strerror(errno));
    return false;
  }
  ::tcflush(fd_, TCIOFLUSH);
  return true;
}

bool SlcanBus::write_all(const std::string& bytes, int timeout_ms) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd_, bytes.data() + done, bytes.size() - done);
    if (n > 0) {
      done += static_cast<std::size_t>(n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && errno != EAGAIN) {
      set_error(describe_ + ": write failed: " + std::strerror(errno));
      if (errno == EIO) hung_up_ = true;
      return false;
    }
    const int left = ms_left(deadline);
    if (left == 0) {
      set_error(describe_ + ": the adapter does not accept bytes (output buffer full)");
      return false;
    }
    pollfd p{fd_, POLLOUT, 0};
    ::poll(&p, 1, left);
  }
  return true;
}

// Sends one configuration command and waits for its reply. Frames and text replies that arrive
// meanwhile are dropped: nothing is open yet.
bool SlcanBus::command(const std::string& cmd, const char* what) {
  std::string shown = cmd.substr(0, cmd.size() - 1);
  if (!write_all(cmd, options_.reply_timeout_ms)) return false;
  const auto deadline =
      std::chrono::steady_clock::now() + std::chrono::milliseconds(options_.reply_timeout_ms);
  std::vector<slcan::Item> items;
  std::uint8_t buffer[256];
  for (;;) {
    for (const slcan::Item& item : items) {
      if (item.kind == slcan::ItemKind::ack || item.kind == slcan::ItemKind::tx_ack) return true;
      if (item.kind == slcan::ItemKind::refused) {
        set_error(describe_ + ": the adapter refused the " + what + " command '" + shown +
                  "' (BEL)");
        return false;
      }
    }
    items.clear();
    const int left = ms_left(deadline);
    pollfd p{fd_, POLLIN, 0};
    const int ready = left > 0 ? ::poll(&p, 1, left) : 0;
    if (ready <= 0) {
      set_error(describe_ + ": no reply from '" + options_.device + "' to the " + what +
                " command '" + shown + "' within " + std::to_string(options_.reply_timeout_ms) +
                " ms (is it an SLCAN adapter?)");
      return false;
    }
    const ssize_t n = ::read(fd_, buffer, sizeof buffer);
    if (n < 0 && (errno == EAGAIN || errno == EINTR)) continue;
    if (n <= 0) {
      set_error(describe_ + ": '" + options_.device + "' hung up during the " + what +
                " command");
      return false;
    }
    decoder_.feed(buffer, static_cast<std::size_t>(n), items);
  }
}

CanStatus SlcanBus::send(const CanFrame& frame) {
  if (!is_open()) return CanStatus::closed;
  const std::string line = slcan::encode_frame(frame);
  if (line.empty()) return CanStatus::invalid_frame;
  if (!write_all(line, 20)) return hung_up_.load() ? CanStatus::closed : CanStatus::tx_full;
  return CanStatus::ok;
}

CanStatus SlcanBus::receive(CanFrame& frame, int timeout_ms) {
  if (!is_open()) return CanStatus::closed;
  const auto deadline = std::chrono::steady_clock::now() +
                        std::chrono::milliseconds(timeout_ms < 0 ? 0 : timeout_ms);
  std::vector<slcan::Item> items;
  std::uint8_t buffer[512];
  for (;;) {
    if (!frames_.empty()) {
      frame = frames_.front();
      frames_.pop_front();
      return CanStatus::ok;
    }
    pollfd p{fd_, POLLIN, 0};
    const int wait = timeout_ms < 0 ? -1 : ms_left(deadline);
    const int ready = ::poll(&p, 1, wait);
    if (ready < 0 && errno == EINTR) continue;
    if (ready < 0) {
      set_error(describe_ + ": poll failed: " + std::strerror(errno));
      return CanStatus::io_error;
    }
    if (ready == 0) return CanStatus::timeout;
    const ssize_t n = ::read(fd_, buffer, sizeof buffer);
    if (n < 0 && (errno == EAGAIN || errno == EINTR)) continue;
    if (n <= 0 || (p.revents & (POLLHUP | POLLERR)) != 0) {
      if (n > 0) {
        // Keep what arrived with the hang-up, then report closed on the next call.
        decoder_.feed(buffer, static_cast<std::size_t>(n), items);
      }
      hung_up_ = true;
      set_error(describe_ + ": '" + options_.device + "' hung up (adapter unplugged?)");
      if (frames_.empty()) return CanStatus::closed;
    }
    if (n > 0 && !hung_up_.load()) decoder_.feed(buffer, static_cast<std::size_t>(n), items);
    bool refused_now = false;
    const std::int64_t now = wall_utime();
    for (slcan::Item& item : items) {
      switch (item.kind) {
        case slcan::ItemKind::frame:
          if (frames_.size() >= kQueueCapacity) frames_.pop_front();
          item.frame.utime = now;
          frames_.push_back(item.frame);
          break;
        case slcan::ItemKind::refused:
          ++refused_;
          refused_now = true;
          break;
        case slcan::ItemKind::malformed:
          ++malformed_;
          set_error(describe_ + ": skipped a malformed adapter line (" + item.text + ")");
          break;
        default:
          break;
      }
    }
    items.clear();
    if (refused_now) {
      set_error(describe_ + ": the adapter refused a command (BEL): a frame was not queued "
                            "(channel closed or transmit buffer full)");
      return CanStatus::io_error;
    }
  }
}

std::string SlcanBus::last_error() const {
  std::lock_guard<std::mutex> lock(error_mutex_);
  return error_;
}

void SlcanBus::set_error(std::string error) {
  std::lock_guard<std::mutex> lock(error_mutex_);
  error_ = std::move(error);
}

}  // namespace porter::can
