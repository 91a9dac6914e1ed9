#include "nn/torch_settings.h"

#include <ATen/Context.h>
#include <ATen/Parallel.h>
#include <ATen/Version.h>

#include <cstdlib>
#include <string>
#include <thread>

namespace nsf {

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
  if (auto set = reinterpret_cast<void (*)(int)>(blas_symbol("openblas_set_num_threads"))) {
    set(n);
    return n;
  }
  at::set_num_threads(n);  // no OpenBLAS: torch's own threads are the only parallelism
  return at::get_num_threads();
}

std::string blas_info() {
  auto config = reinterpret_cast<char* (*)()>(blas_symbol("openblas_get_config"));
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
