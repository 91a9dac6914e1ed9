#pragma once
// Process-wide settings for LibTorch, without torch in the header.
#include <string>

namespace nsf {

// Sets torch's intra-op threads and OpenBLAS's own pool to `requested` (0 = all cores) so the
// two do not oversubscribe the cores; returns the count in use.
int set_nn_threads(int requested);

// Which BLAS the process actually loaded: "OpenBLAS 0.3.21 … (2 threads)", or a warning when
// it is not OpenBLAS (the reference BLAS is 6–10× slower; see scripts/install-deps.sh).
std::string blas_info();
bool blas_is_openblas();

// Seeds torch's global generator (network initialisation).
void seed_torch(unsigned long long seed);

}  // namespace nsf
