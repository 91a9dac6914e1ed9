#pragma once
// `nsf train` as a child process on the tiny synthetic dataset of nn_fixtures.h, with networks
// small enough to train in a few seconds: for the command-line tests of training and its files.
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "cli_runner.h"
#include "nn_fixtures.h"

namespace nsf::testing {

constexpr int kTinyParticles = 300;  // 4 training runs of 12 frames, 1 test run

// Shapes and steps of a model that trains in seconds (g's weights are 64 x 64: a tensor of 16 KiB),
// and its batches.
inline const char* kTinyTrainFlags =
    " -r 2 --depth 2 --widths 64,8,8 --encoder-hidden 8 --steps 20,5,5"
    " --refine-latents 0 -j 1 -q";
inline const char* kTinyBatchFlags = " --frames-per-batch 2 --particles-per-frame 16";

inline std::string quoted(const std::filesystem::path& p) {
  return "'" + p.string() + "'";
}

// `nsf train DATA --out MODEL` with the tiny flags, `extra`, and `batches`.
inline CliResult train_tiny(const std::filesystem::path& data, const std::filesystem::path& model,
                            const std::string& extra = "",
                            const std::string& batches = kTinyBatchFlags) {
  return run_cli("train " + quoted(data) + " --out " + quoted(model) + kTinyTrainFlags + " " +
                 extra + batches);
}

inline std::string file_bytes(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

}  // namespace nsf::testing
