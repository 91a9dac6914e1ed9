// `nsf export run.h5 --format vtu --out dir/`: a run's frames for ParaView, Blender or Houdini.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "app/commands.h"
#include "core/error.h"
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
};

// All checks come before anything is written, so a bad option leaves no half-made output.
void run_export(const ExportArgs& a) {
  if (a.format != "ply" && a.format != "vtk" && a.format != "vtu")
    fail("--format '", a.format, "' is not an export format; use ply, vtk or vtu");
  const RunReader run(a.run);
  const std::vector<size_t> frames = parse_frame_range(a.frames, run.frame_count());
  std::error_code ec;
  fs::create_directories(a.out, ec);
  if (ec) fail(a.out, ": cannot create the output directory: ", ec.message());

  // Files are numbered by run frame, so frame_0012.vtu is frame 12 whatever --frames picked.
  const size_t last = run.frame_count() - 1;
  const int digits = std::max(4, static_cast<int>(std::to_string(last).size()));
  std::vector<SeriesEntry> series;
  Progress progress("export", static_cast<long>(frames.size()), "frames");
  for (size_t i = 0; i < frames.size(); ++i) {
    const size_t k = frames[i];
    char name[48];
    std::snprintf(name, sizeof name, "frame_%0*zu.%s", digits, k, a.format.c_str());
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
  const std::string stem = (fs::path(a.out) / fs::path(a.run).stem()).string();
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
  cmd->add_option("--format,-f", args->format, "ply, vtk or vtu")->capture_default_str();
  cmd->add_option("--out,-o", args->out, "Output directory")->required();
  cmd->add_option("--frames", args->frames, "Frames a:b:step, Python slice rules (default: all)");
  cmd->add_flag("--double", args->double_positions, "PLY positions as double, not float");
  cmd->add_flag("--quiet,-q", args->quiet, "No progress line");
  cmd->callback([args] { run_export(*args); });
}

}  // namespace nsf::app
