// `nsf export run.h5 ... --format vtu --out dir/`: runs' frames for ParaView, Blender, Houdini or
// meshio.
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
#include "app/export_sources.h"
#include "app/option_checks.h"
#include "core/error.h"
#include "core/path_clash.h"
#include "core/progress.h"
#include "io/frame_range.h"
#include "io/ply_writer.h"
#include "io/position_check.h"
#include "io/run_reader.h"
#include "io/vtk_writer.h"
#include "io/xdmf_series.h"

namespace nsf::app {

namespace {

namespace fs = std::filesystem;

struct ExportArgs {
  std::vector<std::string> runs;
  std::string out, format = "vtu", frames;
  bool double_positions = false, quiet = false;
  int threads = 0;  // accepted, as by every command; export runs on one thread
};

// "<run>_0012.vtu.tmp", "<run>.pvd.tmp", "<run>.vtk.series.tmp", "<run>.series.h5.tmp",
// "<run>.series.xdmf.tmp" (not another run's).
bool is_stale_temp_of(const std::string& name, const std::string& run) {
  for (const char* collection :
       {".pvd.tmp", ".vtk.series.tmp", ".series.h5.tmp", ".series.xdmf.tmp"})
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

std::string run_name(const std::string& run) {
  return fs::path(run).stem().string();
}

// Two inputs whose files would carry the same names: sweeps name their runs alike in every folder.
void refuse_same_names(const std::vector<std::string>& runs, const ExportArgs& a) {
  for (size_t i = 0; i < runs.size(); ++i)
    for (size_t j = 0; j < i; ++j) {
      if (same_file(runs[i], runs[j]))
        fail("the run '", runs[j], "' is given twice ('", runs[i], "')");
      if (run_name(runs[i]) == run_name(runs[j]))
        fail("the runs '", runs[j], "' and '", runs[i], "' have the same name '", run_name(runs[i]),
             "', so their files in --out '", a.out,
             "' would have the same names: export them into different folders");
    }
}

struct Input {
  std::string path;
  RunReader run;
  std::vector<size_t> frames;
};

// One run's frames, as files named after the run and numbered by run frame, so sand_0012.vtu is
// frame 12 of sand.h5 whatever --frames picked, plus the collection file of the format.
void export_run(const Input& in, const ExportArgs& a) {
  const RunReader& run = in.run;
  const std::string name = run_name(in.path);
  remove_stale_temp_files(a.out, name);
  const std::string stem = (fs::path(a.out) / name).string();
  const size_t last = run.frame_count() - 1;
  const int digits = std::max(4, static_cast<int>(std::to_string(last).size()));
  std::vector<SeriesEntry> series;
  std::unique_ptr<XdmfSeriesWriter> xdmf;
  if (a.format == "xdmf")
    xdmf = std::make_unique<XdmfSeriesWriter>(stem + ".series.xdmf", stem + ".series.h5",
                                              run.material(), run.object());
  Progress progress("export", static_cast<long>(in.frames.size()), "frames");
  for (size_t i = 0; i < in.frames.size(); ++i) {
    const size_t k = in.frames[i];
    char number[32];
    std::snprintf(number, sizeof number, "_%0*zu.", digits, k);
    const std::string file = name + number + a.format;
    const std::string path = (fs::path(a.out) / file).string();
    const RunFrame f = run.read_frame(k);
    check_run_positions(f.x, run.path(), k);
    char title[160];
    std::snprintf(title, sizeof title, "nsf run %s frame %zu time %.9g", run.scene_name().c_str(),
                  k, f.time);
    if (a.format == "ply") {
      write_ply(path, f, run.material(), run.object(), {a.double_positions, title});
    } else if (a.format == "vtk") {
      write_vtk_legacy(path, f, run.material(), run.object(), {title, f.time});
    } else if (a.format == "vtu") {
      write_vtu(path, f, run.material(), run.object(), {title, f.time});
    } else {
      xdmf->add_frame(k, f);
    }
    series.push_back({file, f.time});
    if (!a.quiet) progress.update(static_cast<long>(i + 1));
  }
  if (!a.quiet) progress.finish();
  if (a.format == "xdmf") {
    xdmf->finish();
    std::printf("wrote %zu frames of %s to %s.series.h5 and %s.series.xdmf (open this)\n",
                in.frames.size(), in.path.c_str(), stem.c_str(), stem.c_str());
    return;
  }
  std::printf("wrote %zu %s files of %s to %s\n", in.frames.size(), a.format.c_str(),
              in.path.c_str(), a.out.c_str());
  if (a.format == "vtu") {
    write_pvd(stem + ".pvd", series);
    std::printf("wrote %s.pvd (open this in ParaView)\n", stem.c_str());
  } else if (a.format == "vtk") {
    write_vtk_series(stem + ".vtk.series", series);
    std::printf("wrote %s.vtk.series (open this in ParaView)\n", stem.c_str());
  }
}

// All checks come before anything is written, so a bad option leaves no half-made output.
void run_export(const ExportArgs& a) {
  if (a.format != "ply" && a.format != "vtk" && a.format != "vtu" && a.format != "xdmf")
    fail("--format '", a.format, "' is not an export format; use ply, vtk, vtu or xdmf");
  for (const std::string& run : a.runs) refuse_path_clash({{"--out", a.out}}, {{"the run", run}});
  refuse_same_names(a.runs, a);
  if (a.format == "xdmf")
    for (const std::string& run : a.runs)
      if (run_name(run).find(':') != std::string::npos)
        fail("the run '", run,
             "': an XDMF file cannot name an HDF5 file whose name holds ':' "
             "(it separates the file from the dataset); rename the run or use another --format");
  std::vector<Input> inputs;
  for (const std::string& path : a.runs) {
    RunReader run(path);
    std::vector<size_t> frames =  // a malformed --frames is a usage error (exit status 2)
        parse_option_value([&] { return parse_frame_range(a.frames, run.frame_count()); });
    inputs.push_back({path, std::move(run), std::move(frames)});
  }
  ExportSources sources(a.out);
  for (const std::string& run : a.runs) sources.check(run);

  std::error_code ec;
  fs::create_directories(a.out, ec);
  if (ec) fail(a.out, ": cannot create the output directory: ", ec.message());
  sources.record(a.runs);
  for (const Input& in : inputs) export_run(in, a);
}

}  // namespace

void add_export_command(CLI::App& app) {
  auto args = std::make_shared<ExportArgs>();
  CLI::App* cmd =
      app.add_subcommand("export", "Write runs' frames as PLY, legacy VTK, VTU or XDMF files");
  cmd->add_option("runs", args->runs,
                  "Run files written by `nsf simulate`, `nsf sweep` or `nsf rom` (HDF5); runs of "
                  "the same name need different --out folders")
      ->required();
  cmd->add_option("--format,-f", args->format, "ply, vtk, vtu or xdmf (docs/VISUALISE.md)")
      ->capture_default_str()
      ->check(CLI::IsMember({"ply", "vtk", "vtu", "xdmf"}));
  cmd->add_option("--out,-o", args->out, "Output directory")->required();
  cmd->add_option("--frames", args->frames, "Frames a:b:step, Python slice rules (default: all)");
  cmd->add_flag("--double", args->double_positions, "PLY positions as double, not float");
  add_threads_option(cmd, args->threads, "Accepted as by every command; export runs on one thread");
  add_quiet_flag(cmd, args->quiet);
  cmd->callback([args] { run_export(*args); });
}

}  // namespace nsf::app
