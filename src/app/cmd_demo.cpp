// `nsf demo`: the main job. The whole chain on one small scene — sweep (training data), train,
// a reduced-order run at the held-out μ — then a summary and ground truth | ROM pictures.
// Reuses a dataset and a model that already exist, so a second run is quick.
#include <cstdio>
#include <filesystem>
#include <optional>

#include "app/commands.h"
#include "app/common_options.h"
#include "app/pipeline.h"
#include "app/train_size_options.h"
#include "core/error.h"
#include "core/timer.h"
#include "data/manifest.h"
#include "io/run_comparison.h"
#include "nn/dataset.h"
#include "nn/torch_settings.h"
#include "rom/eval/generalize.h"
#include "rom/eval/result_row.h"
#include "rom/eval/results_page.h"
#include "rom/eval/rom_evaluation.h"
#include "rom/setup/scene_file.h"

namespace nsf::app {

namespace {

namespace fs = std::filesystem;

struct DemoArgs {
  // The scene the method shows best today (docs/ROM.md): a plastic frame crushed by two plates,
  // where the ROM (per-point bases, one point per cell) follows the ground truth at δ < 1 %.
  std::string scene = "scenes/paper/metal_small.json";
  std::string data, model, out = "out";
  std::string docs;  // also store the row and the picture here (docs/results/demo.{json,png})
  TrainPlan train = chain_plan();
  TrainSizeArgs train_size;  // --steps, --widths: else the scene's "train" section may set them
  int samples = 0;
  int draws = 1;    // of the scene's benchmark of unseen interactions, after the held-out μ
  int threads = 0;  // all cores; the callback puts the count in use here
  bool quiet = false;
};

std::string stem_of(const std::string& path) {
  return fs::path(path).stem().string();
}

// The product's promise: cases no training run made (the scene's "generalize" section), as a
// row; none where the scene has no such section or --draws is 0.
std::optional<nlohmann::json> unseen_interactions(const DemoArgs& a, const std::string& data,
                                                  const std::string& model) {
  if (a.draws <= 0 || !read_scene_file(a.scene).sections.generalize) return std::nullopt;
  std::printf("== 4/4 unseen interactions: nsf generalize %s %s --draws %d\n", model.c_str(),
              data.c_str(), a.draws);
  GeneralizeOptions go;
  go.model_path = model;
  go.data_dir = data;
  go.scene_path = a.scene;
  go.draws = a.draws;
  if (a.samples > 0) go.rom.samples = a.samples;
  go.rom.threads = a.threads;
  go.quiet = a.quiet;
  return generalize_json(run_generalize(go), "nsf generalize " + model + " " + data + " --scene " +
                                                 a.scene + " --draws " + std::to_string(a.draws));
}

// The summary, the demo's row in --out, and with --docs the row and picture as `nsf report`
// stores its own (docs/RESULTS.md shows this one too, labelled "demo").
void print_and_store(const DemoArgs& a, const RomReport& r, const ComparisonFiles& pics,
                     const std::optional<nlohmann::json>& unseen, const std::string& model) {
  std::printf("\n== summary\n%s", format_rom_report(r).c_str());
  if (unseen) std::printf("%s", format_generalize(*unseen).c_str());
  std::printf("  picture:   %s (top: ground truth, bottom: reduced order)\n", pics.still.c_str());
  if (!pics.video.empty()) std::printf("  animation: %s\n", pics.video.c_str());
  if (!pics.note.empty()) std::printf("  note: %s\n", pics.note.c_str());
  const std::string row = a.out + "/demo.json";
  nlohmann::json row_json = result_json(r, a.scene, model, pics.still, "demo");
  if (unseen) row_json["generalize"] = *unseen;
  write_json_atomically(row, row_json);
  std::printf("  summary row: %s\n", row.c_str());
  if (a.docs.empty()) return;
  fs::create_directories(a.docs + "/results");
  fs::copy_file(pics.still, a.docs + "/results/demo.png", fs::copy_options::overwrite_existing);
  row_json["picture"] = "results/demo.png";
  write_json_atomically(a.docs + "/results/demo.json", row_json);
  const size_t rows = write_results_page(a.docs);
  std::printf("  stored in %s/results/demo.json, shown in %s/RESULTS.md (%zu rows)\n",
              a.docs.c_str(), a.docs.c_str(), rows);
}

void run_demo(const DemoArgs& a) {
  const double start = now_seconds();
  const std::string name = stem_of(a.scene);
  const std::string data = a.data.empty() ? "data/" + name : a.data;
  const std::string model = a.model.empty() ? "models/" + name + ".nsf" : a.model;
  fs::create_directories(a.out);
  set_nn_threads(a.threads);

  std::printf("== 1/4 training data: nsf sweep %s --out %s\n", a.scene.c_str(), data.c_str());
  ensure_dataset(a.scene, data, a.threads, a.quiet);
  const Dataset dataset(data);
  if (dataset.test().empty()) fail("demo: dataset ", data, " has no test run to hold out");
  std::printf("== 2/4 neural fields: nsf train %s --out %s\n", data.c_str(), model.c_str());
  ensure_model(data, model,
               with_scene_recipe(a.train, a.scene, !a.train_size.steps.empty(),
                                 !a.train_size.widths.empty()),
               a.threads, a.quiet);

  const SimulationFile& held_out = dataset.test()[0];
  std::printf("== 3/4 reduced-order run at the held-out mu = %g (not in the training set)\n",
              held_out.mu);
  RomEvalOptions ro;
  ro.model_path = model;
  ro.scene_path = a.scene;
  if (held_out.has_mu) ro.mu = held_out.mu;
  if (a.samples > 0) ro.samples = a.samples;
  ro.threads = a.threads;
  ro.quiet = a.quiet;
  ro.out_path = a.out + "/" + name + "_rom.h5";
  ro.fom_out = a.out + "/" + name + "_full_order.h5";
  const RomReport r = evaluate_rom(ro);
  const ComparisonFiles pics =
      write_comparison(ro.fom_out, ro.out_path, "ground truth (full order)", "reduced order",
                       a.out + "/" + name + "_compare");
  const std::optional<nlohmann::json> unseen = unseen_interactions(a, data, model);
  print_and_store(a, r, pics, unseen, model);
  std::printf("  demo total: %.1f s\n", now_seconds() - start);
}
}  // namespace

void add_demo_command(CLI::App& app) {
  auto a = std::make_shared<DemoArgs>();
  CLI::App* cmd = app.add_subcommand(
      "demo", "The whole chain on a small scene: sweep, train, reduced-order run, pictures");
  cmd->add_option("--scene", a->scene, "Scene with a sweep")->capture_default_str();
  cmd->add_option("--data", a->data, "Dataset directory (default data/<scene name>)");
  cmd->add_option("--model", a->model, "Model file (default models/<scene name>.nsf)");
  cmd->add_option("--out,-o", a->out, "Directory for the runs and pictures")->capture_default_str();
  cmd->add_option("--docs", a->docs,
                  "Also store the summary row and picture as DOCS/results/demo.{json,png}, the "
                  "one README quotes (e.g. --docs docs)");
  add_train_size_options(cmd, a->train_size,
                         "6000,4000,4000 when training; a basis model's stages 2 and 3: 20000",
                         "an MLP model's 0,128,128: smaller than Table 1, so the demo trains in "
                         "minutes on 2 cores");
  cmd->add_option("--decoder", a->train.decoder,
                  "Decoder family when training: basis (default) or mlp (docs/TRAINING.md)")
      ->check(CLI::IsMember({"mlp", "basis"}));
  cmd->add_option("--samples,-k", a->samples, "Sample particles (default: the scene's)")
      ->check(in_range(1, 100000000));
  cmd->add_option("--draws", a->draws,
                  "Draws of the scene's benchmark of unseen interactions to run after the "
                  "held-out mu (nsf generalize; 0: none)")
      ->capture_default_str()
      ->check(in_range(0, 1000));
  add_threads_option(cmd, a->threads);
  add_quiet_flag(cmd, a->quiet);
  cmd->callback([a] {
    a->train.steps = per_stage(a->train_size.steps, a->train.steps, "--steps");
    a->train.widths = per_stage(a->train_size.widths, a->train.widths, "--widths");
    // Line-buffered, so the step headers interleave correctly with the progress lines on stderr.
    std::setvbuf(stdout, nullptr, _IOLBF, 0);
    a->threads = set_threads(a->threads);
    run_demo(*a);
  });
}

}  // namespace nsf::app
