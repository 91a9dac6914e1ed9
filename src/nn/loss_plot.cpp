#include "nn/loss_plot.h"

#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>
#include <vector>

#include "core/process.h"

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

// A private directory (mode 0700, fresh name) in the temp directory for the script and gnuplot's
// messages: their names owe nothing to the data, and no one else can put or link anything there.
class ScriptDir {
 public:
  ScriptDir() {
    std::error_code ec;
    fs::path tmp = fs::temp_directory_path(ec);
    if (ec || tmp.empty()) tmp = "/tmp";
    const std::string pattern = (fs::absolute(tmp, ec) / "nsf_loss_XXXXXX").string();
    std::vector<char> buf(pattern.begin(), pattern.end());
    buf.push_back('\0');
    if (!::mkdtemp(buf.data())) return;
    dir_ = buf.data();
    std::ofstream(script()) << kScript;
  }
  ~ScriptDir() {
    std::error_code ec;
    if (!dir_.empty()) fs::remove_all(dir_, ec);
  }
  ScriptDir(const ScriptDir&) = delete;
  ScriptDir& operator=(const ScriptDir&) = delete;
  bool ok() const { return !dir_.empty(); }
  std::string script() const { return (dir_ / "loss.gp").string(); }
  std::string log() const { return (dir_ / "gnuplot.log").string(); }

 private:
  fs::path dir_;
};

}  // namespace

std::string plot_loss_curves(const std::string& csv_path, const std::string& png_path,
                             const std::string& title) {
  if (!program_exists("gnuplot")) return "gnuplot not found";
  const ScriptDir work;
  if (!work.ok()) return "no temporary directory for the gnuplot script";
  const std::string csv = plain_file_name(csv_path), png = plain_file_name(png_path);
  // Written under a temporary name and renamed when complete, like every nsf output.
  const std::string tmp = png + ".tmp";
  int status = -1;
  // pngcairo is missing in some gnuplot builds; the plain png terminal always exists.
  for (const char* terminal : {"pngcairo", "png"}) {
    status = run_program({"gnuplot", "-c", work.script(), csv, tmp, title, terminal}, work.log());
    if (status == 0) break;
  }
  std::error_code ec;
  if (status == 0) {
    fs::rename(tmp, png, ec);
    if (!ec) return "";
  }
  fs::remove(tmp, ec);
  if (status != 0) {
    const std::string why = first_line_of(work.log());
    return "gnuplot failed" + (why.empty() ? "" : " (" + why + ")");
  }
  return "cannot move " + tmp + " into place";
}

}  // namespace nsf
