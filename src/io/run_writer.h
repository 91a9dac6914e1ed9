#pragma once
// Writes one simulation run to HDF5 (layout: docs/OUTPUT.md). The file is written under
// "<path>.tmp" and renamed to <path> by finish(), so a crashed, interrupted or failed run never
// leaves a file that looks complete; a writer destroyed without finish() deletes its temp file.
#include <cstdint>
#include <memory>
#include <string>
#include <type_traits>

#include "mpm/particles.h"
#include "mpm/scene/scene.h"

namespace nsf {

struct RunWriterOptions {
  // 0 = off. Level 1 with byte shuffling roughly halves smooth trajectories but costs time per
  // frame; off by default because the simulator, not disk space, is the usual bottleneck.
  int gzip_level = 0;
};

class RunWriter {
 public:
  // Creates <path>.tmp and writes the static per-particle data (/X, /mass, /volume, /material,
  // /object) and the root attributes. Does not write a frame: call write_frame for the initial
  // state too if it should be in the file.
  RunWriter(const std::string& path, const Particles& p, const SimSettings& s,
            const std::string& scene_name, const std::string& scene_json,
            const RunWriterOptions& options = {});
  ~RunWriter();
  RunWriter(RunWriter&&) noexcept;
  RunWriter& operator=(RunWriter&&) noexcept;
  RunWriter(const RunWriter&) = delete;
  RunWriter& operator=(const RunWriter&) = delete;

  // Appends x, v, C, F, τ and the time of every particle as the next frame. The particle count
  // must not change during a run.
  void write_frame(const Particles& p, double time);

  // Root attributes a caller adds, e.g. the sweep parameter "mu". Replaces one of the same name.
  void set_attribute(const std::string& name, double value);
  void set_attribute(const std::string& name, const std::string& value);
  void set_attribute(const std::string& name, const char* value) {
    set_attribute(name, std::string(value));
  }
  template <typename Int,
            typename = std::enable_if_t<std::is_integral_v<Int> && !std::is_same_v<Int, bool>>>
  void set_attribute(const std::string& name, Int value) {
    set_int_attribute(name, static_cast<int64_t>(value));
  }

  // A table a caller adds beside the frames, written at once: rows × cols doubles (row-major) at
  // `name`, which must lie outside the layout's own datasets (e.g. "/rom/latent").
  void write_table(const std::string& name, size_t rows, size_t cols, const double* data);

  // Closes the file and renames it to the final path. Nothing may be written afterwards.
  void finish();

  size_t frames_written() const;
  const std::string& path() const;

 private:
  void set_int_attribute(const std::string& name, int64_t value);

  struct Impl;
  Impl& live(const char* call) const;  // the Impl, or fails if finished, broken or moved-from
  std::unique_ptr<Impl> impl_;
};

}  // namespace nsf
