#pragma once
/// @file parallel_for.h
/// Index-parallel loops for the diagnosis's cell evaluations (issue 36): each index is handled exactly once, by
/// one of `jobs` threads (the caller's among them), and writes only its own result slot, so every result, and any
/// reduction the caller does afterwards in index order, is the same for any number of jobs. The harness's case
/// workers (harness.cpp) follow the same pattern: an atomic next index, the caller working as one of the threads.

#include <cstddef>
#include <functional>

namespace tread_wear {
namespace diagnosis {

/// Threads that the default `--jobs` uses: the hardware's concurrency, at least 1.
int defaultJobs();

/// Calls fn(i) once for each i in [0, count) on min(jobs, count) threads. The first exception thrown by fn is
/// rethrown here after every thread has finished; the remaining indices are then skipped.
void parallelFor(std::size_t count, int jobs, const std::function<void(std::size_t)>& fn);

}  // namespace diagnosis
}  // namespace tread_wear
