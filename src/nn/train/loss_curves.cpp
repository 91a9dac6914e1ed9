// The loss curves of a run: the CSV of every optimiser step's loss (with a trailing mean), and
// the picture gnuplot draws from it (nn/train/loss_plot.h).
#include <filesystem>
#include <sstream>

#include "io/atomic_file.h"
#include "nn/train/loss_plot.h"
#include "nn/train/trainer_state.h"

namespace nsf {

namespace fs = std::filesystem;

std::string loss_csv_path_for(const std::string& model_path) {
  return (fs::path(model_path).replace_extension("").string()) + ".loss.csv";
}

namespace train {

void Trainer::write_loss_curves(TrainReport& report) const {
  report.loss_csv = loss_csv_path_for(out_);
  std::ostringstream csv;
  csv << "stage,network,step,loss,loss_smooth,lr\n";
  // A trailing mean over 50 steps: single-batch losses are too noisy to read a trend from.
  double window_sum = 0;
  std::vector<double> window;
  int last_stage = -1;
  for (const LossRow& r : history_) {
    if (r.stage != last_stage) window.clear(), window_sum = 0, last_stage = r.stage;
    window.push_back(r.loss);
    window_sum += r.loss;
    if (window.size() > 50) window_sum -= window[window.size() - 51];
    const double smooth = window_sum / double(std::min<size_t>(window.size(), 50));
    csv << r.stage + 1 << "," << kNetworkNames[r.stage] << "," << r.step << "," << r.loss << ","
        << smooth << "," << r.lr << "\n";
  }
  write_file_atomic(report.loss_csv, csv.str());
  if (history_.empty()) {  // stage 1 from a base model, maps for τ and C: nothing was stepped
    say("note: no optimiser steps in this run (coefficient maps only), so no loss curves");
    return;
  }
  const std::string png = fs::path(report.loss_csv).replace_extension(".png").string();
  const std::string no_plot =
      plot_loss_curves(report.loss_csv, png, "nsf train: " + model_.scene.scene_name);
  if (no_plot.empty())
    report.loss_png = png;
  else
    say("note: " + no_plot + ", loss curves only as CSV (" + report.loss_csv + ")");
}

}  // namespace train

}  // namespace nsf
