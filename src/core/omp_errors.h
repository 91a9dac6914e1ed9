#pragma once
// An exception must not leave an OpenMP parallel region or critical section: GCC then calls
// std::terminate, so a damaged input file ends in SIGABRT instead of a message naming it. Code
// inside a region runs its work through capture_exception, keeps what it returns, and the
// caller rethrows after the region (rethrow_first).
#include <exception>
#include <vector>

namespace nsf {

// Runs f; returns the exception it threw, or null.
template <typename F>
std::exception_ptr capture_exception(F&& f) noexcept {
  try {
    f();
  } catch (...) {
    return std::current_exception();
  }
  return nullptr;
}

// Rethrows the first captured exception, if any: with one slot per loop index, the lowest index
// that failed, whatever the thread count.
inline void rethrow_first(const std::vector<std::exception_ptr>& errors) {
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
}

}  // namespace nsf
