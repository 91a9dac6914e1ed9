#include "core/isa.h"

namespace nsf {

const char* kernel_isa() {
#if defined(NSF_HAS_CLONES)
  // The tests GCC's resolver makes for target_clones' arch= versions.
  __builtin_cpu_init();
  if (__builtin_cpu_supports("x86-64-v4")) return "x86-64-v4";
  if (__builtin_cpu_supports("x86-64-v3")) return "x86-64-v3";
  return "x86-64-v2";
#else
  return "as built";
#endif
}

}  // namespace nsf
