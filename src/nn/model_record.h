#pragma once
// A model file's run-time record: everything the reduced-order runtime needs of a basis model,
// in a plain binary form that needs no torch to read (docs/TRAINING.md, "Model file"). Every save
// of a basis model (nsf train, calibrate, upgrade) stores it inside the model file, as one more
// entry of its zip, and the bases live there alone, so that libnsf_runtime.so loads basis models
// with the C++ standard library, Eigen and OpenMP. An MLP model's networks need LibTorch: its
// file has no record, and the runtime's MLP plugin (nn/mlp_plugin_abi.h) makes one from the
// torch archive when it loads the model.
#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "data/training_box.h"
#include "nn/basis_decoders.h"
#include "nn/config.h"
#include "nn/scene_fingerprint.h"

namespace nsf {

// Records that other layers keep of a model in its file, by name: texts (JSON) that nn stores and
// loads with the model without reading them. The ROM keeps its calibration so
// (rom/calibration/rom_calibration.h). A training run drops them: they described other fields.
using ModelAttachments = std::map<std::string, std::string>;

// Entries that model files of format versions 1-8 (run-time records of version 1) stored in their
// own names for another layer, now that layer's attachment: `entries`, a JSON object of those
// entries by their names, becomes the attachment they belong to, unless `attachments` holds it
// already. Nothing where `entries` is empty. (nn/model/model_file.cpp and model_record.cpp.)
void adopt_legacy_entries(ModelAttachments& attachments, const nlohmann::json& entries);

struct ModelRecord {
  SceneFingerprint scene;
  DecoderFamily family = DecoderFamily::basis;
  int latent_dim = 0;
  bool stress_uses_mu = false;
  double mu_min = 0, mu_max = 0;
  TrainingBox training_box;
  double train_seconds = 0;
  ModelAttachments attachments;   // as the model file's (the runtime reads them too)
  Eigen::VectorXd latent_spread;  // each latent component's spread over the training frames
  // The training runs' latents, runs × frames, and each run's μ (empty: not stored).
  std::vector<std::vector<Eigen::VectorXd>> trajectory_latents;
  std::vector<double> trajectory_mu;
  Eigen::VectorXd rest_latent;  // e(X), the encoder at the rest state (empty: not stored)
  std::shared_ptr<const BasisDecoders> bases;  // null for an MLP model
};

// The record as bytes ("NSFRTREC", a version, the payload's size and CRC-32, the payload).
std::string encode_model_record(const ModelRecord& record);
// Throws nsf::Error naming `path` when `bytes` is not a whole, undamaged record.
ModelRecord decode_model_record(std::string_view bytes, const std::string& path);
// Where a record starts inside an archive entry: the entry's first bytes.
bool is_model_record(const char* p, size_t n);

// The record inside model file `path`, its checksum and the record's own verified; nothing when
// the file holds none (an MLP model, or a basis model saved before nsf stored one). Throws
// nsf::Error naming the file when it cannot be read or is damaged.
std::optional<ModelRecord> find_model_record(const std::string& path);
// The same, where the file must hold one. Throws
// nsf::Error naming the file when it cannot be read, is damaged, or holds no record (an MLP model,
// or a basis model saved before nsf stored one), saying what to do.
ModelRecord read_model_record(const std::string& path);

}  // namespace nsf
