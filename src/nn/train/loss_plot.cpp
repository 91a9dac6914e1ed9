#include "nn/train/loss_plot.h"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>
#include <vector>

#include "core/error.h"
#include "core/exclusive_file.h"
#include "core/process.h"
#include "io/atomic_file.h"

namespace nsf {

namespace {

namespace fs = std::filesystem;

// The whole gnuplot program. It contains no data: `gnuplot -c script csv png title terminal`
// hands the four strings in as ARG1..ARG4, and the script only ever uses them as string values,
// so a quote, `;`, `system "..."` or newline in a scene name or path stays text.
constexpr const char* kScript = R"(# nsf loss curves: ARG1 CSV, ARG2 PNG, ARG3 title, ARG4 terminal
if (ARG4 eq "png") {
  set terminal png size 900,500 noenhanced
} else {
  set terminal pngcairo size 900,500 noenhanced
}
set output ARG2
set datafile separator ','
set logscale y
set grid
set key top right
set xlabel 'optimiser step'
set ylabel 'normalised MSE'
set title ARG3 noenhanced
f = ARG1
plot f every ::1 using 3:($1==1?$5:1/0) with lines lw 2 title 'g (deformation + e)', \
     f every ::1 using 3:($1==2?$5:1/0) with lines lw 2 title 'h (stress)', \
     f every ::1 using 3:($1==3?$5:1/0) with lines lw 2 title 'l (affine)'
)";

// gnuplot reads a file name that starts with '<' as a command to run, and an output name that
// starts with '|' as a pipe to one. An absolute path starts with '/', so it is only ever a file.
std::string plain_file_name(const std::string& path) {
  return fs::absolute(path).lexically_normal().string();
}

std::string first_line_of(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  return line;
}

}  // namespace

std::string plot_loss_curves(const std::string& csv_path, const std::string& png_path,
                             const std::string& title) {
  if (!program_exists("gnuplot")) return "gnuplot not found";
  try {
    // The script, gnuplot's messages and its picture live in a private directory (mode 0700, a
    // fresh name): their names owe nothing to the data, and no one else can put or link anything
    // there. The picture then reaches png_path like every nsf output: an exclusive temp file,
    // renamed.
    const PrivateDir work("nsf_loss");
    const std::string script = work.path("loss.gp"), log = work.path("gnuplot.log"),
                      plot = work.path("loss.png");
    write_file_atomic(script, kScript);
    const std::string csv = plain_file_name(csv_path);
    int status = -1;
    // pngcairo is missing in some gnuplot builds; the plain png terminal always exists.
    for (const char* terminal : {"pngcairo", "png"}) {
      status = run_program({"gnuplot", "-c", script, csv, plot, title, terminal}, log);
      if (status == 0) break;
    }
    if (status != 0) {
      const std::string why = first_line_of(log);
      return "gnuplot failed" + (why.empty() ? "" : " (" + why + ")");
    }
    write_file_atomic(png_path, read_file_bytes(plot));
  } catch (const Error& e) {
    return e.what();  // a note, like a missing gnuplot: the model is what matters
  }
  return "";
}

}  // namespace nsf
