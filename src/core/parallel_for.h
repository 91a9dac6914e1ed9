#pragma once
// A static-schedule OpenMP loop that, on one thread, runs inline without a thread team: libgomp
// makes a team of one for `omp parallel` even then (an `if` clause too) and wakes a futex at its
// end, a system call per loop that the reduced-order step, on one thread, pays several times a
// step. Iterations must be independent; their results do not depend on the thread count.
#include <omp.h>

namespace nsf {

template <typename Body>
void parallel_for(long n, Body&& body) {
  if (omp_get_max_threads() > 1) {
#pragma omp parallel for schedule(static)
    for (long i = 0; i < n; ++i) body(i);
  } else {
    for (long i = 0; i < n; ++i) body(i);
  }
}

}  // namespace nsf
