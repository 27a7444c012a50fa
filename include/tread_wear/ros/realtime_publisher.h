#pragma once
/// @file realtime_publisher.h
/// Publishing from a real-time loop without allocation or blocking, after realtime_tools::RealtimePublisher
/// (not packaged in Debian): the loop fills a preallocated message and hands it over with try_lock; a
/// background thread copies and publishes it (serialisation allocates, so it must not happen in the loop).
/// Flags are std::atomic (realtime_tools' volatile bool is not a synchronisation primitive).

#include <ros/node_handle.h>
#include <ros/publisher.h>

#include <atomic>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>

namespace tread_wear {

template <class Msg>
class RealtimePublisher {
 public:
  RealtimePublisher(ros::NodeHandle& nh, const std::string& topic, int queue_size, bool latch = false)
      : publisher_(nh.advertise<Msg>(topic, queue_size, latch)), thread_(&RealtimePublisher::run, this) {}
  ~RealtimePublisher() { stop(); }
  RealtimePublisher(const RealtimePublisher&) = delete;
  RealtimePublisher& operator=(const RealtimePublisher&) = delete;

  /// Real-time side: true if the message slot was free; then fill msg() and call unlockAndPublish().
  bool trylock() {
    if (!mutex_.try_lock()) return false;
    if (pending_) {  // the previous message has not been taken yet: skip this one
      mutex_.unlock();
      return false;
    }
    return true;
  }
  Msg& msg() { return msg_; }
  void unlockAndPublish() {
    pending_ = true;
    mutex_.unlock();
    cv_.notify_one();
  }
  /// Messages the loop had to skip because the publisher thread was still busy [-].
  std::uint64_t skipped() const { return skipped_.load(); }
  void countSkip() { skipped_.fetch_add(1, std::memory_order_relaxed); }
  void stop() {
    if (!running_.exchange(false)) return;
    cv_.notify_one();
    if (thread_.joinable()) thread_.join();
  }

 private:
  void run() {
    Msg outgoing;
    while (running_) {
      {
        std::unique_lock<std::mutex> lock(mutex_);
        cv_.wait(lock, [this] { return pending_ || !running_; });
        if (!running_) return;
        outgoing = msg_;
        pending_ = false;
      }
      publisher_.publish(outgoing);
    }
  }

  ros::Publisher publisher_;
  Msg msg_;
  std::mutex mutex_;
  std::condition_variable cv_;
  bool pending_ = false;  // guarded by mutex_
  std::atomic<bool> running_{true};
  std::atomic<std::uint64_t> skipped_{0};
  std::thread thread_;
};

}  // namespace tread_wear
