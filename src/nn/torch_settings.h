#pragma once
// Process-wide settings for LibTorch, without torch in the header.
#include <string>

namespace nsf {

// Uses `requested` threads (0 = all cores) for the networks: OpenBLAS's pool gets them all (the
// GEMMs are nearly all the work); torch's intra-op OpenMP pool gets one thread unless
// OMP_WAIT_POLICY=passive, since idle libgomp threads otherwise spin on the cores OpenBLAS
// needs. Also calls retain_freed_memory() unless told not to. Returns the thread count of the
// GEMMs.
int set_nn_threads(int requested, bool retain_memory = true);

// Keeps freed blocks up to 32 MiB in the process's heap (glibc mallopt) instead of handing them
// back to the kernel, so that the tensors every step allocates anew do not page-fault again.
// The price: memory freed after a peak stays with the process until it exits.
void retain_freed_memory();

// Runs the GEMMs of a scope on `n` threads and restores the previous count on exit. For work
// on a few hundred points (the Gauss–Newton fit on the sample particles), where splitting each
// small GEMM across threads costs more than it saves. No effect without OpenBLAS.
class ScopedBlasThreads {
 public:
  explicit ScopedBlasThreads(int n);
  ~ScopedBlasThreads();
  ScopedBlasThreads(const ScopedBlasThreads&) = delete;
  ScopedBlasThreads& operator=(const ScopedBlasThreads&) = delete;

 private:
  int previous_ = 0;
};

// Which BLAS the process actually loaded: "OpenBLAS 0.3.21 … (2 threads)", or a warning when
// it is not OpenBLAS (the reference BLAS is 6–10× slower; see scripts/install-deps.sh).
std::string blas_info();
bool blas_is_openblas();
int blas_thread_count();  // OpenBLAS's current thread count; 0 without OpenBLAS

// Seeds torch's global generator (network initialisation).
void seed_torch(unsigned long long seed);

}  // namespace nsf
