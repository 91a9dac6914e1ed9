#pragma once
// The trained model as a whole: encoder, the decoders of its family, normalisation statistics,
// the parameter range and the scene it was trained for. One file on disk (docs/TRAINING.md). Torch
// level; the runtime facade without torch types is nn/neural_fields.h. Its parts are defined by
// job in nn/model/: the networks built and moved here (neural_model.cpp), the encoder
// (encoder.cpp), an MLP model's decoders g, h, l (mlp_decoders.cpp), a basis model's fields and
// coefficients (basis_fields.h), the normalisation (normalizer.h) and the file with its format
// versions (model_file.cpp).
#include <torch/serialize/archive.h>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "core/types.h"
#include "data/training_box.h"
#include "nn/config.h"
#include "nn/model/basis_fields.h"
#include "nn/model/normalizer.h"
#include "nn/model_record.h"
#include "nn/networks.h"
#include "nn/scene_fingerprint.h"

namespace nsf {

class NeuralModel {
 public:
  NeuralModel(const NetConfig& config, const SceneFingerprint& scene, bool has_mu);

  // ---- the model file (model_file.cpp) ----
  // Atomic: written to "<path>.tmp" and renamed, so a crash never leaves a half model.
  void save(const std::string& path) const;
  // Throws nsf::Error naming the file for a missing, foreign or damaged file.
  static NeuralModel load(const std::string& path);

  // Archive form, shared by the model file and the training checkpoint. bases_in_record: the
  // bases' means and modes are left out (save() stores them in the run-time record).
  void write(torch::serialize::OutputArchive& a, bool bases_in_record = false) const;
  static NeuralModel read(torch::serialize::InputArchive& a, const std::string& path);

  bool stress_has_mu() const { return has_mu && config.stress_uses_mu; }
  bool is_basis() const { return config.decoder == DecoderFamily::basis; }
  int64_t latent_dim() const { return config.latent_dim; }
  // Throws nsf::Error when `data` (what: e.g. the dataset path) is another scene.
  void check_scene(const SceneFingerprint& data, const std::string& what) const;

  // ---- batched evaluation, physical units in and out (float32) ----
  // x: B × |P| × 3 current positions → B × r latents (encoder.cpp).
  torch::Tensor encode(const torch::Tensor& x);
  // An MLP model's decoders (mlp_decoders.cpp). Their inputs per point: Xn = normalised rest
  // positions (N × 3), z = latents (N × r), mu (N × 1, physical; ignored unless
  // stress_has_mu()).
  torch::Tensor deform(const torch::Tensor& Xn, const torch::Tensor& z);  // N × 3
  torch::Tensor stress(const torch::Tensor& Xn, const torch::Tensor& z,
                       const torch::Tensor& mu);                          // N × 6
  torch::Tensor affine(const torch::Tensor& Xn, const torch::Tensor& z);  // N × 9
  // The normalised decoder inputs the trainer and the functions above share.
  torch::Tensor g_input(const torch::Tensor& Xn, const torch::Tensor& z) const;
  torch::Tensor h_input(const torch::Tensor& Xn, const torch::Tensor& z,
                        const torch::Tensor& mu) const;
  torch::Tensor l_input(const torch::Tensor& Xn, const torch::Tensor& z) const;

  void set_eval_mode();
  // Every network and tensor onto `device` (training on a GPU: nn/train/trainer.h); a model is
  // saved, loaded and run on the CPU.
  void to(const torch::Device& device);

  // ---- basis models (basis_fields.cpp): coefficients of field f (0: x − X, 1: τ, 2: C) in
  // physical units, B × K, for raw latents z (B × r) and μ (B × 1, physical; used by τ when
  // stress_has_mu()).
  torch::Tensor coefficients(int field, const torch::Tensor& z, const torch::Tensor& mu);
  torch::Tensor coefficient_input(int field, const torch::Tensor& z, const torch::Tensor& mu) const;

  NetConfig config;
  SceneFingerprint scene;
  bool has_mu = false;
  double mu_min = 0, mu_max = 0;
  // The swept values' ranges and the colliders' envelopes over the training runs
  // (data/training_box.h); empty in files written before nsf recorded it.
  TrainingBox training_box;
  Encoder encoder{nullptr};
  FieldMlp g{nullptr}, h{nullptr}, l{nullptr};  // mlp models
  BasisField basis[3];                          // basis models: x − X, τ, C
  // X: rest positions, x: current positions (also the encoder's input), z: latents as seen by
  // h and l (g learns with raw encoder output), mu, tau (6), C (9).
  Normalizer norm_X, norm_x, norm_z, norm_mu, norm_tau, norm_C;
  // Displacement form (format version 2): the encoder sees u = x − X and g predicts u, both
  // normalised by norm_u; deform() adds X back. The rest shape, identical in every frame, no
  // longer swamps the frame-to-frame signal. Off for models of format version 1 (x, norm_x).
  bool displacement = true;
  Normalizer norm_u;
  torch::Tensor rest;  // |P| × 3 physical rest positions X (float32), set with displacement
  // The latents h and l were trained on, one row per frame of each training run (runs × frames ×
  // r, float32), and each run's μ (runs; zeros without μ): the region of latent space the ROM's
  // latent prior holds its inversion near (rom/inversion/latent_prior.h). Undefined in older
  // model files.
  torch::Tensor trajectory_latents, trajectory_mu;
  // Wall time of the training that made this model, all stages (and resumed runs) together;
  // 0 in files written before nsf recorded it.
  double train_seconds = 0;
  // Other layers' records of this model, by name (nn/model_record.h, ModelAttachments): stored in
  // its file, never read here.
  ModelAttachments attachments;
  // The run-time record (nn/model_record.h) of the file it was loaded from; null where the file
  // has none. save() writes a fresh one.
  std::shared_ptr<const ModelRecord> stored_record;
};

}  // namespace nsf
