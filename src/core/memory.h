#pragma once
// Peak resident memory of this process, for the memory figures users compare (ROM vs full order).

namespace nsf {

double peak_rss_mib();     // high-water mark since the process started (VmHWM)
double current_rss_mib();  // resident now (VmRSS)
// Memory the kernel could hand out now without swapping (MemAvailable); 0 when unknown.
double available_memory_mib();
// Restarts the high-water mark at the current resident size (Linux ≥ 4.0, /proc/self/clear_refs),
// so that phases run one after another in one process each get their own peak. False if the
// kernel refused; the peak then still covers earlier phases.
bool reset_peak_rss();

}  // namespace nsf
