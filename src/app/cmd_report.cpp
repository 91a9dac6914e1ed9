// `nsf report`: the paper's Table 1 on nsf. For each of the seven scenes: dataset, model (made
// if missing), a reduced-order run at the held-out μ against full order, a picture; then
// docs/RESULTS.md rebuilt from every scene's stored measurements.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>

#include "app/beyond_sweep.h"
#include "app/commands.h"
#include "app/common_options.h"
#include "app/pipeline.h"
#include "app/retired_options.h"
#include "app/train_size_options.h"
#include "core/error.h"
#include "data/manifest.h"
#include "io/run_comparison.h"
#include "nn/dataset.h"
#include "rom/eval/result_row.h"
#include "rom/eval/results_page.h"
#include "rom/eval/rom_evaluation.h"

namespace nsf::app {

namespace {

namespace fs = std::filesystem;

struct ReportArgs {
  std::string size = "small";
  std::vector<std::string> scenes = {"bread",      "cake",  "sand",        "metal",
                                     "toothpaste", "jelly", "squishy_ball"};
  TrainPlan train = chain_plan();
  TrainSizeArgs train_size;  // --steps, --widths: else the scene's "train" section may set them
  bool no_make = false;
  int threads = 0;  // all cores; the callback puts the count in use here
  bool quiet = false;
  std::string docs = "docs", out = "out/report";
  int quadrature = 0;    // > 0: the ROM's thinned quadrature, rows labelled with it
  bool tracked = false;  // the tracked state on N in place of h and l, rows labelled with it
  bool check = false;    // rerun the stored rows and compare instead of storing them
  bool page_only = false;
  bool beyond_sweep = false;  // run the scenes' beyond-sweep cases (app/beyond_sweep.h) instead
};

// --check: the rerun of the row `tag` against the stored one (rom/eval/result_row.h).
void check_row(const ReportArgs& a, const std::string& tag, const nlohmann::json& fresh) {
  const std::string path = a.docs + "/results/" + tag + ".json";
  if (!fs::exists(path)) fail("report --check: no stored row ", path, " to compare with");
  std::ifstream in(path);
  const nlohmann::json stored = nlohmann::json::parse(in);
  const std::vector<std::string> diff = row_differences(stored, fresh);
  const bool other_file =
      stored.contains("model_crc32") && fresh.value("model_crc32", "") != stored["model_crc32"];
  if (diff.empty()) {
    std::printf("   %s reproduces to the digit (every figure but the timings and memory)%s\n",
                tag.c_str(),
                other_file ? ", with another model file than the row's (recalibrated, or "
                             "retrained to the same decoders)"
                           : "");
    return;
  }
  std::string all;
  for (const std::string& d : diff) all += "\n    " + d;
  if (!stored.contains("model_crc32"))
    all +=
        "\n    (the stored row does not name its model's checksum: it may have been made "
        "with another model file)";
  else if (other_file)
    all += "\n    (the stored row was made with another model file)";
  fail(path, " does not reproduce:", all);
}

// --check reruns a row with the latent prior and the ROM step it was made with (the scene's then,
// or its model's calibration), whatever the scene or the model says now; a row that names no
// prior had none, a row that names no step (stored before it was recorded) takes today's.
struct StoredSettings {
  double latent_prior = 0;
  std::optional<double> dt_ratio;
};
StoredSettings stored_settings(const ReportArgs& a, const std::string& tag) {
  std::ifstream in(a.docs + "/results/" + tag + ".json");
  const nlohmann::json stored = nlohmann::json::parse(in, nullptr, false);
  StoredSettings s;
  if (!stored.is_object()) return s;
  s.latent_prior = stored.value("latent_prior", 0.0);
  if (stored.contains("dt_ratio")) s.dt_ratio = stored["dt_ratio"].get<double>();
  return s;
}

// One reduced-order run, its picture and its stored row.
// `tag` names the row's files (docs/results/TAG.json, …); `set` are the case's --set overrides.
void report_run(const ReportArgs& a, const std::string& scene, const DecoderRows& decoder,
                const std::string& data, double mu, std::string label, std::string tag,
                const std::vector<std::string>& set = {}) {
  const std::string& model = decoder.model;
  if (a.quadrature > 0) {
    const std::string q = "quadrature " + std::to_string(a.quadrature) + "/cell";
    label = label.empty() ? q : label + ", " + q;
    tag += "_q" + std::to_string(a.quadrature);
  }
  if (a.tracked) {
    label = label.empty() ? "tracked state" : label + ", tracked state";
    tag += "_tracked";
  }
  if (!decoder.label.empty()) {
    label = label.empty() ? decoder.label : label + ", " + decoder.label;
    tag += decoder.tag_suffix;
  }
  RomEvalOptions ro;
  if (a.quadrature > 0) ro.quadrature = a.quadrature;
  if (a.tracked) ro.rom.fields.stress = ro.rom.fields.affine = "tracked";
  ro.model_path = model;
  ro.overrides = set;
  ro.scene_path = scene;
  ro.mu = mu;
  ro.threads = a.threads;
  ro.quiet = a.quiet;
  ro.out_path = a.out + "/" + tag + "_rom.h5";
  ro.fom_out = a.out + "/" + tag + "_full_order.h5";
  ro.gzip = 1;  // half the disk (a paper-size row's two runs: gigabytes); outside the timings
  // The baselines beside the ROM: look-up and interpolation from the training runs; the
  // engine on the small scene (for a paper-size row), or on the small scene at 1.5× Δx (or the
  // coarsest tenth below that builds: rom/eval/rom_evaluation.h).
  ro.baseline_data = data;
  if (a.size == "paper")
    ro.coarse_scene = std::regex_replace(scene, std::regex("_paper\\.json$"), "_small.json");
  else
    ro.coarse_factor = 1.5;
  ro.coarse_optional = true;  // a row without it (a body in the coarser wall band) still counts
  if (a.check) {
    const StoredSettings stored = stored_settings(a, tag);
    ro.latent_prior = stored.latent_prior;
    ro.dt_ratio = stored.dt_ratio;
  }
  const RomReport r = evaluate_rom(ro);
  std::printf("%s", format_rom_report(r).c_str());
  const std::string picture = "results/" + tag + ".png";
  if (a.check) return check_row(a, tag, result_json(r, scene, model, picture, label));
  // The row's label in the truth's title: a beyond-sweep or tracked row's picture says so.
  const std::string truth = label.empty() ? "ground truth" : "ground truth (" + label + ")";
  const ComparisonFiles pics = write_comparison(ro.fom_out, ro.out_path, truth, "reduced order",
                                                a.out + "/" + tag + "_compare");
  fs::copy_file(pics.still, a.docs + "/" + picture, fs::copy_options::overwrite_existing);
  write_json_atomically(a.docs + "/results/" + tag + ".json",
                        result_json(r, scene, model, picture, label));
}

// The rows of one of the paper's scenes (`base`, e.g. "metal"), each run through `row`: the
// held-out μ's, or with --beyond-sweep the scene's cases outside its sweep.
template <typename Row>
void report_scene(const ReportArgs& a, const std::string& base, Row&& row) {
  const std::string name = base + "_" + a.size;
  const std::string scene = "scenes/paper/" + name + ".json";
  if (!fs::exists(scene)) fail("report: no scene file ", scene, " (known: the paper's seven)");
  const DecoderRows decoder = decoder_rows(name, scene_decoder(scene), a.train.decoder);
  const std::string data = "data/" + name, model = decoder.model;
  std::printf("== %s\n", name.c_str());
  if ((a.no_make || a.check) && (!fs::exists(data + "/manifest.json") || !fs::exists(model))) {
    std::printf("   skipped: %s or %s is missing (%s)\n", data.c_str(), model.c_str(),
                a.check ? "--check makes nothing" : "--no-make");
    return;
  }
  ensure_dataset(scene, data, a.threads, a.quiet);
  ensure_model(
      data, model,
      with_scene_recipe(a.train, scene, !a.train_size.steps.empty(), !a.train_size.widths.empty()),
      a.threads, a.quiet);
  const Dataset dataset(data);
  if (dataset.test().empty() || !dataset.test()[0].has_mu)
    fail("report: dataset ", data, " has no test run with a parameter to hold out");
  const double test_mu = dataset.test()[0].mu;
  if (a.beyond_sweep) {
    const std::vector<BeyondSweepCase> cases = beyond_sweep_cases(base);
    if (cases.empty()) std::printf("   no beyond-sweep case for %s\n", base.c_str());
    for (size_t i = 0; i < cases.size(); ++i) {
      const std::string tag = name + "_beyond" + std::to_string(i);
      row(tag, [&] {
        const double mu = cases[i].at_test_mu ? test_mu : cases[i].mu;
        report_run(a, scene, decoder, data, mu, "beyond-sweep: " + cases[i].what, tag,
                   cases[i].set);
      });
    }
    return;
  }
  row(name, [&] { report_run(a, scene, decoder, data, test_mu, "", name); });
}

void run_report(const ReportArgs& a) {
  if (a.size != "small" && a.size != "paper")
    fail("report: --size must be small or paper, got '", a.size, "'");
  // A row that fails (a ROM that diverges, say) is named at the end; the others still run.
  std::vector<std::string> failed;
  auto row = [&](const std::string& tag, auto&& run) {
    try {
      run();
    } catch (const Error& e) {
      std::printf("   %s failed: %s\n", tag.c_str(), e.what());
      failed.push_back(tag + ": " + e.what());
    }
  };
  fs::create_directories(a.out);
  fs::create_directories(a.docs + "/results");
  for (const std::string& base : a.page_only ? std::vector<std::string>{} : a.scenes)
    report_scene(a, base, row);
  std::string all_failed;
  for (const std::string& f : failed) all_failed += "\n  " + f;
  if (a.check) {
    if (!failed.empty())
      fail("report --check: ", failed.size(), " row(s) do not reproduce:", all_failed);
    std::printf("report --check: every row run reproduces its stored figures\n");
    return;
  }
  const size_t rows = write_results_page(a.docs);
  std::printf("wrote %s/RESULTS.md (%zu rows)\n", a.docs.c_str(), rows);
  if (!failed.empty()) {
    fail("report: ", failed.size(), " row(s) failed, the others are stored:", all_failed);
  }
}

}  // namespace

void add_report_command(CLI::App& app) {
  auto a = std::make_shared<ReportArgs>();
  CLI::App* cmd = app.add_subcommand(
      "report", "The paper's Table 1 on nsf: ROM vs full order on the seven scenes");
  cmd->add_option("--size", a->size, "small or paper")
      ->capture_default_str()
      ->check(CLI::IsMember({"small", "paper"}));
  cmd->add_option("--scenes", a->scenes, "Scenes to run (default all seven)")->delimiter(',');
  cmd->add_option("--decoder", a->train.decoder,
                  "Decoder family: basis or mlp (docs/TRAINING.md). A scene's own family (its "
                  "recipe's, else basis) uses models/NAME.nsf; the other family trains and reads "
                  "models/NAME_FAMILY.nsf, and its rows are labelled with it and kept beside the "
                  "others")
      ->check(CLI::IsMember({"mlp", "basis"}));
  add_train_size_options(cmd, a->train_size,
                         "where a model is trained: the scene's \"train\" section, else "
                         "6000,4000,4000; a basis model's stages 2 and 3: 20000",
                         "the scene's \"train\" section, else an MLP model's 0,128,128");
  cmd->add_flag("--no-make", a->no_make,
                "Skip scenes without a dataset and model instead of making them");
  add_threads_option(cmd, a->threads);
  add_quiet_flag(cmd, a->quiet);
  cmd->add_option("--docs", a->docs, "Where RESULTS.md and results/ go")->capture_default_str();
  cmd->add_option("--out", a->out, "Where the runs and animations go")->capture_default_str();
  cmd->add_option("--quadrature", a->quadrature,
                  "ROM with this many quadrature points per grid cell (nsf rom --quadrature); "
                  "0 = every particle, the paper. Rows are labelled with it and kept beside the "
                  "others")
      ->capture_default_str()
      ->check(in_range(0, 1000));
  cmd->add_flag("--tracked", a->tracked,
                "ROM with the tracked state in place of h and l: each integration point carries "
                "its own F^E, plastic state and C (nsf rom --stress tracked --affine tracked); "
                "rows are labelled with it and kept beside the others");
  cmd->add_flag("--check", a->check,
                "Rerun the rows these options name and compare each with its stored row in "
                "DOCS/results/: every figure but the timings and memory must come out bit for "
                "bit (a regression check; stores nothing, makes no dataset or model)");
  cmd->add_flag("--beyond-sweep", a->beyond_sweep,
                "Run each scene's held-out case outside its sweep family instead (the plates "
                "squeezing deeper, the blade stopping halfway, ...; docs/ROM.md), rows labelled "
                "beyond-sweep");
  cmd->add_flag("--page-only", a->page_only,
                "Run nothing: rebuild RESULTS.md from the rows stored in docs/results/");
  add_retired_options(cmd, "report");
  cmd->callback([a] {
    a->train.steps = per_stage(a->train_size.steps, a->train.steps, "--steps");
    a->train.widths = per_stage(a->train_size.widths, a->train.widths, "--widths");
    // Line-buffered, so the step headers interleave correctly with the progress lines on stderr.
    std::setvbuf(stdout, nullptr, _IOLBF, 0);
    a->threads = set_threads(a->threads);
    run_report(*a);
  });
}

}  // namespace nsf::app
