#pragma once
// The model of a runtime: a basis model from its file's run-time record, torch-free; an MLP model
// (a file without a record) through the MLP plugin (runtime/plugin_networks.h), which the
// runtime loads for it alone.
#include <string>

#include "nn/neural_fields.h"

namespace nsf {

// Throws nsf::Error naming the file when it cannot be used; for an MLP model without the plugin,
// naming the files looked for and how to get it (runtime/mlp_plugin_library.h).
NeuralFields load_runtime_model(const std::string& path, int threads);

}  // namespace nsf
