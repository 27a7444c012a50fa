#include "tread_wear/diagnosis/parallel_for.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace tread_wear {
namespace diagnosis {
namespace {

/// Indices a thread takes at a time: one brush evaluation costs 5 us (fast) to 4 ms (reference), so a block of 8
/// keeps the shared counter out of the profile without leaving one thread a long tail.
constexpr std::size_t kBlock = 8;

}  // namespace

int defaultJobs() { return std::max(1, static_cast<int>(std::thread::hardware_concurrency())); }

void parallelFor(std::size_t count, int jobs, const std::function<void(std::size_t)>& fn) {
  const std::size_t threads = std::min<std::size_t>(static_cast<std::size_t>(std::max(1, jobs)), count);
  if (threads <= 1) {
    for (std::size_t i = 0; i < count; ++i) fn(i);
    return;
  }
  std::atomic<std::size_t> next{0};
  std::atomic<bool> failed{false};
  std::exception_ptr first_error;
  std::mutex error_lock;
  auto worker = [&] {
    for (;;) {
      const std::size_t begin = next.fetch_add(kBlock);
      if (begin >= count || failed.load()) return;
      const std::size_t end = std::min(count, begin + kBlock);
      try {
        for (std::size_t i = begin; i < end; ++i) fn(i);
      } catch (...) {
        std::lock_guard<std::mutex> lock(error_lock);
        if (!first_error) first_error = std::current_exception();
        failed = true;
        return;
      }
    }
  };
  std::vector<std::thread> pool;
  for (std::size_t t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();
  if (first_error) std::rethrow_exception(first_error);
}

}  // namespace diagnosis
}  // namespace tread_wear
