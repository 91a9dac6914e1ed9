#pragma once
// Process-wide settings for LibTorch, without torch in the header.
#include <string>

#include "core/blas_threads.h"

namespace nsf {

// Uses `requested` threads (0 = all cores) for the networks: OpenBLAS's pool gets them all (the
// GEMMs are nearly all the work); torch's intra-op OpenMP pool gets one thread unless
// OMP_WAIT_POLICY=passive, since idle libgomp threads otherwise spin on the cores OpenBLAS
// needs. Also calls retain_freed_memory() unless told not to. Returns the thread count of the
// GEMMs.
int set_nn_threads(int requested, bool retain_memory = true);

// Which BLAS the process actually loaded: "OpenBLAS 0.3.21 … (2 threads)", or a warning when
// it is not OpenBLAS (the reference BLAS is 6–10× slower; see scripts/install-deps.sh).
std::string blas_info();

// Seeds torch's global generator (network initialisation).
void seed_torch(unsigned long long seed);

}  // namespace nsf
