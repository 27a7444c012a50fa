#pragma once
/// @file loop_clock.h
/// The clocks of the nodes' loops and their records, once for the wear pipeline and both ROS nodes: a steady clock
/// for durations and deadlines, the wall clock for what is stored (save times), the thread's CPU clock, and a
/// lock-free running maximum for a figure the loop writes and a diagnostic reads. Allocation- and lock-free.

#include <time.h>

#include <atomic>
#include <chrono>

namespace tread_wear {

/// Steady (monotonic) time [s]: only differences mean anything.
inline double steadyNow_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

/// Wall-clock time since the Unix epoch [s].
inline double wallNow_s() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

/// CPU time of the calling thread [s].
inline double threadCpuNow_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

/// a = max(a, v), safe against concurrent writers.
inline void atomicMax(std::atomic<double>& a, double v) {
  double cur = a.load(std::memory_order_relaxed);
  while (v > cur && !a.compare_exchange_weak(cur, v, std::memory_order_relaxed)) {
  }
}

}  // namespace tread_wear
