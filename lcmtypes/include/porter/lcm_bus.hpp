#pragma once
// Typed publish/subscribe over LCM using the channel registry (channels.hpp).
//
//   porter::LcmBus bus("memq://");            // in-process; "" = $LCM_DEFAULT_URL or udpm default
//   bus.subscribe(porter::channels::kRobotState,
//                 [](const porter::robot_state_t& s) { ... });
//   bus.publish(porter::channels::kRobotState, state);
//   while (running) bus.handle_timeout(100);
//
// The channel descriptor fixes the message type, so a process cannot publish or decode the wrong
// type on a channel, and no channel string appears in application code.
//
// Failure: nothing here throws or prints. A bus whose URL cannot be opened is !good(), and its
// calls return failure. Every datagram passes the guard (porter/lcm_guard.hpp) before lcm-gen's
// decoder sees it, so no byte sequence can crash the process or make it read past the datagram.
// A message that does not decode as the channel's type (wrong type, a truncated buffer, a string
// length or array count the datagram cannot hold) is dropped and counted in decode_failures(),
// with the reason in last_error() (process_decode_failures() sums them over the process, for
// its HEARTBEAT); a callback that throws is
// counted in callback_failures() and its message kept in last_error(). Counted arrays must have
// their count field equal to the vector size before publish (lcm-gen encodes `count` elements).
//
// Thread-safety: publish() may be called from any thread (lcm_publish is thread-safe).
// subscribe(), unsubscribe(), handle*() and last_error() must be called from one thread (the
// handling thread); callbacks run on that thread, inside handle*(). The failure counters may be
// read from any thread.
//
// Testing: "memq://" gives an in-process bus; messages published on it are delivered by the
// next handle*() call on the same LcmBus.

#include <atomic>
#include <cstdint>
#include <exception>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "porter/channels.hpp"
#include "porter/lcm_guard.hpp"

namespace porter {

namespace detail {
template <class T>
struct CallbackOf {
  using type = std::function<void(const T&)>;
};
}  // namespace detail

class LcmBus {
 public:
  /// Identifies one subscription of this bus; 0 is never a valid id.
  using SubscriptionId = std::uint64_t;

  /// Callback for messages of type T. Spelled through a nested type so that T is deduced from
  /// the channel alone and a lambda converts to it.
  template <class T>
  using Callback = typename detail::CallbackOf<T>::type;

  /// Opens LCM on `url` ("" = $LCM_DEFAULT_URL, else udpm://239.255.76.67:7667?ttl=0).
  explicit LcmBus(const std::string& url = std::string())
      : owned_(std::make_unique<lcm::LCM>(url)), lcm_(owned_.get()) {}

  /// Uses an lcm::LCM owned by the caller; it must outlive this bus.
  explicit LcmBus(lcm::LCM& lcm) : lcm_(&lcm) {}

  LcmBus(const LcmBus&) = delete;
  LcmBus& operator=(const LcmBus&) = delete;

  ~LcmBus() {
    while (!subscriptions_.empty()) unsubscribe(subscriptions_.back()->id);
  }

  /// True when the underlying LCM instance was created successfully.
  bool good() const { return lcm_ != nullptr && lcm_->good(); }

  /// Encodes and publishes `msg` on `channel`. Returns false when the bus is not good or the
  /// transport refused the message.
  template <class T>
  bool publish(const channels::Channel<T>& channel, const T& msg) {
    if (!good()) return false;
    const int size = msg.getEncodedSize();
    if (size < 0) return false;
    std::vector<std::uint8_t> buffer(static_cast<std::size_t>(size));
    if (msg.encode(buffer.data(), 0, size) != size) return false;
    return lcm_->publish(std::string(channel.name()), buffer.data(),
                         static_cast<unsigned int>(size)) == 0;
  }

  /// Calls `callback` with every message received on `channel` (during handle*()). The message
  /// reference is valid only for the duration of the call. A callback must not unsubscribe its
  /// own subscription. `queue_capacity` is the number of undelivered messages LCM keeps for this
  /// subscription before dropping (LCM default 30). Returns 0 when the bus is not good or the
  /// subscription failed.
  template <class T>
  SubscriptionId subscribe(const channels::Channel<T>& channel, Callback<T> callback,
                           int queue_capacity = 30) {
    if (!good() || !callback) return 0;
    auto sub = std::make_unique<Typed<T>>(this, std::move(callback));
    sub->lcm_subscription =
        lcm_->subscribe(std::string(channel.name()), &Typed<T>::on_message, sub.get());
    if (sub->lcm_subscription == nullptr) return 0;
    sub->lcm_subscription->setQueueCapacity(queue_capacity);
    sub->id = ++last_id_;
    subscriptions_.push_back(std::move(sub));
    return last_id_;
  }

