#pragma once
// The processor a measurement ran on, for the rows that quote speed: a speed-up measured in one
// process is still a property of the machine (docs/BENCHMARKS.md: the same ROM step runs about
// 2x slower per core on one 2-core host than on another).
#include <string>

namespace nsf {

// /proc/cpuinfo's first "model name" (x86), else its "Hardware" or "Model" line (ARM boards);
// "" where there is none.
std::string cpu_model();

}  // namespace nsf
