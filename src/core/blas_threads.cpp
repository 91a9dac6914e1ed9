#include "core/blas_threads.h"

#include <dlfcn.h>
#include <malloc.h>

namespace nsf {

void* blas_symbol(const char* name) {
  return dlsym(RTLD_DEFAULT, name);
}

namespace {

template <typename Fn>
Fn openblas_symbol(const char* name) {
  return reinterpret_cast<Fn>(blas_symbol(name));
}

// OpenBLAS's thread count setter and getter, looked up once: the ROM sets the count around every
// step's fit, and a dlsym per call cost 3 % of its step (perf, metal_small).
using SetThreads = void (*)(int);
using GetThreads = int (*)();
SetThreads openblas_set_threads() {
  static const SetThreads f = openblas_symbol<SetThreads>("openblas_set_num_threads");
  return f;
}
GetThreads openblas_get_threads() {
  static const GetThreads f = openblas_symbol<GetThreads>("openblas_get_num_threads");
  return f;
}

}  // namespace

void retain_freed_memory() {
  // Every training step allocates the same activation and gradient tensors (0.1-10 MiB) and
  // frees them again. By default glibc serves such blocks with mmap, or trims them off the heap
  // top on free, so each step re-faults its pages in and zero-fills them: perf showed a third of
  // a stage-1 step in page faults and OpenBLAS's sgemm_beta touching fresh pages. Keeping them
  // in the heap doubled the Adam step of g at width 192 (bench/nn_throughput, allocator rows;
  // docs/BENCHMARKS.md, "The allocator").
  mallopt(M_MMAP_THRESHOLD, 32 << 20);  // glibc's maximum on 64-bit
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
}

ScopedBlasThreads::ScopedBlasThreads(int n) : previous_(blas_thread_count()) {
  const SetThreads set = openblas_set_threads();
  if (set && previous_ > 0 && previous_ != n) set(n);
}

ScopedBlasThreads::~ScopedBlasThreads() {
  const SetThreads set = openblas_set_threads();
  if (set && previous_ > 0 && blas_thread_count() != previous_) set(previous_);
}

int blas_thread_count() {
  const GetThreads get = openblas_get_threads();
  return get ? get() : 0;
}

bool blas_is_openblas() {
  return openblas_symbol<char* (*)()>("openblas_get_config") != nullptr;
}

}  // namespace nsf