  /// Removes a subscription. Returns false for an unknown id.
  bool unsubscribe(SubscriptionId id) {
    for (auto it = subscriptions_.begin(); it != subscriptions_.end(); ++it) {
      if ((*it)->id != id) continue;
      if (good()) lcm_->unsubscribe((*it)->lcm_subscription);
      subscriptions_.erase(it);
      return true;
    }
    return false;
  }

  /// Waits for and dispatches one message. 0 on success, -1 on error.
  int handle() { return good() ? lcm_->handle() : -1; }

  /// Waits up to `timeout_ms` for one message and dispatches it. >0: a message was handled,
  /// 0: timeout, <0: error.
  int handle_timeout(int timeout_ms) { return good() ? lcm_->handleTimeout(timeout_ms) : -1; }

  /// Dispatches every message already queued, without waiting. Returns how many were handled,
  /// or -1 on error.
  int handle_pending() {
    int handled = 0;
    for (;;) {
      const int status = handle_timeout(0);
      if (status < 0) return -1;
      if (status == 0) return handled;
      ++handled;
    }
  }

  /// File descriptor that becomes readable when a message is waiting (for poll/select), -1 if
  /// the bus is not good.
  int fileno() { return good() ? lcm_->getFileno() : -1; }

  /// Messages dropped because they did not decode as the channel's type.
  std::uint64_t decode_failures() const { return decode_failures_.load(); }
  /// decode_failures() summed over every LcmBus of this process since it started (buses that no
  /// longer exist included): what the process's HEARTBEAT reports as dropped datagrams, so drops
  /// on a bus a library owns (e.g. an lcm: CAN bus) are seen too.
  static std::uint64_t process_decode_failures() { return process_decode_failures_.load(); }
  /// Callbacks that threw; the message is dropped, the bus keeps running.
  std::uint64_t callback_failures() const { return callback_failures_.load(); }
  /// Description of the last decode or callback failure ("" when none).
  const std::string& last_error() const { return last_error_; }

  /// The underlying LCM instance (for raw access, e.g. a LogFile replay).
  lcm::LCM& lcm() { return *lcm_; }

 private:
  struct Subscription {
    virtual ~Subscription() = default;
    SubscriptionId id = 0;
    lcm::Subscription* lcm_subscription = nullptr;
  };

  template <class T>
  struct Typed final : Subscription {
    Typed(LcmBus* owner, std::function<void(const T&)> cb)
        : bus(owner), callback(std::move(cb)) {}

    // Raw handler: we decode ourselves so that failures are counted instead of printed.
    // The guard runs first: lcm-gen's decoders trust the lengths in the bytes.
    // A fresh T per message: lcm-gen 1.3.1 leaves a vector untouched when its count is 0, so a
    // reused decode target would keep the previous message's array. The try block stays for
    // std::bad_alloc on a datagram the guard accepted but memory could not hold.
    void on_message(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
      const LcmGuardResult guard = lcm_guard_check<T>(rbuf->data, rbuf->data_size);
      if (!guard.ok) {
        bus->record_decode_failure("channel " + channel + ": not a valid " + T::getTypeName() + ": " +
                                   guard.describe());
        return;
      }
      const int size = static_cast<int>(rbuf->data_size);
      T message;
      bool decoded = false;
      try {
        decoded = message.decode(rbuf->data, 0, size) == size;
      } catch (...) {
        decoded = false;
      }
      if (!decoded) {
        bus->record_decode_failure("channel " + channel + ": message does not decode as " +
                                   T::getTypeName());
        return;
      }
      try {
        callback(message);
      } catch (const std::exception& e) {
        bus->record_failure(bus->callback_failures_,
                            "channel " + channel + ": callback threw: " + e.what());
      } catch (...) {
        bus->record_failure(bus->callback_failures_,
                            "channel " + channel + ": callback threw a non-std exception");
      }
    }

    LcmBus* bus;
    std::function<void(const T&)> callback;
  };

  void record_failure(std::atomic<std::uint64_t>& counter, std::string what) {
    counter.fetch_add(1);
    last_error_ = std::move(what);
  }
  void record_decode_failure(std::string what) {
    process_decode_failures_.fetch_add(1);
    record_failure(decode_failures_, std::move(what));
  }

  std::unique_ptr<lcm::LCM> owned_;
  lcm::LCM* lcm_ = nullptr;
  std::vector<std::unique_ptr<Subscription>> subscriptions_;
  SubscriptionId last_id_ = 0;
  std::atomic<std::uint64_t> decode_failures_{0};
  inline static std::atomic<std::uint64_t> process_decode_failures_{0};
  std::atomic<std::uint64_t> callback_failures_{0};
  std::string last_error_;
};

}  // namespace porter
