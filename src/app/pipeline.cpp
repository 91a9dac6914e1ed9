#include "app/pipeline.h"

#include <cstdio>
#include <filesystem>

#include "core/error.h"
#include "data/sweep.h"
#include "nn/dataset.h"
#include "nn/model/neural_model.h"
#include "nn/neural_fields.h"
#include "nn/train/trainer.h"
#include "rom/calibration/latent_prior_calibration.h"
#include "rom/setup/scene_file.h"

namespace nsf::app {

TrainPlan chain_plan() {
  TrainPlan plan;
  plan.steps = {6000, 4000, 4000};
  plan.widths = {0, 128, 128};
  return plan;
}

double ensure_dataset(const std::string& scene, const std::string& data, int threads, bool quiet) {
  SweepOptions so;
  so.quiet = quiet;
  so.out_dir = data;
  so.jobs = std::max(1, threads);
  so.threads = 1;
  const SceneFile file = read_scene_file(scene);
  const SweepSummary s = run_sweep(file.json, file.sections.sweep, file.path, so);
  std::printf("   %s: %d runs (%d simulated now, %d reused) in %.1f s\n", data.c_str(), s.planned,
              s.ran, s.skipped, s.seconds);
  return s.seconds;
}

TrainPlan with_scene_recipe(TrainPlan plan, const std::string& scene, bool steps_given,
                            bool widths_given) {
  plan.steps_given = steps_given;
  const std::optional<TrainSection> train = read_scene_file(scene).sections.train;
  if (!train) return plan;
  GivenOnCommandLine given;
  given.steps = steps_given;
  given.widths.fill(widths_given);
  given.decoder = !plan.decoder.empty();  // --decoder on the command line
  return with_train_section(plan, *train, given);
}

std::string scene_decoder(const std::string& scene) {
  const std::optional<TrainSection> train = read_scene_file(scene).sections.train;
  return train && !train->decoder.empty() ? train->decoder : family_name(NetConfig().decoder);
}

DecoderRows decoder_rows(const std::string& name, const std::string& own,
                         const std::string& asked) {
  if (asked.empty() || asked == own) return {"models/" + name + ".nsf", "", ""};
  return {
      "models/" + name + "_" + asked + ".nsf", "_" + asked,
      parse_family(asked, "--decoder") == DecoderFamily::mlp ? "MLP fields" : "per-point bases"};
}

void apply_plan(const TrainPlan& plan, TrainConfig& config) {
  config.steps = plan.steps;
  if (!plan.decoder.empty()) config.net.decoder = parse_family(plan.decoder, "decoder");
  int* widths[3] = {&config.net.width_g, &config.net.width_h, &config.net.width_l};
  for (int n = 0; n < 3; ++n)
    if (plan.widths[n] > 0) *widths[n] = plan.widths[n];
  if (plan.encoder_max_length > 0) config.net.encoder_max_length = plan.encoder_max_length;
  if (plan.latent_dim > 0) config.net.latent_dim = plan.latent_dim;
  // A recipe's encoder is a basis model's: with --decoder mlp over a basis recipe it stays out.
  if (!plan.encoder.empty() && config.net.decoder == DecoderFamily::basis)
    config.net.encoder = plan.encoder;
  for (int s = 0; s < kStageCount; ++s) {
    if (plan.frames_per_batch[s] > 0) config.frames_per_batch[s] = plan.frames_per_batch[s];
    if (plan.particles_per_frame[s] > 0)
      config.particles_per_frame[s] = plan.particles_per_frame[s];
  }
}

bool ensure_model(const std::string& data, const std::string& model, const TrainPlan& plan,
                  int threads, bool quiet) {
  const Dataset dataset(data);
  if (std::filesystem::exists(model)) {
    try {
      NeuralFields f = NeuralFields::load(model);
      f.check_scene(dataset.scene_name(), dataset.rest_positions(), "dataset " + data);
      const DecoderFamily wanted =
          plan.decoder.empty() ? NetConfig().decoder : parse_family(plan.decoder, "--decoder");
      if (f.family() != wanted)
        fail("it holds ", f.decoder(), " decoders, not ", family_name(wanted), " (--decoder)");
      const std::string encoder = wanted == DecoderFamily::basis && !plan.encoder.empty()
                                      ? plan.encoder
                                      : NetConfig().encoder;
      if (f.encoder_kind() != encoder)
        fail("its encoder is '", f.encoder_kind(), "', the scene's recipe asks for '", encoder,
             "'");
      std::printf("   reusing %s (delete it to retrain)\n", model.c_str());
      return false;
    } catch (const Error& e) {
      std::printf("   not reusing %s: %s\n", model.c_str(), e.what());
    }
  }
  TrainOptions to;
  to.config.net = default_net_config(dataset.scene_name());
  apply_plan(plan, to.config);
  apply_family_defaults(to.config, plan.steps_given, false);
  to.config.threads = threads;
  to.config.quiet = quiet;
  to.resume = true;  // an interrupted demo or report continues where it stopped
  train_model(data, model, to);
  calibrate_trained_model(model, data, threads, quiet);
  return true;
}

}  // namespace nsf::app
