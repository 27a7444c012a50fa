#pragma once
/// @file realtime_publisher.h
/// Publishing from a real-time loop without allocation or blocking, after realtime_tools::RealtimePublisher
/// (not packaged in Debian): the loop fills a preallocated message and hands it over with try_lock; a
/// background thread copies it and passes the copy to the sink (a ros::Publisher in the node, a recorder in the
/// tests), since serialisation allocates and must not happen in the loop. Flags are std::atomic (realtime_tools'
/// volatile bool is not a synchronisation primitive).

#include <ros/publisher.h>

#include <atomic>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>
#include <utility>

namespace tread_wear {

template <class Msg>
class RealtimePublisher {
 public:
  using Sink = std::function<void(const Msg&)>;

  /// Publishes on `publisher` (an advertised handle; copies share the advertisement).
  explicit RealtimePublisher(ros::Publisher publisher)
      : RealtimePublisher(Sink([publisher](const Msg& m) { publisher.publish(m); })) {}
  explicit RealtimePublisher(Sink sink) : sink_(std::move(sink)), thread_(&RealtimePublisher::run, this) {}
  ~RealtimePublisher() { stop(); }
  RealtimePublisher(const RealtimePublisher&) = delete;
  RealtimePublisher& operator=(const RealtimePublisher&) = delete;

  /// Real-time side: true if the message slot is free; then fill msg() and call unlockAndPublish(). false while
  /// the publisher thread holds the slot or has not taken the previous message yet: the caller skips this one.
  bool trylock() {
    if (!mutex_.try_lock()) return false;
    if (pending_) {
      mutex_.unlock();
      return false;
    }
    return true;
  }
  /// Off the real-time path (a replay in input time, where every message counts): waits until the publisher thread
  /// has taken the previous message, then holds the slot as a successful trylock() does. false once stopped.
  bool lock() {
    std::unique_lock<std::mutex> lock(mutex_);
    taken_.wait(lock, [this] { return !pending_ || !running_; });
    if (!running_) return false;
    lock.release();
    return true;
  }
  /// The preallocated message; only between a successful trylock() or lock() and unlockAndPublish().
  Msg& msg() { return msg_; }
  void unlockAndPublish() {
    pending_ = true;
    mutex_.unlock();
    cv_.notify_one();
  }
  /// Ends the publisher thread (a message not taken yet is dropped); idempotent.
  void stop() {
    if (!running_.exchange(false)) return;
    {
      // Under the lock, so that the thread cannot miss the notification between its check and its wait.
      std::lock_guard<std::mutex> lock(mutex_);
    }
    cv_.notify_one();
    taken_.notify_all();
    if (thread_.joinable()) thread_.join();
  }

 private:
  void run() {
    Msg outgoing;
    while (true) {
      {
        std::unique_lock<std::mutex> lock(mutex_);
        cv_.wait(lock, [this] { return pending_ || !running_; });
        if (!running_) return;
        outgoing = msg_;
        pending_ = false;
      }
      taken_.notify_all();
      sink_(outgoing);
    }
  }

  Sink sink_;
  Msg msg_;
  std::mutex mutex_;
  std::condition_variable cv_;
  std::condition_variable taken_;  ///< the thread took a message: the slot is free for lock()
  bool pending_ = false;  // guarded by mutex_
  std::atomic<bool> running_{true};
  std::thread thread_;  // last: starts once everything above is constructed
};

}  // namespace tread_wear
