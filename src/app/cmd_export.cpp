// `nsf export run.h5 --format vtu --out dir/`: a run's frames for ParaView, Blender or Houdini.
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <system_error>
#include <vector>

#include "app/commands.h"
#include "app/common_options.h"
#include "core/error.h"
#include "core/path_clash.h"
#include "core/progress.h"
#include "io/frame_range.h"
#include "io/ply_writer.h"
#include "io/position_check.h"
#include "io/run_reader.h"
#include "io/vtk_writer.h"

namespace nsf::app {

namespace {

namespace fs = std::filesystem;

struct ExportArgs {
  std::string run, out, format = "vtu", frames;
  bool double_positions = false, quiet = false;
  int threads = 0;  // accepted, as by every command; export runs on one thread
};

// "<run>_0012.vtu.tmp", "<run>.pvd.tmp", "<run>.vtk.series.tmp" (not another run's).
bool is_stale_temp_of(const std::string& name, const std::string& run) {
  for (const char* collection : {".pvd.tmp", ".vtk.series.tmp"})
    if (name == run + collection) return true;
  if (name.rfind(run + "_", 0) != 0) return false;
  const size_t digits = run.size() + 1, dot = name.find('.', digits);
  if (dot == std::string::npos || dot == digits) return false;
  for (size_t i = digits; i < dot; ++i)
    if (!std::isdigit(static_cast<unsigned char>(name[i]))) return false;
  const std::string rest = name.substr(dot);
  return rest == ".ply.tmp" || rest == ".vtk.tmp" || rest == ".vtu.tmp";
}

// Files of that kind left in `dir` by an export of the same run that was killed
// (SIGKILL; other signals remove their own): a new export would not overwrite those of frames it
// does not write.
void remove_stale_temp_files(const std::string& dir, const std::string& run_name) {
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec)) {
    if (is_stale_temp_of(e.path().filename().string(), run_name) && e.is_regular_file(ec))
      fs::remove(e.path(), ec);
  }
}

// All checks come before anything is written, so a bad option leaves no half-made output.
void run_export(const ExportArgs& a) {
  if (a.format != "ply" && a.format != "vtk" && a.format != "vtu")
    fail("--format '", a.format, "' is not an export format; use ply, vtk or vtu");
  refuse_path_clash({{"--out", a.out}}, {{"the run", a.run}});
  const RunReader run(a.run);
  if (run.frame_count() == 0) fail(a.run, ": the run has no frames");
  const std::vector<size_t> frames =  // a malformed --frames is a usage error (exit status 2)
      parse_option_value([&] { return parse_frame_range(a.frames, run.frame_count()); });
  std::error_code ec;
  fs::create_directories(a.out, ec);
  if (ec) fail(a.out, ": cannot create the output directory: ", ec.message());

  // Files are named after the run and numbered by run frame, so sand_0012.vtu is frame 12 of
  // sand.h5 whatever --frames picked, and a second run exported into the same folder writes its
  // own files and collection instead of overwriting the first one's.
  const std::string run_name = fs::path(a.run).stem().string();
  remove_stale_temp_files(a.out, run_name);
  const size_t last = run.frame_count() - 1;
  const int digits = std::max(4, static_cast<int>(std::to_string(last).size()));
  std::vector<SeriesEntry> series;
  Progress progress("export", static_cast<long>(frames.size()), "frames");
  for (size_t i = 0; i < frames.size(); ++i) {
    const size_t k = frames[i];
    char number[32];
    std::snprintf(number, sizeof number, "_%0*zu.", digits, k);
    const std::string name = run_name + number + a.format;
    const std::string path = (fs::path(a.out) / name).string();
    const RunFrame f = run.read_frame(k);
    check_run_positions(f.x, run.path(), k);
    char title[160];
    std::snprintf(title, sizeof title, "nsf run %s frame %zu time %.9g", run.scene_name().c_str(),
                  k, f.time);
    if (a.format == "ply") {
      write_ply(path, f, run.material(), run.object(), {a.double_positions, title});
    } else if (a.format == "vtk") {
      write_vtk_legacy(path, f, run.material(), run.object(), {title, f.time});
    } else {
      write_vtu(path, f, run.material(), run.object(), {title, f.time});
    }
    series.push_back({name, f.time});
    if (!a.quiet) progress.update(static_cast<long>(i + 1));
  }
  if (!a.quiet) progress.finish();
  std::printf("wrote %zu %s files to %s\n", frames.size(), a.format.c_str(), a.out.c_str());
  const std::string stem = (fs::path(a.out) / run_name).string();
  if (a.format == "vtu") {
    write_pvd(stem + ".pvd", series);
    std::printf("wrote %s.pvd (open this in ParaView)\n", stem.c_str());
  } else if (a.format == "vtk") {
    write_vtk_series(stem + ".vtk.series", series);
    std::printf("wrote %s.vtk.series (open this in ParaView)\n", stem.c_str());
  }
}

}  // namespace

void add_export_command(CLI::App& app) {
  auto args = std::make_shared<ExportArgs>();
  CLI::App* cmd =
      app.add_subcommand("export", "Write a run's frames as PLY, legacy VTK or VTU files");
  cmd->add_option("run", args->run, "Run file written by `nsf simulate` (HDF5)")->required();
  cmd->add_option("--format,-f", args->format, "ply, vtk or vtu")
      ->capture_default_str()
      ->check(CLI::IsMember({"ply", "vtk", "vtu"}));
  cmd->add_option("--out,-o", args->out, "Output directory")->required();
  cmd->add_option("--frames", args->frames, "Frames a:b:step, Python slice rules (default: all)");
  cmd->add_flag("--double", args->double_positions, "PLY positions as double, not float");
  add_threads_option(cmd, args->threads, "Accepted as by every command; export runs on one thread");
  add_quiet_flag(cmd, args->quiet);
  cmd->callback([args] { run_export(*args); });
}

}  // namespace nsf::app
