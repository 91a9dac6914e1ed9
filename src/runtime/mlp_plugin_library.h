#pragma once
// Finding and opening the MLP plugin (libnsf_mlp.so, src/plugin/), which the runtime loads with
// dlopen only for an MLP model, so that libnsf_runtime.so itself links no LibTorch. Looked for,
// in order (docs/EMBEDDING.md, "MLP models"):
//   $NSF_MLP_PLUGIN, a path to the file: where it is set, there alone;
//   beside the runtime library (the build tree), then in nsf/ beside it (where `cmake --install`
//   puts it: LIBDIR/nsf/libnsf_mlp.so); for the runtime's glibc-hwcaps copy, beside the baseline
//   copy two folders up.
// The library, once opened, stays loaded for the process (LibTorch does not unload cleanly).
#include <string>
#include <vector>

#include "nn/mlp_plugin_abi.h"

namespace nsf {

inline constexpr const char* kMlpPluginFile = "libnsf_mlp.so";
inline constexpr const char* kMlpPluginVariable = "NSF_MLP_PLUGIN";

// The files looked for, in order. `env` is $NSF_MLP_PLUGIN (null or empty: unset), `runtime_dir`
// the folder of the runtime library.
std::vector<std::string> mlp_plugin_candidates(const char* env, const std::string& runtime_dir);

// The table of the first candidate that is a usable plugin (its ABI version and nsf version the
// runtime's), for model file `model`; each file is opened once per process. Throws nsf::Error
// naming the model, every file looked for and why each failed, and how to get the plugin.
const nsf_mlp_plugin& mlp_plugin(const std::string& model);

}  // namespace nsf
