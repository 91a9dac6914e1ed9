#pragma once
// Runs a simulation to the end and writes every frame (initial state included) to one run file:
// the frame loop shared by `nsf simulate` and `nsf sweep`. The file also records where the
// colliders went (attribute collider_envelope, data/training_box.h).
#include <functional>
#include <map>
#include <string>

#include "io/run_writer.h"
#include "mpm/simulation.h"

namespace nsf {

// Extra root attributes for the run file (RunWriter::set_attribute), e.g. "mu" and "split".
struct RunAttributes {
  std::map<std::string, double> numbers;
  std::map<std::string, std::string> strings;
};

// Called after each saved frame f = 1 … frames.
using FrameCallback = std::function<void(int frame)>;

// Writes <path>.tmp while running and renames it to <path> only at the end, so an interrupted
// run leaves no file under the final name. `options`: the file's compression.
void run_to_file(Simulation& sim, const std::string& path, const RunAttributes& attributes = {},
                 const FrameCallback& on_frame = {}, const RunWriterOptions& options = {});

}  // namespace nsf
