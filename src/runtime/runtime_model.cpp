#include "runtime/runtime_model.h"

#include "nn/coordinate_networks.h"
#include "runtime/plugin_networks.h"

namespace nsf {

NeuralFields load_runtime_model(const std::string& path, int threads) {
  std::optional<ModelRecord> record = find_model_record(path);
  // Every basis model nsf saves holds its record; an MLP model's file holds none (and a basis
  // model saved before nsf stored one, which the plugin refuses, saying so).
  if (!record || record->family == DecoderFamily::mlp) return load_mlp_model(path, threads);
  return NeuralFields::from_record(std::move(*record));
}

}  // namespace nsf
