#pragma once
// Run-time choice of instruction set for the hot kernels. Every installed artefact is built for a
// baseline (x86-64-v2 unless NSF_ARCH says otherwise, CMakeLists.txt); a function marked
// NSF_CLONES is also compiled for x86-64-v3 (AVX2, FMA) and x86-64-v4 (AVX-512), and the
// dynamic loader picks the best one the CPU has (GCC's target_clones, through an ifunc). Off where
// that cannot work: other compilers, CPUs or C libraries, and builds for the building machine
// alone (NSF_NATIVE, which defines NSF_NO_CLONES). Clones cannot be virtual (GCC), and Eigen picks
// its packets when a file is compiled, so a cloned kernel does its 4-wide arithmetic in
// nsf::simd4 (GCC vector extensions, lowered per clone) rather than in Eigen types.
#include <cstring>  // before the test: it defines __GLIBC__

#if defined(__x86_64__) && defined(__GNUC__) && defined(__linux__) && defined(__GLIBC__) && \
    !defined(NSF_NO_CLONES)
#define NSF_CLONES __attribute__((target_clones("default", "arch=x86-64-v3", "arch=x86-64-v4")))
#define NSF_HAS_CLONES 1
#else
#define NSF_CLONES
#endif

namespace nsf {

// The version of the cloned kernels this CPU runs: "x86-64-v4", "x86-64-v3" or "x86-64-v2", or,
// in a build without clones, "as built" (`nsf --version`).
const char* kernel_isa();

// Four doubles as one vector: two SSE2 registers in the baseline clone, one AVX register in
// the v3 and v4 clones.
#if defined(__GNUC__)
typedef double simd4 __attribute__((vector_size(32)));
#else
#error "nsf's kernels need GCC or Clang vector extensions"
#endif

// Unaligned loads and stores. A simd4 goes by reference, never by value: passing one by value
// would depend on the ISA of the caller (GCC's -Wpsabi).
inline void load4(simd4& v, const double* p) {
  std::memcpy(&v, p, sizeof v);
}
inline void store4(double* p, const simd4& v) {
  std::memcpy(p, &v, sizeof v);
}

}  // namespace nsf
