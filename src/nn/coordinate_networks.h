#pragma once
// The torch-level half of a model behind a torch-free interface: the encoder e and the paper's
// coordinate networks g, h, l (nn/torch_networks.cpp, in libnsf_nn). NeuralFields holds one when
// it was loaded with LibTorch (NeuralFields::load); the reduced-order stepper's network
// sources (src/rom/fields/network_fields.cpp) call it. The torch-free runtime takes one from its
// MLP plugin (runtime/plugin_networks.h, over the C table of nn/mlp_plugin_abi.h) for an MLP
// model, and needs none for a basis model.
#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "core/types.h"

namespace nsf {

class SampleDeformation;

class CoordinateNetworks {
 public:
  virtual ~CoordinateNetworks() = default;

  // Rest positions prepared once (normalised, as the networks take them).
  class Points {
   public:
    virtual ~Points() = default;
  };
  virtual std::unique_ptr<Points> prepare(const std::vector<Vec3>& X) const = 0;

  // e(xⁿ) of whole frames (|P| positions each, the scene's particle order).
  virtual std::vector<Eigen::VectorXd> encode(
      const std::vector<std::vector<Vec3>>& frames) const = 0;

  // The fields at the prepared points `ids` (every point, in chunks, when ids is null). deform
  // evaluates each latent of `zs` in one batched call and appends their rows in that order.
  virtual void deform(const Points& X, const std::vector<uint32_t>* ids,
                      const std::vector<const Eigen::VectorXd*>& zs,
                      std::vector<Vec3>& x) const = 0;
  virtual void stress(const Points& X, const std::vector<uint32_t>* ids, const Eigen::VectorXd& z,
                      double mu, std::vector<Mat3>& tau) const = 0;
  virtual void affine(const Points& X, const std::vector<uint32_t>* ids, const Eigen::VectorXd& z,
                      std::vector<Mat3>& C) const = 0;
  // g and ∂g/∂ẑ at the points `ids`, for the inversion (nn/latent_inversion.h).
  virtual std::unique_ptr<SampleDeformation> samples(const Points& X,
                                                     const std::vector<uint32_t>& ids) const = 0;
  // F = ∂g/∂X (physical rest coordinates) at the points `ids`, by reverse-mode autodiff.
  virtual void deformation_gradients(const Points& X, const std::vector<uint32_t>& ids,
                                     const Eigen::VectorXd& z, std::vector<Mat3>& F) const = 0;

  // The encoder's kind (NetConfig::encoder): "network" or "modes".
  virtual const std::string& encoder_kind() const = 0;
};

}  // namespace nsf
