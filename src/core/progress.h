#pragma once
// A one-line progress display with rate and ETA for long work (simulation, sweeps, training).
// On a terminal it redraws in place; otherwise (CI logs, pipes) it prints a line every few
// seconds so logs stay short.
#include <string>

namespace nsf {

class Progress {
 public:
  Progress(std::string label, long total, std::string unit = "");
  // `done` units finished; `extra` is appended (e.g. "1.9M particle-steps/s").
  void update(long done, const std::string& extra = "");
  void finish(const std::string& extra = "");  // prints the final line with total time

  static std::string format_seconds(double s);  // "1m05s", "3.2s"
  static std::string format_rate(double r);     // "1.94M", "820k"

 private:
  void print(long done, const std::string& extra, bool final);

  std::string label_, unit_;
  long total_;
  double start_, last_print_ = -1e9;
  bool tty_;
};

}  // namespace nsf
