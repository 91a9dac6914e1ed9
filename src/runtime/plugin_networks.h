#pragma once
// An MLP model in the torch-free runtime: its networks (nn/coordinate_networks.h) evaluated by
// the MLP plugin through the C table of nn/mlp_plugin_abi.h. Every Eigen object and vector stays
// on this side; the plugin sees raw arrays sized here, and its handles are freed through it.
#include <string>

#include "nn/neural_fields.h"

namespace nsf {

// Loads MLP model file `path` through the plugin (runtime/mlp_plugin_library.h): the record the
// plugin makes of it and the plugin's networks, on `threads` threads (0: the plugin's default).
// Throws nsf::Error naming the file when the plugin is missing or refuses the model.
NeuralFields load_mlp_model(const std::string& path, int threads);

}  // namespace nsf
