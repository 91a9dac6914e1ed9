#include "core/progress.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>

#include "core/timer.h"

namespace nsf {

Progress::Progress(std::string label, long total, std::string unit)
    : label_(std::move(label)),
      unit_(std::move(unit)),
      total_(total),
      start_(now_seconds()),
      tty_(isatty(fileno(stderr))) {}

std::string Progress::format_seconds(double s) {
  char buf[32];
  if (!std::isfinite(s)) return "?";
  if (s < 60)
    std::snprintf(buf, sizeof buf, "%.1fs", s);
  else if (s < 3600)
    std::snprintf(buf, sizeof buf, "%dm%02ds", int(s) / 60, int(s) % 60);
  else
    std::snprintf(buf, sizeof buf, "%dh%02dm", int(s) / 3600, (int(s) % 3600) / 60);
  return buf;
}

std::string Progress::format_rate(double r) {
  char buf[32];
  if (r >= 1e9)
    std::snprintf(buf, sizeof buf, "%.2fG", r / 1e9);
  else if (r >= 1e6)
    std::snprintf(buf, sizeof buf, "%.2fM", r / 1e6);
  else if (r >= 1e3)
    std::snprintf(buf, sizeof buf, "%.1fk", r / 1e3);
  else
    std::snprintf(buf, sizeof buf, "%.1f", r);
  return buf;
}

void Progress::update(long done, const std::string& extra) {
  const double now = now_seconds();
  if (now - last_print_ < (tty_ ? 0.2 : 5.0) && done < total_) return;
  last_print_ = now;
  print(done, extra, false);
}

void Progress::finish(const std::string& extra) {
  print(total_, extra, true);
}

void Progress::print(long done, const std::string& extra, bool final) {
  const double elapsed = now_seconds() - start_;
  const double frac = total_ > 0 ? double(done) / total_ : 1.0;
  char line[512];
  if (final) {
    std::snprintf(line, sizeof line, "%s %ld/%ld%s%s done in %s%s%s", label_.c_str(), done, total_,
                  unit_.empty() ? "" : " ", unit_.c_str(), format_seconds(elapsed).c_str(),
                  extra.empty() ? "" : ", ", extra.c_str());
  } else {
    const double eta = done > 0 ? elapsed * (1.0 - frac) / frac : NAN;
    std::snprintf(line, sizeof line, "%s %ld/%ld%s%s (%3.0f%%)%s%s, elapsed %s, ETA %s",
                  label_.c_str(), done, total_, unit_.empty() ? "" : " ", unit_.c_str(),
                  100.0 * frac, extra.empty() ? "" : ", ", extra.c_str(),
                  format_seconds(elapsed).c_str(), format_seconds(eta).c_str());
  }
  if (tty_)
    std::fprintf(stderr, "\r\033[K%s%s", line, final ? "\n" : "");
  else
    std::fprintf(stderr, "%s\n", line);
  std::fflush(stderr);
}

}  // namespace nsf
