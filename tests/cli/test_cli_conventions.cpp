// One command-line convention for every `nsf` command (issue #28, item 18): -j/--threads N means
// threads and defaults to all cores, sweep's parallel runs are --jobs, -q/--quiet exists
// everywhere, train, demo and report spell --steps and --widths alike, options with a fixed set
// of values list them in the help and refuse others before running, flags show no "{false}",
// and the exit status is 0 success, 1 error, 2 usage error (3 internal), as `nsf --help` says.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "app/exit_codes.h"
#include "cli_runner.h"
#include "error_matchers.h"

namespace {

namespace fs = std::filesystem;
using nsf::app::kExitError;
using nsf::app::kExitSuccess;
using nsf::app::kExitUsage;
using nsf::testing::CliResult;
using nsf::testing::expect_contains;
using nsf::testing::run_cli;

const std::vector<std::string> kCommands = {
    "simulate",      "sweep", "train",  "eval",  "rom",       "render",     "export",
    "contact-sheet", "demo",  "report", "serve", "calibrate", "generalize", "upgrade"};

const std::string kScene = NSF_SOURCE_DIR "/scenes/examples/elastic_drop.json";

// The help without its "Deprecated" group (old names that still work).
std::string current_part(const std::string& help) {
  return help.substr(0, help.find("\nDeprecated:"));
}

// The help line of `option` (the first line holding it), or "".
std::string help_line(const std::string& help, const std::string& option) {
  std::istringstream in(help);
  for (std::string line; std::getline(in, line);)
    if (line.find(option) != std::string::npos) return line;
  return "";
}

// `nsf COMMAND --help`, run once per command (each run loads LibTorch: about a second).
const CliResult& help_of(const std::string& command) {
  static std::map<std::string, CliResult> helps;
  auto it = helps.find(command);
  if (it == helps.end()) it = helps.emplace(command, run_cli(command + " --help")).first;
  return it->second;
}

class CliConventions : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = nsf::testing::fresh_dir(std::string("cli_conventions_") +
                                   ::testing::UnitTest::GetInstance()->current_test_info()->name());
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string in_dir(const std::string& name) const { return "'" + (dir_ / name).string() + "'"; }
  fs::path dir_;
};

