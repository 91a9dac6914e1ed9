#pragma once
// The process's BLAS and heap settings, without torch: OpenBLAS is looked up at run time (dlsym),
// so code that links no BLAS (the torch-free runtime) gets no-ops.
#include <string>

namespace nsf {

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

// An OpenBLAS entry point of the process (null without OpenBLAS): libtorch links libblas.so.3,
// which the alternatives system may point at OpenBLAS or at the reference BLAS, so linking them
// directly would fail for the latter.
void* blas_symbol(const char* name);
bool blas_is_openblas();
int blas_thread_count();  // OpenBLAS's current thread count; 0 without OpenBLAS

}  // namespace nsf
