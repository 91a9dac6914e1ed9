// `nsf contact-sheet a.h5 b.h5 ... --out sheet.png`: one row of frames per run.
#include <cstdio>
#include <string>
#include <vector>

#include "app/commands.h"
#include "app/common_options.h"
#include "core/error.h"
#include "core/path_clash.h"
#include "io/contact_sheet.h"

namespace nsf::app {

namespace {
struct SheetArgs {
  std::vector<std::string> runs;
  std::string out, color = "object", size = "480x360";
  int columns = 4;
  bool no_colliders = false;
  int threads = 0;     // accepted, as by every command; the sheet is drawn on one thread
  bool quiet = false;  // likewise: it prints no progress
};
}  // namespace

void add_contact_sheet_command(CLI::App& app) {
  auto a = std::make_shared<SheetArgs>();
  CLI::App* cmd =
      app.add_subcommand("contact-sheet", "One PNG with a row of frames for each run file");
  cmd->add_option("runs", a->runs, "Run files (HDF5)")->required();
  cmd->add_option("--out,-o", a->out, "Output PNG")->required();
  cmd->add_option("--columns", a->columns, "Frames per run, first to last")
      ->check(in_range(1, 32))
      ->capture_default_str();
  cmd->add_option("--color,-c", a->color, "Colour by material, object, speed or stress")
      ->capture_default_str()
      ->check(CLI::IsMember({"material", "object", "speed", "stress"}));
  cmd->add_option("--size", a->size, "Size of each panel, WIDTHxHEIGHT")->capture_default_str();
  cmd->add_flag("--no-colliders", a->no_colliders,
                "Draw only the particles, not the scenes' rigid colliders");
  add_threads_option(cmd, a->threads,
                     "Accepted as by every command; the sheet is drawn on one thread");
  add_quiet_flag(cmd, a->quiet, "Accepted as by every command; contact-sheet prints no progress");
  cmd->callback([a] {
    RunRenderOptions o;
    o.color = parse_color_by(a->color);
    o.colliders = !a->no_colliders;
    char x = 0, extra = 0;
    if (std::sscanf(a->size.c_str(), "%d%c%d%c", &o.width, &x, &o.height, &extra) != 3 ||
        (x != 'x' && x != 'X') || o.width < 16 || o.height < 16 || o.width > 8192 ||
        o.height > 8192)
      throw CLI::ValidationError("--size",
                                 "must be WIDTHxHEIGHT between 16 and 8192, got '" + a->size + "'");
    std::vector<NamedPath> runs;
    for (const std::string& r : a->runs) runs.push_back({"the run", r});
    refuse_path_clash({{"--out", a->out}}, runs);
    write_png(contact_sheet(a->runs, a->columns, o), a->out);
    std::printf("wrote %s (%zu runs)\n", a->out.c_str(), a->runs.size());
  });
}

}  // namespace nsf::app