// -j is threads on every command (default 0 = all cores: rom, demo and report used to default
// to 2), -q exists on every command (rom, eval, contact-sheet, demo and report lacked it), and
// no flag shows CLI11's "{false}" (report's --no-make did).
TEST_F(CliConventions, EveryCommandTakesThreadsAndQuietAlike) {
  for (const std::string& command : kCommands) {
    SCOPED_TRACE(command);
    const CliResult& r = help_of(command);
    ASSERT_EQ(r.exit_code, kExitSuccess) << r.output;
    const std::string threads = help_line(r.output, "-j,--threads");
    ASSERT_FALSE(threads.empty()) << r.output;
    expect_contains(threads, "INT:in 0 to 1024=0");
    expect_contains(r.output, "-q,--quiet");
    EXPECT_EQ(current_part(r.output).find("-J"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("{false}"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("{true}"), std::string::npos) << r.output;
    expect_contains(r.output, "Exit status: 0 success, 1 error, 2 usage error");
  }
  expect_contains(help_line(help_of("report").output, "--no-make"),
                  "Skip scenes without a dataset");
}

// sweep's parallel runs are --jobs (make's -j is jobs, nsf's -j is threads); the old -J still
// works, with a note, so scripts keep running.
TEST_F(CliConventions, SweepJobsAreLongOnlyAndTheOldShortNameStillWorks) {
  const CliResult& help = help_of("sweep");
  expect_contains(help_line(help.output, "--jobs"), "Simulations run at once");
  EXPECT_EQ(help_line(help.output, "--jobs").find("-J"), std::string::npos) << help.output;
  expect_contains(help.output.substr(help.output.find("\nDeprecated:")), "-J INT");
  // A bad value names the old option too.
  CliResult bad = run_cli("sweep " + in_dir("s.json") + " --out " + in_dir("d") + " -J -1");
  EXPECT_EQ(bad.exit_code, kExitUsage) << bad.output;
  expect_contains(bad.output, "nsf: usage error: -J: -1 is out of range");
  // Parsed, then stopped by the missing scene: a runtime error, so the options were accepted.
  const std::string missing = in_dir("missing.json") + " --out " + in_dir("data");
  CliResult r = run_cli("sweep " + missing + " -J 1 -j 1");
  EXPECT_EQ(r.exit_code, kExitError) << r.output;
  expect_contains(r.output, "-J is deprecated; use --jobs");
  expect_contains(r.output, "missing.json");
  r = run_cli("sweep " + missing + " --jobs 1 -j 1 -q");
  EXPECT_EQ(r.exit_code, kExitError) << r.output;
  EXPECT_EQ(r.output.find("deprecated"), std::string::npos) << r.output;
}

// train, demo and report size the networks with the same options, each one value or g,h,l (demo
// and report took exactly three; train spelled the widths --width-g/-h/-l).
TEST_F(CliConventions, TrainDemoAndReportSpellTheTrainingSizesAlike) {
  for (const std::string command : {"train", "demo", "report"}) {
    SCOPED_TRACE(command);
    const CliResult& r = help_of(command);
    expect_contains(help_line(r.output, "--steps"), "INT[,INT,INT]");
    expect_contains(r.output, "Optimiser steps per stage: one value or g,h,l");
    expect_contains(r.output, "Hidden widths of the decoders: one value or g,h,l; 0 keeps the");
    EXPECT_EQ(current_part(r.output).find("--width-g"), std::string::npos) << r.output;
  }
  // One value passes the parser (then the missing scene stops the demo: exit status 1) ...
  CliResult r = run_cli("demo --steps 5 --widths 0 -q --scene " + in_dir("missing.json") +
                        " --out " + in_dir("out"));
  EXPECT_EQ(r.exit_code, kExitError) << r.output;
  expect_contains(r.output, "missing.json");
  // ... two are a usage error naming the option, in all three commands.
  r = run_cli("demo --steps 5,6 --scene " + in_dir("missing.json"));
  EXPECT_EQ(r.exit_code, kExitUsage) << r.output;
  expect_contains(r.output, "--steps");
  expect_contains(r.output, "one value for every stage or three");
  // A second --steps is refused, not appended to the first (5 then 6,7 read as 5,6,7).
  r = run_cli("demo --steps 5 --steps 6,7 --scene " + in_dir("missing.json"));
  EXPECT_EQ(r.exit_code, kExitUsage) << r.output;
  expect_contains(r.output, "--steps");
  r = run_cli("report --widths 8,8 --scenes nothing");
  EXPECT_EQ(r.exit_code, kExitUsage) << r.output;
  expect_contains(r.output, "--widths");
  r = run_cli("train " + in_dir("data") + " --out " + in_dir("m.nsf") + " --widths 8,8");
  EXPECT_EQ(r.exit_code, kExitUsage) << r.output;
  expect_contains(r.output, "--widths");
  // The old per-decoder spelling still parses (hidden), but not beside --widths.
  r = run_cli("train " + in_dir("data") + " --out " + in_dir("m.nsf") + " --width-h 8 -q");
  EXPECT_EQ(r.exit_code, kExitError) << r.output;
  expect_contains(r.output, "does not exist");
  r = run_cli("train " + in_dir("data") + " --out " + in_dir("m.nsf") +
              " --width-h 8 --widths 0,8,0");
  EXPECT_EQ(r.exit_code, kExitUsage) << r.output;
  EXPECT_FALSE(fs::exists(dir_ / "m.nsf"));
}

struct ChoiceCase {
  std::string command;  // its --help lists the choices
  std::string option, choices;
  std::string bad;  // a command line with a value not among them
};

// Options with a fixed set of values show them by name in the help ("TEXT:{...}"), and any other
// value is a usage error before anything is read (they used to fail later, with status 1, after
// loading the model or the run, or not at all for rom's field sources until the step).
TEST_F(CliConventions, ChoicesAreListedByNameAndCheckedBeforeRunning) {
  const std::string run = in_dir("run.h5");
  const std::vector<ChoiceCase> cases = {
      {"rom", "--stress", "{basis,crom,network,tracked}",
       "rom " + in_dir("m.nsf") + " " + in_dir("s.json") + " --stress bogus"},
      {"rom", "--affine", "{basis,network,none,tracked}",
       "rom " + in_dir("m.nsf") + " " + in_dir("s.json") + " --affine bogus"},
      {"rom", "--velocity", "{latent,tracked}",
       "rom " + in_dir("m.nsf") + " " + in_dir("s.json") + " --velocity bogus"},
      {"rom", "--deformation", "{basis,network}",
       "rom " + in_dir("m.nsf") + " " + in_dir("s.json") + " --deformation bogus"},
      {"render", "--color", "{material,object,speed,stress}",
       "render " + run + " --out " + in_dir("frames") + " --color bogus"},
      {"render", "--view", "{front,side,top,iso}",
       "render " + run + " --out " + in_dir("frames") + " --view bogus"},
      {"contact-sheet", "--color", "{material,object,speed,stress}",
       "contact-sheet " + run + " --out " + in_dir("sheet.png") + " -c bogus"},
      {"export", "--format", "{ply,vtk,vtu,xdmf}",
       "export " + run + " --out " + in_dir("vtu") + " --format obj"},
      {"eval", "--split", "{test,train,all}", "eval " + in_dir("m.nsf") + " " + run + " --split x"},
      {"report", "--size", "{small,paper}", "report --size huge --page-only"},
  };
  for (const ChoiceCase& c : cases) {
    SCOPED_TRACE(c.bad);
    expect_contains(help_line(help_of(c.command).output, c.option + " TEXT:"), c.choices);
    const CliResult r = run_cli(c.bad);
    EXPECT_EQ(r.exit_code, kExitUsage) << r.output;
    expect_contains(r.output, "nsf: usage error: " + c.option);
  }
  EXPECT_FALSE(fs::exists(dir_ / "frames"));
  EXPECT_FALSE(fs::exists(dir_ / "vtu"));
}

// The options of experiments that lost were removed (docs/experiments/README.md): each still
// parses, with or without a value, only to be a usage error that names its record, and is not in
// the help.
TEST_F(CliConventions, RetiredOptionsAreUsageErrorsNamingTheirRecord) {
  const std::string rom = "rom " + in_dir("m.nsf") + " " + in_dir("s.json") + " ";
  const std::string train = "train " + in_dir("data") + " --out " + in_dir("m.nsf") + " ";
  struct Retired {
    std::string command, args, option, record;
  };
  const std::vector<Retired> cases = {
      {"rom", rom + "--linearize 0.05", "--linearize", "2026-11-22-tangent-cache.md"},
      {"rom", rom + "--linearize", "--linearize", "2026-11-22-tangent-cache.md"},
      {"rom", rom + "--flip 0.5", "--flip", "2026-11-25-flip-correction.md"},
      {"rom", rom + "--gn-threads 0", "--gn-threads", "2026-11-23-gn-threads.md"},
      {"rom", rom + "--deformation tangent", "--deformation", "2026-11-22-tangent-cache.md"},
      {"rom", rom + "--stress tangent", "--stress", "2026-11-22-tangent-cache.md"},
      {"rom", rom + "--affine tangent", "--affine", "2026-11-22-tangent-cache.md"},
      {"rom", rom + "--affine velocity", "--affine", "2026-11-22-velocity-affine.md"},
      {"report", "report --flip 0.5 --page-only", "--flip", "2026-11-25-flip-correction.md"},
      {"train", train + "--mix-frames 0.5", "--mix-frames", "2026-11-23-jelly-encoder-overfits.md"},
      {"train", train + "--base-model " + in_dir("b.nsf") + " --rom-latents " + in_dir("r"),
       "--rom-latents", "2026-11-25-rom-latents.md"},
      {"train", "train --rom-latents " + in_dir("r"), "--rom-latents", "2026-11-25-rom-latents.md"},
  };
  for (const Retired& c : cases) {
    SCOPED_TRACE(c.args);
    const CliResult r = run_cli(c.args);
    EXPECT_EQ(r.exit_code, kExitUsage) << r.output;
    expect_contains(r.output, "nsf: usage error: " + c.option);
    expect_contains(r.output, "was retired (it lost: docs/experiments/" + c.record + ")");
    EXPECT_TRUE(fs::exists(fs::path(NSF_SOURCE_DIR) / "docs/experiments" / c.record)) << c.record;
    const std::string help = help_of(c.command).output;
    if (c.option != "--deformation" && c.option != "--stress" && c.option != "--affine") {
      EXPECT_EQ(help.find(c.option + " "), std::string::npos) << help;
    }
    if (c.command == "rom") {
      EXPECT_EQ(help.find("tangent"), std::string::npos) << help;
    }
  }
  EXPECT_FALSE(fs::exists(dir_ / "m.nsf"));
}

// 0 success; 1 the work failed (a missing input, for every command alike: simulate and sweep
// used to give 105 for a missing scene); 2 the command line (CLI11's 105, 106, 109, ... before).
TEST_F(CliConventions, ExitStatusIsOneDocumentedConvention) {
  CliResult r = run_cli("--help");
  EXPECT_EQ(r.exit_code, kExitSuccess) << r.output;
  expect_contains(r.output, "Exit status: 0 success; 1 error");
  expect_contains(r.output, "2 usage error");
  expect_contains(r.output, "3 internal error");
  expect_contains(r.output, "128+N killed by signal N");
  EXPECT_EQ(run_cli("--version").exit_code, kExitSuccess);

  const std::string scene = "'" + kScene + "' --out " + in_dir("run.h5");
  const std::vector<std::string> usage = {
      "",                                         // no command
      "simulate",                                 // a missing argument
      "simulate " + scene + " --no-such-option",  // an unknown option
      "simulate " + scene + " --threads -1",      // a value out of range
      "simulate " + scene + " --threads two",     // not a number
      "render " + in_dir("run.h5"),               // a missing required option
      "train " + in_dir("d") + " -o " + in_dir("m") + " --resume --fresh",  // options that clash
  };
  for (const std::string& args : usage) {
    SCOPED_TRACE(args);
    r = run_cli(args);
    EXPECT_EQ(r.exit_code, kExitUsage) << r.output;
    expect_contains(r.output, "nsf: usage error: ");
    expect_contains(r.output, "Run with --help for more information.");
  }
  EXPECT_FALSE(fs::exists(dir_ / "run.h5"));

  const std::string missing = in_dir("missing");
  const std::vector<std::string> errors = {
      "simulate " + missing + ".json --out " + in_dir("out.h5"),
      "sweep " + missing + ".json --out " + in_dir("data"),
      "train " + missing + " --out " + in_dir("m.nsf"),
      "train " + in_dir("d") + " --out " + in_dir("m.nsf") + " --base-model " + missing + ".nsf",
      "eval " + missing + ".nsf " + missing,
      "rom " + missing + ".nsf '" + kScene + "'",
      "render " + missing + ".h5 --out " + in_dir("frames"),
      "export " + missing + ".h5 --out " + in_dir("vtu"),
      "contact-sheet " + missing + ".h5 --out " + in_dir("sheet.png"),
      "upgrade " + missing + ".nsf",
  };
  for (const std::string& args : errors) {
    SCOPED_TRACE(args);
    r = run_cli(args + " -q");
    EXPECT_EQ(r.exit_code, kExitError) << r.output;
    expect_contains(r.output, "nsf: error: ");
    expect_contains(r.output, "missing");
  }
}

}  // namespace
