#include "core/memory.h"

#include <fstream>
#include <string>

namespace nsf {

namespace {
double status_field_mib(const char* field, const char* file = "/proc/self/status") {
  std::ifstream f(file);
  std::string key;
  while (f >> key) {
    if (key == field) {
      double kib = 0;
      f >> kib;
      return kib / 1024.0;
    }
    f.ignore(1 << 16, '\n');
  }
  return 0.0;
}
}  // namespace

double peak_rss_mib() {
  return status_field_mib("VmHWM:");
}
double current_rss_mib() {
  return status_field_mib("VmRSS:");
}

double available_memory_mib() {
  return status_field_mib("MemAvailable:", "/proc/meminfo");
}

bool reset_peak_rss() {
  std::ofstream f("/proc/self/clear_refs");
  f << "5";
  f.flush();
  return bool(f);
}

}  // namespace nsf
