// Loads a model through the embedding API (include/nsf/runtime.h) and times it: the load (model
// file, scene, the stepper's set-up) and each frame of advance_frame(). Built and run by
// bench/runtime.py against each runtime it compares, and by bench/runtime_mlp.py; prints one JSON
// object.
//   step_timer MODEL SCENE MU THREADS
#include <nsf/runtime.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  if (argc != 5) {
    std::fprintf(stderr, "usage: %s MODEL SCENE MU THREADS\n", argv[0]);
    return 2;
  }
  using Clock = std::chrono::steady_clock;
  const auto seconds = [](Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double>(b - a).count();
  };
  try {
    nsf::RuntimeOptions options;
    options.mu = std::stod(argv[3]);
    options.threads = std::atoi(argv[4]);
    const Clock::time_point t0 = Clock::now();
    nsf::Runtime rom(argv[1], argv[2], options);
    const double load = seconds(t0, Clock::now());
    std::vector<double> frames;
    std::vector<float> x(3 * rom.particle_count());
    for (int f = 0; f < rom.frame_count(); ++f) {
      const Clock::time_point a = Clock::now();
      rom.advance_frame();
      frames.push_back(seconds(a, Clock::now()));
    }
    rom.positions(x.data(), x.size());
    double checksum = 0;
    for (float v : x) checksum += double(v);
    std::printf("{\"load_s\": %.6f, \"frame_s\": [", load);
    for (size_t f = 0; f < frames.size(); ++f) std::printf("%s%.6f", f ? ", " : "", frames[f]);
    std::printf("], \"steps_per_frame\": %d, \"sum_positions\": %.9g, \"build_arch\": \"%s\"}\n",
                rom.steps_per_frame(), checksum, nsf::build_arch());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "step_timer: %s\n", e.what());
    return 1;
  }
  return 0;
}
