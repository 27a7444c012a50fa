#pragma once
/// @file allocation_counter.h
/// Counts the heap allocations of the calling thread, for the tests that hold a real-time path to "no allocation
/// per cycle". Replaces the global operator new/delete: include it in exactly one source file of a test binary.
/// Per thread, because some parts under test (the realtime publishers) allocate on their own threads by design.

#include <cstdlib>
#include <new>

// GCC pairs the inlined replacement delete's free() with the standard operator new it assumes; both are malloc here.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"

namespace {
/// Allocations made so far by this thread.
thread_local long t_allocations = 0;
}  // namespace

void* operator new(std::size_t n) {
  ++t_allocations;
  if (void* p = std::malloc(n == 0 ? 1 : n)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) { return operator new(n); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
