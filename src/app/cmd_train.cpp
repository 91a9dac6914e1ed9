// `nsf train data/NAME --out models/NAME.nsf`: train e, g, h, l on a dataset (docs/TRAINING.md).
// Also registers `nsf eval` (cmd_eval.cpp), so commands.h needs one line for both.
#include <cstdio>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "app/commands.h"
#include "app/common_options.h"
#include "app/pipeline.h"
#include "app/retired_options.h"
#include "app/train_size_options.h"
#include "app/train_team.h"
#include "core/cpu_model.h"
#include "core/error.h"
#include "core/memory.h"
#include "core/path_clash.h"
#include "core/progress.h"
#include "io/atomic_file.h"
#include "nn/config.h"
#include "nn/dataset.h"
#include "nn/torch_settings.h"
#include "nn/train/trainer.h"
#include "nn/train_section.h"
#include "rom/calibration/calibration_recipe.h"
#include "rom/calibration/latent_prior_calibration.h"
#include "rom/setup/scene_file.h"

namespace nsf::app {

void add_eval_command(CLI::App& app);  // cmd_eval.cpp

namespace {

struct TrainArgs {
  std::string data, out;
  TrainSizeArgs size;  // --steps, --widths (as demo and report spell them)
  std::vector<double> epochs;
  std::vector<int> frames, particles;
  int r = 0, depth = 0, width_g = 0, width_h = 0, width_l = 0, encoder_channels = 0,
      encoder_hidden = 0, encoder_max_length = 0;
  bool no_mu = false, no_scene_recipe = false, latent_noise_given = false, no_calibrate = false;
  std::string decoder;
  std::vector<int> modes;
  int coefficient_width = 0, coefficient_depth = 0;
  std::vector<std::string> coefficients;
  std::string affine_input, stress_input;
  std::string encoder;  // --encoder network|modes
  std::string scene;    // --scene: the recipe from this scene file, not the dataset's own
  std::string json;     // --json: the run's row (per stage: steps, seconds, throughput)
  TrainOptions opt;
};

template <typename T, typename U>
void set_per_stage(const std::vector<T>& in, U& out, const char* flag) {
  if (in.empty()) return;
  require_one_or_three(in.size(), flag, "stage");
  for (int s = 0; s < kStageCount; ++s) out[s] = in[in.size() == 1 ? 0 : s];
}

// The counts of the per-stage options are usage errors, found before anything is read; then
// --widths into the per-decoder widths (0: the default), which the old --width-g, --width-h and
// --width-l set one by one.
void check_stage_options(TrainArgs& a) {
  if (!a.size.steps.empty()) require_one_or_three(a.size.steps.size(), "--steps", "stage");
  if (!a.epochs.empty()) require_one_or_three(a.epochs.size(), "--epochs", "stage");
  if (!a.frames.empty()) require_one_or_three(a.frames.size(), "--frames-per-batch", "stage");
  if (!a.particles.empty())
    require_one_or_three(a.particles.size(), "--particles-per-frame", "stage");
  if (!a.size.widths.empty() && (a.width_g > 0 || a.width_h > 0 || a.width_l > 0))
    throw CLI::ValidationError("--widths",
                               "give it or the old --width-g, --width-h, --width-l, not both");
  const std::array<int, 3> widths = per_stage(a.size.widths, {0, 0, 0}, "--widths");
  int* fields[3] = {&a.width_g, &a.width_h, &a.width_l};
  for (int n = 0; n < 3; ++n)
    if (widths[n] > 0) *fields[n] = widths[n];
}

// The "train" section of the scene the dataset was simulated from, as its first run stored it
// (docs/SCENES.md, "Training recipe"), or of `scene_path`'s scene when given (which must be the
// dataset's scene); none for a scene without one. A dataset keeps its scene as it was swept, so
// a recipe edited in the scene file since is named, with the flag that takes it.
std::optional<TrainSection> scene_recipe(const Dataset& data, const std::string& scene_path,
                                         bool lead) {
  if (!scene_path.empty()) {
    const SceneFile file = read_scene_file(scene_path);
    const std::string name = file.json.value("name", std::string());
    if (name != data.scene_name())
      fail("--scene ", scene_path, ": its scene is '", name, "', the dataset's is '",
           data.scene_name(), "'");
    return file.sections.train;
  }
  const nlohmann::json scene = nlohmann::json::parse(data.scene_json(), nullptr, false);
  if (scene.is_discarded() || !scene.is_object()) return std::nullopt;
  const std::string file = dataset_scene_file(data.dir());
  if (lead && !file.empty()) {
    try {  // only a note: a scene file unreadable now does not stop training on the runs' scene
      const nlohmann::json now = read_scene_file(file).json;
      const nlohmann::json none = nlohmann::json::object();
      if (now.value("train", none) != scene.value("train", none))
        std::fprintf(stderr,
                     "  note: %s's \"train\" section is not the one this dataset was swept "
                     "with, which this training takes; --scene %s takes the file's\n",
                     file.c_str(), file.c_str());
    } catch (const Error&) {
    }
  }
  if (!scene.contains("train")) return std::nullopt;
  try {
    const TrainSection t = parse_train_section(scene.at("train"));
    parse_calibration_recipes(scene.at("train"));  // its "calibrate" (the ROM's) checked too
    return t;
  } catch (const Error& e) {
    fail(data.train().front().path, ": the training recipe of its scene: ", e.what());
  }
}

// The recipe's values where the command line gives none; returns what it set, for the log.
std::string apply_recipe(const TrainSection& t, const TrainArgs& a, TrainConfig& c) {
  GivenOnCommandLine given;
  given.steps = !a.size.steps.empty() || !a.epochs.empty();
  given.widths = {a.width_g > 0, a.width_h > 0, a.width_l > 0};
  given.encoder_max_length = a.encoder_max_length > 0;
  given.latent_dim = a.r > 0;
  given.decoder = !a.decoder.empty();
  given.encoder = !a.encoder.empty();
  given.frames_per_batch = !a.frames.empty();
  given.particles_per_frame = !a.particles.empty();
  TrainPlan plan;  // widths, encoder length and batches 0: c's stay unless the recipe sets them
  plan.steps = c.steps;
  apply_plan(with_train_section(plan, t, given), c);
  return recipe_taken(t, given);
}

// The model, its checkpoint and loss curves must not replace a file training reads: `nsf train d
// --out d/train_0.h5` destroyed a run of the dataset.
void refuse_overwriting_inputs(const TrainArgs& a, const Dataset& data) {
  std::vector<NamedPath> inputs = {
      {"the dataset's manifest", (std::filesystem::path(a.data) / "manifest.json").string()},
      {"--base-model", a.opt.base_model}};
  for (const auto* runs : {&data.train(), &data.test()})
    for (const SimulationFile& run : *runs) inputs.push_back({"the dataset's run", run.path});
  const std::string csv = loss_csv_path_for(a.out);
  refuse_path_clash(
      {{"--out", a.out},
       {"the checkpoint of --out", checkpoint_path_for(a.out)},
       {"the loss curves of --out", csv},
       {"the loss plot of --out", std::filesystem::path(csv).replace_extension(".png").string()},
       {"--json", a.json}},
      inputs);
}

// --json: what the summary lines print, machine-readable (docs/TRAINING.md, "Training on a GPU"
// compares devices with it).
void write_json(const TrainArgs& a, const TrainReport& r, int threads) {
  nlohmann::json j;
  j["model"] = r.model_path;
  j["data"] = a.data;
  j["device"] = a.opt.device;
  j["threads"] = threads;
  j["cpu"] = cpu_model();
  const bool basis = a.opt.config.net.decoder == DecoderFamily::basis;
  j["decoder"] = family_name(a.opt.config.net.decoder);
  if (basis)
    j["coefficients"] = {{"tau", a.opt.config.net.coefficients[0]},
                         {"C", a.opt.config.net.coefficients[1]},
                         {"affine_reads_velocity", a.opt.config.net.affine_reads_velocity()},
                         {"stress_reads_velocity", a.opt.config.net.stress_reads_velocity()}};
  if (basis) j["encoder"] = a.opt.config.net.encoder;
  j["peak_memory_mib"] = peak_rss_mib();
  for (int s = 0; s < kStageCount; ++s) {
    const StageReport& st = r.stages[s];
    nlohmann::json row = {{"stage", s + 1},
                          {"name", kStageNames[s]},
                          {"steps", st.steps},
                          {"seconds", st.seconds},
                          {"points_per_second", st.points_per_second},
                          {"final_loss", st.final_loss},
                          // a coefficient map: final_loss is its cross-validated error
                          {"fitted", a.opt.config.net.uses_map(s)}};
    if (s == 0) row["frames_per_second"] = st.frames_per_second;
    j["stages"].push_back(row);
  }
  write_file_atomic(a.json, j.dump(2) + "\n");
}

// The dataset's scene: the Table 1 row of its networks (`row`), the decoder family of --decoder,
// and the scene's "train" recipe where the command line leaves a value open.
void read_dataset_recipe(const TrainArgs& a, TrainConfig& c, std::string& row, bool lead) {
  const Dataset data(a.data, a.opt.allow_incomplete);
  if (!data.incomplete().empty() && lead)
    std::fprintf(stderr, "WARNING: %s\n  --allow-incomplete: training on the runs it has\n",
                 data.incomplete().c_str());
  refuse_overwriting_inputs(a, data);
  c.net = default_net_config(data.scene_name(), &row);
  // Before the recipe, so that a basis recipe's encoder stays off an MLP model (apply_plan).
  if (!a.decoder.empty()) c.net.decoder = parse_family(a.decoder, "--decoder");
  if (lead)
    std::fprintf(stderr,
                 "nsf train: %s, scene '%s', %zu particles, %zu training runs, %zu test "
                 "runs%s\n",
                 a.data.c_str(), data.scene_name().c_str(), data.particle_count(),
                 data.train().size(), data.test().size(), data.has_mu() ? " (with mu)" : "");
  const std::optional<TrainSection> recipe = scene_recipe(data, a.scene, lead);
  if (recipe && a.no_scene_recipe) {
    if (lead)
      std::fprintf(stderr, "  the scene's \"train\" recipe is ignored (--no-scene-recipe)\n");
  } else if (recipe) {
    const std::string set = apply_recipe(*recipe, a, c);
    if (!set.empty() && lead)
      std::fprintf(stderr,
                   "  the scene's \"train\" recipe: %s (flags on the command line take "
                   "precedence; --no-scene-recipe for the defaults)\n",
                   set.c_str());
  }
}

// The networks' shapes from the command line, over the scene's defaults and recipe.
void apply_shape_flags(const TrainArgs& a, TrainConfig& c) {
  if (a.r > 0) c.net.latent_dim = a.r;
  if (a.depth > 0) c.net.depth = a.depth;
  if (a.width_g > 0) c.net.width_g = a.width_g;
  if (a.width_h > 0) c.net.width_h = a.width_h;
  if (a.width_l > 0) c.net.width_l = a.width_l;
  if (a.encoder_channels > 0) c.net.encoder_channels = a.encoder_channels;
  if (a.encoder_hidden > 0) c.net.encoder_hidden = a.encoder_hidden;
  if (a.encoder_max_length > 0) c.net.encoder_max_length = a.encoder_max_length;
  if (a.no_mu) c.net.stress_uses_mu = false;
  if (a.modes.size() == 1) c.net.modes = {a.modes[0], a.modes[0], a.modes[0]};
  if (a.modes.size() == 3) c.net.modes = {a.modes[0], a.modes[1], a.modes[2]};
  if (!a.modes.empty() && a.modes.size() != 3 && a.modes.size() != 1)
    fail("--modes takes one K for all fields or three (x,tau,C), got ", a.modes.size());
  if (a.coefficient_width > 0) c.net.coefficient_width = a.coefficient_width;
  // A basis model's own defaults for stages 2 and 3, where the command line leaves them open (a
  // scene's recipe sizes the MLP fields' stages; its stage-1 steps still apply).
  apply_family_defaults(c, !a.size.steps.empty() || !a.epochs.empty(), a.latent_noise_given);
  if (a.coefficient_depth > 0) c.net.coefficient_depth = a.coefficient_depth;
  if (a.coefficients.size() == 1) c.net.coefficients = {a.coefficients[0], a.coefficients[0]};
  if (a.coefficients.size() == 2) c.net.coefficients = {a.coefficients[0], a.coefficients[1]};
  if (a.coefficients.size() > 2)
    fail("--coefficients takes one kind for tau and C or two (tau,C), got ", a.coefficients.size());
  if (!a.affine_input.empty()) c.net.affine_uses_velocity = a.affine_input == "velocity";
  if (!a.encoder.empty()) c.net.encoder = a.encoder;
  if (!a.stress_input.empty()) c.net.stress_uses_velocity = a.stress_input == "velocity";
}

// The flags that only a basis model reads, and the ones a base model's shapes make moot.
void check_family_flags(const TrainArgs& a, const TrainConfig& c) {
  if (a.affine_input == "velocity" && c.net.coefficients[1] != "map")
    fail(
        "--affine-input velocity needs C's coefficients from a map (--coefficients TAU,map): "
        "the coefficient networks take the latent alone");
  if (a.stress_input == "velocity" && c.net.coefficients[0] != "map")
    fail(
        "--stress-input velocity needs tau's coefficients from a map (--coefficients map,C): "
        "the coefficient networks take the latent alone");
  const bool basis_flags = !a.modes.empty() || a.coefficient_width > 0 || a.coefficient_depth > 0 ||
                           !a.coefficients.empty() || !a.affine_input.empty() ||
                           !a.stress_input.empty() || a.encoder == "modes";
  if (basis_flags && c.net.decoder != DecoderFamily::basis)
    fail(
        "--modes, --coefficient-*, --coefficients, --affine-input, --stress-input and --encoder "
        "modes shape the per-point bases: give --decoder basis");
  // The base model fixes every shape; a shape flag beside it would be silently ignored.
  if (!a.opt.base_model.empty() &&
      (a.r > 0 || a.depth > 0 || a.width_g > 0 || a.width_h > 0 || a.width_l > 0 ||
       a.encoder_channels > 0 || a.encoder_hidden > 0 || a.encoder_max_length > 0 || a.no_mu ||
       !a.decoder.empty() || !a.modes.empty() || a.coefficient_width > 0 ||
       a.coefficient_depth > 0 || !a.encoder.empty()))
    fail("--base-model ", a.opt.base_model,
         " fixes the networks' shapes: drop -r, --depth, --widths, --encoder*, --no-mu, "
         "--decoder, --modes and --coefficient-width/depth");
}

// The log's lines on the networks to be trained and the threads that train them.
void describe_networks(const TrainArgs& a, const std::string& row, int threads, int processes) {
  const TrainConfig& c = a.opt.config;
  const NetConfig& n = c.net;
  if (!a.opt.base_model.empty()) {
    std::fprintf(stderr, "  networks: those of %s\n", a.opt.base_model.c_str());
  } else if (n.decoder == DecoderFamily::basis) {
    const std::string coefficients =
        std::string(n.uses_map(1) ? "map" : "network") + " for tau" +
        (n.stress_reads_velocity() ? " (of the latent velocity too)" : "") + ", " +
        (n.uses_map(2) ? "map" : "network") + " for C" +
        (n.affine_reads_velocity() ? " (of the latent velocity too)" : "");
    std::fprintf(stderr,
                 "  decoders: per-point bases of K = %d (x), %d (tau), %d (C) modes, coefficient "
                 "network %d x %d for x, %s; r = %d (Table 1 row '%s')%s\n",
                 n.modes[0], n.modes[1], n.modes[2], n.coefficient_depth, n.coefficient_width,
                 coefficients.c_str(), n.latent_dim, row.c_str(),
                 n.encoder == "modes" ? "; encoder: the first r modes of x - X" : "");
  } else {
    std::fprintf(stderr,
                 "  networks (Table 1 row '%s'): r = %d, depth %d, widths g %d, h %d, l %d\n",
                 row.c_str(), n.latent_dim, n.depth, n.width_g, n.width_h, n.width_l);
  }
  if (processes > 1)
    std::fprintf(stderr, "  %d processes x %d threads, BLAS: %s; networks on %s\n", processes,
                 threads, blas_info().c_str(), a.opt.device.c_str());
  else
    std::fprintf(stderr, "  %d threads, BLAS: %s; networks on %s\n", threads, blas_info().c_str(),
                 a.opt.device.c_str());
}

// What training made: the model, its loss curves, its training box and the stages' throughput.
void print_summary(const TrainReport& r) {
  std::printf("model: %s\nloss curves: %s%s%s\n", r.model_path.c_str(), r.loss_csv.c_str(),
              r.loss_png.empty() ? "" : ", ", r.loss_png.c_str());
  // What a reduced-order run will check a host's colliders against (docs/SCENES.md).
  for (const std::string& line : r.box.describe()) std::printf("training box: %s\n", line.c_str());
  // "-" for a stage this process did not run (resumed past it, or skipped by --base-model).
  auto rate = [&](int s, double value) {
    return r.stages[s].steps > 0 ? Progress::format_rate(value) : std::string("-");
  };
  std::printf(
      "throughput (points/s): g %s, h %s, l %s; encoder %s frames/s; peak memory %.0f MiB\n",
      rate(0, r.stages[0].points_per_second).c_str(),
      rate(1, r.stages[1].points_per_second).c_str(),
      rate(2, r.stages[2].points_per_second).c_str(),
      rate(0, r.stages[0].frames_per_second).c_str(), peak_rss_mib());
}

void run_train(TrainArgs& a, const SweepRanks& ranks) {
  TrainConfig& c = a.opt.config;
  // Under mpirun: process 0 speaks and writes; each process takes its share of its machine.
  const bool lead = ranks.rank() == 0;
  if (!lead) c.quiet = true;
  if (ranks.size() > 1 && c.threads <= 0) c.threads = ranks.cores();
  const int threads = set_nn_threads(c.threads);
  std::string row;
  read_dataset_recipe(a, c, row, lead);
  apply_shape_flags(a, c);
  check_family_flags(a, c);
  set_per_stage(a.size.steps, c.steps, "--steps");
  set_per_stage(a.epochs, a.opt.epochs, "--epochs");
  set_per_stage(a.frames, c.frames_per_batch, "--frames-per-batch");
  set_per_stage(a.particles, c.particles_per_frame, "--particles-per-frame");
  if (lead) describe_networks(a, row, threads, ranks.size());

  const std::unique_ptr<GradientTeam> team = make_gradient_team(ranks);
  a.opt.team = team.get();
  const TrainReport r = train_model(a.data, a.out, a.opt);
  if (!lead) return;
  if (!r.completed) {
    std::fprintf(stderr, "stopped early (--stop-after); continue with --resume from %s\n",
                 r.checkpoint_path.c_str());
    return;
  }
  print_summary(r);
  if (!a.no_calibrate) calibrate_trained_model(r.model_path, a.data, c.threads, c.quiet);
  if (!a.json.empty()) {
    write_json(a, r, threads);
    std::printf("wrote %s\n", a.json.c_str());
  }
}

}  // namespace

void add_nn_commands(CLI::App& app) {
  auto a = std::make_shared<TrainArgs>();
  TrainConfig& c = a->opt.config;
  CLI::App* cmd = app.add_subcommand("train",
                                     "Train the encoder and the deformation, stress and "
                                     "affine fields on a dataset (nsf sweep)");
  cmd->add_option("data", a->data, "Dataset directory (manifest.json, train_k.h5, test_k.h5)")
      ->required();
  cmd->add_option("--out,-o", a->out, "Model file to write, e.g. models/NAME.nsf")->required();
  add_train_size_options(cmd, a->size, "6000,20000,20000; --decoder mlp: 6000,1500,1500",
                         "Table 1's, or the scene's \"train\" recipe");
  add_list_option(cmd, "--epochs", a->epochs,
                  "Epochs per stage instead of --steps (epoch = every training point once)", 1e-3,
                  1e5);
  add_list_option(cmd, "--frames-per-batch", a->frames,
                  "Frames per batch: one value or g,h,l (default 4; at most the dataset's "
                  "training frames)",
                  1, 1000000);
  add_list_option(cmd, "--particles-per-frame", a->particles,
                  "Particles sampled per batch frame: one value or g,h,l (default 512)", 1,
                  10000000);
  cmd->add_option("--refine-latents", c.refine_latents,
                  "Gauss-Newton iterations refining each frame's latent before stages 2, 3 (0 = "
                  "the encoder's latents, as in the paper)")
      ->capture_default_str()
      ->check(in_range(0, 100));
  auto* noise =
      cmd->add_option("--latent-noise", c.latent_noise,
                      "Noise on the latents of stages 2, 3, in units of each component's spread "
                      "(default 0; --decoder mlp: 0.1)")
          ->check(in_range(0.0, 10.0));
  cmd->add_option("--latent-dim,-r", a->r, "Latent dimension r (default: Table 1 for the scene)")
      ->check(in_range(1, 1024));
  cmd->add_option("--depth", a->depth, "Hidden layers per decoder (default 5)")
      ->check(in_range(1, 64));
  // The old spellings of --widths g,h,l, one decoder each: they still work, listed apart (CLI11's
  // errors cannot name a hidden option).
  for (auto [name, width] :
       {std::pair{"--width-g", &a->width_g}, std::pair{"--width-h", &a->width_h},
        std::pair{"--width-l", &a->width_l}})
    cmd->add_option(name, *width, "Hidden width of one decoder (old name: use --widths)")
        ->check(in_range(1, 65536))
        ->group("Deprecated");
  cmd->add_option("--encoder-channels", a->encoder_channels,
                  "Output channels of each encoder convolution (default: 3, App. E)")
      ->check(in_range(1, 64));
  cmd->add_option("--encoder-max-length", a->encoder_max_length,
                  "Encoder convolutions continue while the length exceeds this (default: 12, "
                  "App. E)")
      ->check(in_range(5, 1 << 20));
  cmd->add_option("--encoder-hidden", a->encoder_hidden,
                  "Width of the encoder's hidden Linear layer (default: 32, App. E)")
      ->check(in_range(1, 4096));
  cmd->add_flag("--no-mu", a->no_mu, "Do not condition the stress field h on mu");
  cmd->add_option("--decoder", a->decoder,
                  "Decoder family: basis (the default: per-point bases of the training frames "
                  "times coefficients from small networks of the latent) or mlp (the paper's "
                  "coordinate networks); docs/TRAINING.md")
      ->check(CLI::IsMember({"mlp", "basis"}));
  add_list_option(cmd, "--modes", a->modes,
                  "Basis modes K: one value or x,tau,C (default 32,64,64)", 1, 4096);
  cmd->add_option("--coefficient-width", a->coefficient_width,
                  "Hidden width of the basis coefficient networks (default 128)")
      ->check(in_range(1, 4096));
  cmd->add_option("--coefficient-depth", a->coefficient_depth,
                  "Hidden layers of the basis coefficient networks (default 3)")
      ->check(in_range(1, 16));
  cmd->add_option("--coefficients", a->coefficients,
                  "How the basis model's tau and C coefficients are made, one kind for both or "
                  "tau,C: network (small networks trained by Adam) or map (thin-plate-spline maps "
                  "through the training latents, fitted in seconds); default network,map "
                  "(docs/TRAINING.md)")
      ->delimiter(',')
      ->check(CLI::IsMember({"map", "network"}));
  cmd->add_option("--affine-input", a->affine_input,
                  "What C's coefficient map reads: velocity (the default: the latent, mu and the "
                  "latent velocity) or latent (the latent alone)")
      ->check(CLI::IsMember({"latent", "velocity"}));
  cmd->add_option("--stress-input", a->stress_input,
                  "What tau's coefficient map reads: latent (the default: the latent and mu) or "
                  "velocity (the latent velocity too; needs --coefficients map,C)")
      ->check(CLI::IsMember({"latent", "velocity"}));
  cmd->add_option("--encoder", a->encoder,
                  "The encoder of a basis model: network (the default: App. E's convolutions, "
                  "trained with c_u) or modes (the latent is the training frames' r leading "
                  "coefficients of x - X, no training; docs/TRAINING.md, \"Encoders\")")
      ->check(CLI::IsMember({"network", "modes"}));
  cmd->add_option("--scene", a->scene,
                  "Take the \"train\" recipe from this scene file (the dataset's scene, edited "
                  "since the sweep) instead of the scene the dataset's runs stored")
      ->check(CLI::ExistingFile);
  cmd->add_flag("--no-scene-recipe", a->no_scene_recipe,
                "Ignore the scene's \"train\" section (steps, widths, encoder length, batches) and "
                "use the defaults: Table 1's widths, the documented steps");
  cmd->add_flag("--no-calibrate", a->no_calibrate,
                "Do not choose the latent prior on the training runs after training (a basis "
                "model's default; nsf calibrate does it later)");
  cmd->add_option("--seed", c.seed, "Random seed (initialisation and batches)")
      ->capture_default_str()
      ->check(in_range<long long>(0, std::numeric_limits<long long>::max()));
  add_threads_option(cmd, c.threads);
  cmd->add_option("--checkpoint-every", c.checkpoint_every,
                  "Steps between checkpoints (0 = only at the end of each stage); a basis "
                  "model's bases of B x 64 MiB space them B times as far")
      ->capture_default_str()
      ->check(in_range<long>(0, 1000000000));
  cmd->add_option("--memory-budget", c.memory_budget_gib,
                  "GiB of training frames kept in RAM; larger datasets are streamed from disk "
                  "(0 = half the available memory, at least 2); batches must fit it too")
      ->capture_default_str()
      ->check(in_range(0.0, 1e6));
  cmd->add_option("--base-model", a->opt.base_model,
                  "Keep this model's encoder and g (no stage 1); train h and l afresh");
  auto* resume = cmd->add_flag("--resume", a->opt.resume, "Continue from <out>.ckpt if it exists");
  cmd->add_flag("--fresh", a->opt.fresh,
                "Delete a checkpoint <out>.ckpt of an interrupted run and start over (without "
                "--resume or --fresh, such a checkpoint is refused)")
      ->excludes(resume);
  cmd->add_flag("--allow-incomplete", a->opt.allow_incomplete,
                "Train on a dataset an interrupted or partial sweep left incomplete (missing or "
                "unfinished runs), with a warning, instead of refusing it");
  cmd->add_option("--stop-after", a->opt.stop_after,
                  "Stop after this many steps (then continue with --resume)")
      ->check(in_range<long>(0, std::numeric_limits<long>::max()));
  cmd->add_option("--device", a->opt.device,
                  "Where the networks train: cpu (default), cuda or cuda:N (a LibTorch with CUDA; "
                  "docs/TRAINING.md)");
  cmd->add_option("--json", a->json,
                  "Also write the run's summary (per stage: steps, seconds, points/s) to this "
                  "JSON file");
  add_quiet_flag(cmd, c.quiet);
  add_retired_options(cmd, "train");
  cmd->callback([a, noise] {
    a->latent_noise_given = noise->count() > 0;
    check_stage_options(*a);
    check_training_device(a->opt.device);
    // Inputs that do not exist are errors of the world, not of the command line (exit status 1).
    if (!a->opt.base_model.empty() && !std::filesystem::is_regular_file(a->opt.base_model))
      fail("--base-model ", a->opt.base_model, ": no such file");
    SweepRanks ranks;  // MPI, when mpirun started this process (app/train_team.h)
    ranks.run([&] { run_train(*a, ranks); });
  });
  add_eval_command(app);
}

}  // namespace nsf::app
