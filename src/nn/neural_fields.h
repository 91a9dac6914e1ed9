#pragma once
// Run-time access to a trained model without torch in the interface: the reduced-order stepper,
// `nsf eval` and other programs evaluate the encoder e and the fields g, h, l over many
// particles per call. Latents and results are double at the interface; the networks run in float.
// Loaded with load_basis(), it needs no torch at all (the model file's run-time record,
// nn/model_record.h), and serves basis models; load() (libnsf_nn) adds the networks, and
// from_record() takes them from elsewhere (the runtime's MLP plugin).
#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "core/types.h"
#include "data/training_box.h"
#include "nn/config.h"
#include "nn/model_record.h"

namespace nsf {

class CoordinateNetworks;
class SampleDeformation;

using Latent = Eigen::VectorXd;  // ẑ ∈ R^r

class NeuralFields {
 public:
  // Loads a model file (nsf train) of either family with LibTorch: the encoder, an MLP model's
  // networks (defined in libnsf_nn, nn/torch_networks.cpp). A basis model's fields
  // are its run-time record's (nn/model_record.h), as load_basis() gives them. Throws nsf::Error
  // naming the file when it cannot be used.
  static NeuralFields load(const std::string& path);
  // Loads a basis model from its file's run-time record, without torch (the runtime). Throws
  // nsf::Error naming the file when it cannot be used: an MLP model, or a file without a
  // record, among them.
  static NeuralFields load_basis(const std::string& path);
  // A model from its run-time record and, for an MLP model, networks that another layer supplies
  // (the runtime's MLP plugin, runtime/plugin_networks.h). Throws nsf::Error when an MLP record
  // comes without networks, or a basis record with them.
  static NeuralFields from_record(ModelRecord record,
                                  std::unique_ptr<CoordinateNetworks> networks = nullptr);
  ~NeuralFields();
  NeuralFields(NeuralFields&&) noexcept;
  NeuralFields& operator=(NeuralFields&&) noexcept;

  int latent_dim() const;
  size_t particle_count() const;  // |P| of the scene it was trained for
  const std::string& scene_name() const;
  bool stress_uses_mu() const;
  // The decoder family: mlp (the paper's coordinate networks) or basis (per-point bases).
  DecoderFamily family() const;
  std::string decoder() const;  // its name: "basis" or "mlp"
  // The encoder's kind: "network" (trained) or "modes" (a basis model's projection on its
  // leading modes). Needs the model loaded with LibTorch (load()): throws nsf::Error otherwise.
  const std::string& encoder_kind() const;
  // A basis model's decoders at run time; null for an MLP model.
  const BasisDecoders* bases() const;
  double mu_min() const;  // the training runs' μ range (extrapolation beyond it is risky)
  double mu_max() const;
  // The swept values' ranges and the colliders' envelopes of the training runs (empty for a
  // model written before nsf recorded them).
  const TrainingBox& training_box() const;
  double train_seconds() const;  // wall time of the training that made it (0: not recorded)
  // The record another layer keeps of this model in its file under `name` (nn/model_record.h,
  // ModelAttachments); null where it has none. nn stores it without reading it.
  const std::string* attachment(const std::string& name) const;
  // Sets (replaces) the attachment `name` of model file `path` to `text`, rewriting the file
  // atomically (defined in libnsf_nn: the file is rewritten with LibTorch).
  static void store_attachment(const std::string& path, const std::string& name,
                               const std::string& text);

  const ModelRecord& record() const { return record_; }
  // The encoder and the coordinate networks; null when loaded without torch.
  const CoordinateNetworks* networks() const { return net_.get(); }

  // e(X) of the rest state X (the scene's particles, checked with check_scene): stored in the
  // record, or encoded where the file has none.
  Latent rest_latent(const std::vector<Vec3>& X) const;
  // g and ∂g/∂ẑ at the particles `ids` (rest positions X[ids]), for the inversion.
  std::unique_ptr<SampleDeformation> sample_deformation(const std::vector<Vec3>& X,
                                                        const std::vector<uint32_t>& ids) const;

  // Throws nsf::Error unless X (rest positions of `what`, e.g. a run file) is the model's scene.
  void check_scene(const std::string& scene_name, const std::vector<Vec3>& X,
                   const std::string& what) const;

  // e(xⁿ): one full frame of current positions (|P| of them, particle order of the scene).
  Latent encode(const std::vector<Vec3>& x) const;
  std::vector<Latent> encode(const std::vector<std::vector<Vec3>>& frames) const;

  // A set of reference positions prepared once for repeated evaluation (the normalised X for the
  // networks; for a basis model, each point's particles and weights, nn/point_interpolation.h).
  // Any X in Ω₀ works, not only the training particles: g queried at more points boosts the
  // resolution (Fig. 6).
  class Points {
   public:
    Points();
    ~Points();
    Points(Points&&) noexcept;
    Points& operator=(Points&&) noexcept;
    size_t size() const;

   private:
    friend class NeuralFields;
    struct Impl;
    std::unique_ptr<Impl> impl_;
  };
  Points prepare(const std::vector<Vec3>& X) const;

  // The fields at every prepared point for one latent, in one batched call each.
  void deform(const Points& X, const Latent& z, std::vector<Vec3>& x) const;  // g → x
  // h → τ (symmetric); mu ignored unless used. A basis model whose τ reads the latent velocity
  // (bases()->stress_uses_velocity) needs ż: an internal error without it.
  void stress(const Points& X, const Latent& z, double mu, std::vector<Mat3>& tau,
              const Latent* zdot = nullptr) const;
  // l → C. A basis model whose C reads the latent velocity (bases()->affine_uses_velocity) needs
  // ż and μ: an internal error without them.
  void affine(const Points& X, const Latent& z, std::vector<Mat3>& C, double mu = 0,
              const Latent* zdot = nullptr) const;

 private:
  NeuralFields();
  ModelRecord record_;
  std::unique_ptr<CoordinateNetworks> net_;
};

}  // namespace nsf
