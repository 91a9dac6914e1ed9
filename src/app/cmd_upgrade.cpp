// `nsf upgrade model.nsf`: rewrites a model file in this nsf's format, in place and atomically;
// a basis model gains the run-time record that the torch-free runtime reads (docs/EMBEDDING.md).
#include <cstdio>
#include <memory>
#include <string>

#include "app/commands.h"
#include "app/common_options.h"
#include "nn/model.h"

namespace nsf::app {

namespace {

struct UpgradeArgs {
  std::string model;
  int threads = 0;
  bool quiet = false;
};

}  // namespace

void add_upgrade_command(CLI::App& app) {
  auto a = std::make_shared<UpgradeArgs>();
  CLI::App* cmd = app.add_subcommand(
      "upgrade", "Rewrite a model file in this nsf's format (adds the runtime's record)");
  cmd->add_option("model", a->model, "Model file (nsf train)")->required();
  add_threads_option(cmd, a->threads, "Accepted as by every command; upgrade runs on one thread");
  add_quiet_flag(cmd, a->quiet, "Print nothing on success");
  cmd->callback([a] {
    const NeuralModel m = NeuralModel::load(a->model);
    m.save(a->model);  // atomic: tmp + rename
    if (!a->quiet)
      std::printf("rewrote %s (%s model)%s\n", a->model.c_str(), family_name(m.config.decoder),
                  m.is_basis() ? " with its run-time record" : "");
  });
}

}  // namespace nsf::app
