// What `nsf` says about itself (issue #53, "CLI"): a suggestion for a mistyped command, --version
// with what it was built from, and the manual page and bash completion made from its own options.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "app/cli_help.h"
#include "cli_runner.h"
#include "core/isa.h"
#include "error_matchers.h"

namespace {

using nsf::testing::expect_contains;
using nsf::testing::run_cli;

TEST(CliHelp, AMistypedCommandGetsTheNearestNameAndExitsAsAUsageError) {
  const std::vector<std::string> names = {"simulate", "sweep", "train", "generalize", "serve"};
  EXPECT_EQ(nsf::app::nearest_name("simulat", names), "simulate");
  EXPECT_EQ(nsf::app::nearest_name("swep", names), "sweep");
  EXPECT_EQ(nsf::app::nearest_name("gen", names), "generalize");  // a beginning
  EXPECT_EQ(nsf::app::nearest_name("xyzzy", names), "");
  std::string out;
  EXPECT_EQ(run_cli("simulat scene.json", out), 2);
  expect_contains(out, "'simulat' is not an nsf command; did you mean 'simulate'?");
  EXPECT_EQ(run_cli("xyzzy", out), 2);
  EXPECT_EQ(out.find("did you mean"), std::string::npos) << out;
  // Options too; a value that begins with '-' (a slice, a negative number) is no option.
  EXPECT_EQ(run_cli("sweep scene.json -o d --jbos 2", out), 2);
  expect_contains(out, "'--jbos' is not an option of 'nsf sweep'; did you mean '--jobs'?");
  EXPECT_EQ(run_cli("export /no/such/run.h5 --frames -3: -f vtu -o /no/such/dir", out), 1);
  expect_contains(out, "no such file");
  EXPECT_EQ(run_cli("rom /no/such.nsf /no/such.json --mu -0.5 -j2", out), 1);
  EXPECT_EQ(out.find("usage error"), std::string::npos) << out;
}

TEST(CliHelp, VersionSaysWhatTheToolWasBuiltFrom) {
  std::string out;
  ASSERT_EQ(run_cli("--version", out), 0) << out;
  for (const char* part : {"nsf " NSF_VERSION "\n", "commit: ", "compiler: ", "build: ",
                           "instruction set: ", "OpenMP: ", "LibTorch: ", "CUDA: "})
    expect_contains(out, part);
    // Which clone of the hot kernels the loader picked on this CPU (src/core/isa.h).
#if defined(NSF_HAS_CLONES)
  expect_contains(out, "hot kernels (P2G, G2P, the ROM's products): x86-64-v");
#else
  expect_contains(out, "hot kernels (P2G, G2P, the ROM's products): as built");
#endif
}

TEST(CliHelp, TheManualPageAndTheCompletionCoverEveryCommand) {
  std::string man, completion;
  ASSERT_EQ(run_cli("man", man), 0) << man;
  ASSERT_EQ(run_cli("completion bash", completion), 0) << completion;
  expect_contains(man, ".TH NSF 1");
  for (const char* cmd : {"simulate", "sweep", "train", "rom", "generalize", "serve", "export"}) {
    expect_contains(man, std::string(".SS ") + cmd + "\n");
    expect_contains(completion, std::string("    ") + cmd + ") words=\"");
  }
  expect_contains(man, "\\-\\-latent\\-prior");  // an option, escaped for roff
  const auto dir = nsf::testing::fresh_dir("completion");
  const std::string script = (dir / "nsf.bash").string();
  std::ofstream(script) << completion;
  const std::string probe = "bash -c 'source " + script +
                            "; COMP_WORDS=(nsf rom --latent-p); COMP_CWORD=2; _nsf; "
                            "echo \"${COMPREPLY[*]}\"'";
  FILE* p = ::popen(probe.c_str(), "r");
  ASSERT_NE(p, nullptr);
  char line[256] = "";
  ASSERT_NE(std::fgets(line, sizeof line, p), nullptr);
  ::pclose(p);
  EXPECT_EQ(std::string(line), "--latent-prior\n");
  std::string bad;
  EXPECT_EQ(run_cli("completion zsh", bad), 2) << bad;
  std::filesystem::remove_all(dir);
}

}  // namespace
