// A model's networks built from its configuration, and moved or switched to evaluation as a whole
// (nn/model/neural_model.h).
#include "nn/model/neural_model.h"

#include "core/error.h"

namespace nsf {

NeuralModel::NeuralModel(const NetConfig& c, const SceneFingerprint& s, bool mu)
    : config(c), scene(s), has_mu(mu) {
  const int64_t r = c.latent_dim;
  encoder = Encoder(s.particles, r, c.encoder_hidden, c.encoder_channels, c.encoder_max_length);
  if (c.encoder != "network" && c.encoder != "modes")
    fail("unknown encoder '", c.encoder, "' (known: network, modes)");
  if (c.encoder == "modes" && c.decoder != DecoderFamily::basis)
    fail("the modes encoder needs the basis decoders (--decoder basis): it projects on B_u");
  if (c.encoder == "modes" && c.latent_dim > c.modes[0])
    fail("the modes encoder takes the first r = ", c.latent_dim, " of the ", c.modes[0],
         " modes of x - X: r must not exceed K");
  if (c.decoder == DecoderFamily::basis) {
    for (int f = 0; f < 3; ++f) {
      if (c.modes[f] < 1) fail("a basis model needs at least one mode per field, got ", c.modes[f]);
      const int64_t in = r + (f == 1 && stress_has_mu() ? 1 : 0);
      basis[f].net = FieldMlp(in, c.modes[f], c.coefficient_width, c.coefficient_depth);
    }
  } else {
    g = FieldMlp(3 + r, 3, c.width_g, c.depth);
    h = FieldMlp(3 + r + (stress_has_mu() ? 1 : 0), 6, c.width_h, c.depth);
    l = FieldMlp(3 + r, 9, c.width_l, c.depth);
  }
  norm_X = Normalizer::identity(3);
  norm_x = Normalizer::identity(3);
  norm_u = Normalizer::identity(3);
  norm_z = Normalizer::identity(r);
  norm_mu = Normalizer::identity(1);
  norm_tau = Normalizer::identity(6);
  norm_C = Normalizer::identity(9);
}

void NeuralModel::check_scene(const SceneFingerprint& data, const std::string& what) const {
  check_same_scene(scene, data, what);
}

void NeuralModel::to(const torch::Device& device) {
  encoder->to(device);
  for (FieldMlp* net : {&g, &h, &l, &basis[0].net, &basis[1].net, &basis[2].net})
    if (!net->is_empty()) (*net)->to(device);
  auto move = [&](torch::Tensor& t) {
    if (t.defined()) t = t.to(device);
  };
  for (Normalizer* n : {&norm_X, &norm_x, &norm_z, &norm_mu, &norm_tau, &norm_C, &norm_u})
    move(n->mean), move(n->std);
  for (BasisField& b : basis) move(b.mean), move(b.modes), move(b.scale);
  // The coefficient maps stay on the CPU: they are fitted and evaluated there.
  move(rest), move(trajectory_latents), move(trajectory_mu);
}

void NeuralModel::set_eval_mode() {
  encoder->eval();
  for (FieldMlp* net : {&g, &h, &l, &basis[0].net, &basis[1].net, &basis[2].net})
    if (!net->is_empty()) (*net)->eval();
}

}  // namespace nsf
