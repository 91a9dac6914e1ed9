// `nsf upgrade model.nsf`: rewrites a model file in this nsf's format, in place and atomically;
// a basis model gains the run-time record that the torch-free runtime reads (docs/EMBEDDING.md).
// With --data, the training box is recorded anew from the dataset the model was trained on, so
// that a model trained before nsf recorded its scene family (data/scene_family.h) knows it.
#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>

#include "app/commands.h"
#include "app/common_options.h"
#include "core/error.h"
#include "nn/dataset.h"
#include "nn/model/neural_model.h"

namespace nsf::app {

namespace {

struct UpgradeArgs {
  std::string model, data;
  int threads = 0;
  bool quiet = false;
};

// The model's training box anew from `dir`, after checking that it is the model's dataset: the
// same scene and the same range of μ.
void record_training_box(NeuralModel& m, const std::string& dir) {
  const Dataset data(dir);
  m.check_scene(SceneFingerprint::of(data.scene_name(), data.rest_positions()), dir);
  double lo = m.mu_min, hi = m.mu_max;
  if (m.has_mu && !data.train().empty()) {
    lo = hi = data.train().front().mu;
    for (const SimulationFile& r : data.train()) lo = std::min(lo, r.mu), hi = std::max(hi, r.mu);
  }
  if (lo != m.mu_min || hi != m.mu_max)
    fail(dir, ": its training runs span mu in [", lo, ", ", hi, "], the model's in [", m.mu_min,
         ", ", m.mu_max, "]: not the dataset the model was trained on");
  m.training_box = training_box(data);
}

}  // namespace

void add_upgrade_command(CLI::App& app) {
  auto a = std::make_shared<UpgradeArgs>();
  CLI::App* cmd = app.add_subcommand(
      "upgrade", "Rewrite a model file in this nsf's format (adds the runtime's record)");
  cmd->add_option("model", a->model, "Model file (nsf train)")->required();
  cmd->add_option("--data", a->data,
                  "Record the training box (the scene's values, swept ranges and colliders) "
                  "anew from the dataset the model was trained on");
  add_threads_option(cmd, a->threads, "Accepted as by every command; upgrade runs on one thread");
  add_quiet_flag(cmd, a->quiet, "Print nothing on success");
  cmd->callback([a] {
    NeuralModel m = NeuralModel::load(a->model);
    if (!a->data.empty()) record_training_box(m, a->data);
    m.save(a->model);  // atomic: tmp + rename
    if (!a->quiet)
      std::printf("rewrote %s (%s model)%s\n", a->model.c_str(), family_name(m.config.decoder),
                  m.is_basis() ? " with its run-time record" : "");
  });
}

}  // namespace nsf::app
