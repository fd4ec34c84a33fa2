#pragma once
// A simulated SLCAN USB-CAN adapter on the master side of a pseudo-terminal pair, for testing
// SlcanBus without hardware. It answers like a LAWICEL adapter: CR for an accepted command, BEL
// for a refused one (S while open, O while open, C while closed, unknown commands, frames while
// closed), 'z' / 'Z' CR for a transmitted t / T frame. Tests inject adapter output in pieces to
// exercise line reassembly.

#include <condition_variable>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "porter/can/can_frame.hpp"

namespace porter::can::test {

class SimulatedSlcanAdapter {
 public:
  struct Options {
    bool silent = false;               ///< never reply (not an SLCAN device)
    std::set<int> refused_bitrates;    ///< Sn codes answered with BEL
  };

  SimulatedSlcanAdapter() : SimulatedSlcanAdapter(Options()) {}
  explicit SimulatedSlcanAdapter(Options options);
  ~SimulatedSlcanAdapter();

  /// Path of the slave side (what SlcanBus opens).
  const std::string& path() const { return path_; }

  /// Every command line received, without its CR, in order.
  std::vector<std::string> commands() const;
  /// Frames the host transmitted while the channel was open.
  std::vector<CanFrame> transmitted() const;
  bool channel_open() const;
  /// Waits until `count` frames were transmitted (or timeout); returns the count reached.
  std::size_t wait_transmitted(std::size_t count, int timeout_ms) const;
  /// Waits until the command list has `count` entries.
  std::size_t wait_commands(std::size_t count, int timeout_ms) const;

  /// Writes `bytes` to the host in pieces of `chunk` bytes, `gap_ms` apart.
  void inject(const std::string& bytes, std::size_t chunk = 0, int gap_ms = 0);
  /// Refuses (BEL) the next transmitted frame.
  void refuse_next_frame();
  /// Closes the master side: the host sees a hang-up.
  void hang_up();

 private:
  void run();
  void handle(const std::string& line);
  void reply(const std::string& bytes);

  Options options_;
  int master_ = -1;
  int slave_ = -1;
  std::string path_;
  std::thread thread_;
  bool stop_ = false;
  mutable std::mutex mutex_;
  mutable std::condition_variable changed_;
  std::mutex write_mutex_;
  std::vector<std::string> commands_;
  std::vector<CanFrame> transmitted_;
  bool open_ = false;
  bool refuse_next_ = false;
};

}  // namespace porter::can::test
