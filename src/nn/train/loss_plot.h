#pragma once
// The training loss curves as a picture: gnuplot draws the CSV the trainer writes
// (stage,network,step,loss,loss_smooth,lr; one curve per network from loss_smooth).
#include <string>

namespace nsf {

// Writes `png_path` from `csv_path`, titled `title`. Returns "" on success, otherwise why there is
// no picture (gnuplot missing or failing), for a note to the user; the CSV is never touched.
// The paths and the title may hold any characters (they come from scene names and --out): they
// reach gnuplot as string arguments of a fixed script, never as shell or gnuplot program text.
std::string plot_loss_curves(const std::string& csv_path, const std::string& png_path,
                             const std::string& title);

}  // namespace nsf
