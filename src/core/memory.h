#pragma once
// Peak resident memory of this process, for the memory figures users compare (ROM vs full order).

namespace nsf {

double peak_rss_mib();     // high-water mark since the process started (VmHWM)
double current_rss_mib();  // resident now (VmRSS)

}  // namespace nsf
