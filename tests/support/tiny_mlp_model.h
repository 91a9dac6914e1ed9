#pragma once
// A tiny MLP model (nsf train --decoder mlp) of scenes/examples/rom_tiny.json, trained by the
// `nsf` tool in a few seconds: for the tests of the runtime's MLP plugin (libnsf_mlp.so).
#include <filesystem>
#include <string>

#include "cli_runner.h"

namespace nsf::testing {

inline std::string rom_tiny_scene() {
  return (std::filesystem::path(NSF_SOURCE_DIR) / "scenes" / "examples" / "rom_tiny.json").string();
}

// Sweeps rom_tiny into DIR/data and trains DIR/tiny_mlp.nsf; the model's path, or "" with the
// tool's output in `log` when a step failed.
inline std::string train_tiny_mlp(const std::filesystem::path& dir, std::string& log) {
  const std::string data = "'" + (dir / "data").string() + "'";
  const std::string model = (dir / "tiny_mlp.nsf").string();
  if (run_cli("sweep '" + rom_tiny_scene() + "' --out " + data + " --jobs 2 -j 1 -q", log) != 0)
    return "";
  if (run_cli("train " + data + " --out '" + model +
                  "' --decoder mlp -r 2 --depth 2 --widths 32,16,16 --encoder-hidden 8"
                  " --steps 100,50,50 --refine-latents 0 -j 2 -q"
                  " --frames-per-batch 2 --particles-per-frame 64",
              log) != 0)
    return "";
  return model;
}

}  // namespace nsf::testing
