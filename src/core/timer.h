#pragma once
// Accumulating wall-clock timers for the per-phase breakdown printed by benchmarks and the CLI.
#include <chrono>

namespace nsf {

class PhaseTimer {
 public:
  double seconds() const { return total_; }
  long calls() const { return calls_; }
  void add(double s) {
    total_ += s;
    ++calls_;
  }
  void reset() { total_ = 0, calls_ = 0; }

 private:
  double total_ = 0;
  long calls_ = 0;
};

// Adds the lifetime of the scope to a PhaseTimer.
class ScopedTimer {
 public:
  explicit ScopedTimer(PhaseTimer& t) : t_(t), start_(std::chrono::steady_clock::now()) {}
  ~ScopedTimer() {
    t_.add(std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count());
  }
  ScopedTimer(const ScopedTimer&) = delete;
  ScopedTimer& operator=(const ScopedTimer&) = delete;

 private:
  PhaseTimer& t_;
  std::chrono::steady_clock::time_point start_;
};

inline double now_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace nsf
