#include "nn/torch_settings.h"

#include <ATen/Context.h>
#include <ATen/Parallel.h>
#include <ATen/Version.h>
#include <dlfcn.h>
#include <malloc.h>

#include <cstdlib>
#include <string>
#include <thread>

namespace nsf {

namespace {

// OpenBLAS's entry points looked up at run time: libtorch links libblas.so.3, which the
// alternatives system may point at OpenBLAS or at the reference BLAS, so linking them directly
// would fail for the latter.
template <typename Fn>
Fn openblas_symbol(const char* name) {
  return reinterpret_cast<Fn>(dlsym(RTLD_DEFAULT, name));
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

int set_nn_threads(int requested, bool retain_memory) {
  if (retain_memory) retain_freed_memory();
  int n = requested > 0 ? requested : static_cast<int>(std::thread::hardware_concurrency());
  if (n < 1) n = 1;
  // The work is GEMM (Linear layers → OpenBLAS, its own thread pool). Torch's intra-op OpenMP
  // pool only runs the element-wise ops (ELU, Adam, losses: a few % of a step), and by default
  // its idle threads spin at every barrier, on the very cores OpenBLAS's threads need: measured
  // 80k vs 230k points/s for a width-96 decoder step with 2 + 2 threads on the shared 2-core
  // machine. So torch gets one thread and OpenBLAS gets n, unless the environment already
  // makes OpenMP threads sleep when idle (OMP_WAIT_POLICY=passive), read by libgomp at start-up.
  const char* policy = std::getenv("OMP_WAIT_POLICY");
  const bool passive =
      policy && (std::string(policy) == "passive" || std::string(policy) == "PASSIVE");
  at::set_num_threads(passive ? n : 1);
  if (auto set = openblas_symbol<void (*)(int)>("openblas_set_num_threads")) {
    set(n);
    return n;
  }
  at::set_num_threads(n);  // no OpenBLAS: torch's own threads are the only parallelism
  return at::get_num_threads();
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

std::string blas_info() {
  auto config = openblas_symbol<char* (*)()>("openblas_get_config");
  // pip's LibTorch (a CUDA build, docs/TRAINING.md) carries its own MKL instead of libblas.so.3.
  if (!config && at::show_config().find("BLAS_INFO=mkl") != std::string::npos)
    return "MKL, LibTorch's own (" + std::to_string(at::get_num_threads()) + " threads)";
  if (!config)
    return "WARNING: libblas.so.3 is not OpenBLAS (the reference BLAS is 6-10x slower); run "
           "scripts/install-deps.sh or `update-alternatives --config "
           "libblas.so.3-x86_64-linux-gnu`";
  return std::string("OpenBLAS ") + config() + " (" + std::to_string(blas_thread_count()) +
         " threads)";
}

void seed_torch(unsigned long long seed) {
  at::manual_seed(seed);
}

}  // namespace nsf
