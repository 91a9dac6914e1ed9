// `nsf train` and the files it reads and writes under hostile input (issue #28, items 6-9):
// batches larger than the data or the memory, model files and checkpoints changed after they
// were written, datasets a killed sweep left incomplete, a checkpoint of a killed run. Each must
// stop with a message naming the problem and a non-zero exit, and leave the files it was given
// alone.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>

#include <chrono>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include "app/exit_codes.h"
#include "cli_child.h"
#include "error_matchers.h"
#include "tiny_training.h"

namespace {

namespace fs = std::filesystem;
using nsf::testing::expect_contains;
using nsf::testing::file_bytes;
using nsf::testing::quoted;
using nsf::testing::run_cli;
using nsf::testing::train_tiny;

class HostileTraining : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = nsf::testing::fresh_dir(std::string("hostile_train_") +
                                   ::testing::UnitTest::GetInstance()->current_test_info()->name());
    nsf::test::write_synthetic_dataset(data(), nsf::testing::kTinyParticles);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path data() const { return dir_ / "data"; }
  fs::path model() const { return dir_ / "m.nsf"; }
  fs::path dir_;
};

uint32_t le32(const std::string& b, size_t at) {
  uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(b[at + size_t(i)]);
  return v;
}

// Byte offset and size of the largest tensor record ("<archive>/data/<k>") of a model zip, from
// its central directory.
void largest_tensor(const std::string& zip, size_t& offset, size_t& size) {
  size = 0;
  for (size_t at = zip.find("PK\x01\x02"); at != std::string::npos;
       at = zip.find("PK\x01\x02", at + 4)) {
    if (at + 46 > zip.size()) break;
    const size_t csize = le32(zip, at + 20);
    const size_t nlen = le32(zip, at + 28) & 0xffff, xlen = le32(zip, at + 30) & 0xffff;
    const size_t local = le32(zip, at + 42);
    const std::string name = zip.substr(at + 46, nlen);
    if (name.find("/data/") == std::string::npos || csize <= size || local + 30 > zip.size())
      continue;
    const size_t lname = le32(zip, local + 26) & 0xffff, lextra = le32(zip, local + 28) & 0xffff;
    offset = local + 30 + lname + lextra;
    size = csize;
    (void)xlen;
  }
}

// Flips 64 bytes in the middle of the largest tensor: what a bad disk or a hostile sender does.
void flip_64_bytes_in_a_tensor(const fs::path& file) {
  std::string bytes = file_bytes(file);
  size_t offset = 0, size = 0;
  largest_tensor(bytes, offset, size);
  ASSERT_GE(size, 1024u) << "no tensor record found in " << file;
  for (size_t i = 0; i < 64; ++i) bytes[offset + size / 2 + i] ^= '\x5a';
  std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
}

// Item 6: a batch of more frames than the dataset holds, or one step over the memory budget, is
// refused before anything is allocated (it used to grow memory without bound).
TEST_F(HostileTraining, BatchesLargerThanTheDataOrTheMemoryAreRefused) {
  nsf::testing::CliResult r = train_tiny(data(), model(), "", "--frames-per-batch 49");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  expect_contains(r.output, "--frames-per-batch 49 (stage 1, deformation)");
  expect_contains(r.output, "48 training frames");
  r = train_tiny(data(), model(), "",
                 "--frames-per-batch 40 --particles-per-frame 300 --memory-budget 0.0001");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  expect_contains(r.output, "more than the memory budget");
  expect_contains(r.output, "--memory-budget");
  EXPECT_FALSE(fs::exists(model()));

  // The issue's case, and the largest count the option's range lets through, under an
  // address-space limit so that a regression fails instead of swapping the machine to death.
  for (const char* frames : {"1000000000", "1000000"}) {
    SCOPED_TRACE(frames);
    const std::string log = (dir_ / "huge.log").string();
    const pid_t pid =
        nsf::testing::spawn_cli({"train", data().string(), "--out", model().string(),
                                 "--frames-per-batch", frames, "-j", "1", "-q"},
                                log, [] {
                                  const rlimit limit{rlim_t(32) << 30, rlim_t(32) << 30};
                                  ::setrlimit(RLIMIT_AS, &limit);
                                });
    ASSERT_GT(pid, 0);
    const int status = nsf::testing::wait_child(pid);
    const std::string text = nsf::testing::read_text(log);
    ASSERT_TRUE(WIFEXITED(status)) << text;
    EXPECT_NE(WEXITSTATUS(status), 0) << text;
    // Not an internal error (bad_alloc, c10).
    EXPECT_NE(WEXITSTATUS(status), nsf::app::kExitInternal) << text;
    expect_contains(text, std::string("--frames-per-batch"));
    expect_contains(text, frames);
    EXPECT_FALSE(fs::exists(model()));
  }
}

// A map's input where the coefficients are networks (which take the latent alone) is refused
// before training, naming the flag and what it needs; nothing is written.
TEST_F(HostileTraining, AVelocityInputWithoutAMapIsRefused) {
  for (const char* flags : {"--decoder basis --coefficients network --stress-input velocity",
                            "--decoder basis --coefficients map,network --affine-input velocity"}) {
    SCOPED_TRACE(flags);
    const nsf::testing::CliResult r = train_tiny(data(), model(), std::string(flags) + " ");
    EXPECT_EQ(r.exit_code, 1) << r.output;
    expect_contains(r.output, "needs");
    expect_contains(r.output, "from a map");
    EXPECT_FALSE(fs::exists(model()));
  }
}

// Item 7: a model (or checkpoint) with 64 bytes flipped inside a weight tensor is refused on load
// by eval, by --base-model and by --resume; it used to load and give errors of 1e30 %.
TEST_F(HostileTraining, AModelOrCheckpointChangedAfterWritingIsRefused) {
  nsf::testing::CliResult r = train_tiny(data(), model());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_cli("eval " + quoted(model()) + " " + quoted(data()) + " -j 1");
  ASSERT_EQ(r.exit_code, 0) << r.output;

  flip_64_bytes_in_a_tensor(model());
  r = run_cli("eval " + quoted(model()) + " " + quoted(data()) + " -j 1");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  expect_contains(r.output, "model file " + model().string() + " is damaged");
  expect_contains(r.output, "checksum");
  r = run_cli("train " + quoted(data()) + " --out " + quoted(dir_ / "m2.nsf") + " --base-model " +
              quoted(model()) + " --steps 20,5,5 --refine-latents 0 -j 1 -q");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  expect_contains(r.output, "checksum");
  EXPECT_FALSE(fs::exists(dir_ / "m2.nsf"));

  // A checkpoint: killed after 4 steps (checkpoints at 2 and 4), damaged, resumed.
  const fs::path other = dir_ / "c.nsf";
  r = train_tiny(data(), other, "--stop-after 4 --checkpoint-every 2");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const fs::path ckpt = other.string() + ".ckpt";
  ASSERT_TRUE(fs::exists(ckpt));
  flip_64_bytes_in_a_tensor(ckpt);
  r = train_tiny(data(), other, "--resume");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  expect_contains(r.output, "checkpoint " + ckpt.string() + " is damaged");
}

// Item 8: a dataset a killed sweep left incomplete is refused with the list of what is missing;
// --allow-incomplete trains on the rest, loudly. It used to train on what was there silently.
TEST_F(HostileTraining, AnIncompleteDatasetIsRefusedUnlessAllowed) {
  // The manifest of a sweep that planned 6 + 2 runs and finished 4 + 1; one listed file is gone.
  std::ofstream(data() / "manifest.json")
      << R"({"format": "nsf-sweep", "planned": {"train": 6, "test": 2}, "runs": [)"
      << R"({"file": "train_0.h5", "split": "train"}, {"file": "train_1.h5", "split": "train"},)"
      << R"({"file": "train_2.h5", "split": "train"}, {"file": "train_3.h5", "split": "train"},)"
      << R"({"file": "test_0.h5", "split": "test"}]})";
  fs::remove(data() / "train_3.h5");
  nsf::testing::CliResult r = train_tiny(data(), model());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  expect_contains(r.output, "is incomplete");
  expect_contains(r.output, "missing: train_3.h5, train_4.h5, train_5.h5, test_1.h5");
  expect_contains(r.output, "--allow-incomplete");
  EXPECT_FALSE(fs::exists(model()));

  r = train_tiny(data(), model(), "--allow-incomplete");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  expect_contains(r.output, "WARNING: dataset");
  expect_contains(r.output, "3 training runs, 1 test runs");
  EXPECT_TRUE(fs::exists(model()));
  // No scene file to run the ROM on (a synthetic dataset): trained, not calibrated, said so.
  expect_contains(r.output, "latent prior: not calibrated (the dataset's scene file is not here");

  // No manifest (the sweep was killed before writing it), and a run killed mid-write.
  fs::remove(data() / "manifest.json");
  std::ofstream(data() / "train_4.h5.tmp") << "half a run";
  r = train_tiny(data(), dir_ / "m2.nsf");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  expect_contains(r.output, "unfinished: train_4.h5.tmp");
  r = run_cli("eval " + quoted(model()) + " " + quoted(data()) + " -j 1");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  expect_contains(r.output, "is incomplete");
}

// Issue #54 item 17: a run that fails on its input (a dataset too small for the coefficient map,
// found after the first stage's checkpoint was written) leaves no checkpoint, so its retry says
// the same thing again instead of refusing "an interrupted training run". A run killed by a
// signal keeps its checkpoint.
TEST_F(HostileTraining, ARunThatFailsOnItsInputLeavesNoCheckpoint) {
  const fs::path small = dir_ / "small";
  nsf::test::write_synthetic_dataset(small, nsf::testing::kTinyParticles, 7, 2, {0.5, 1.0});
  const fs::path ckpt = model().string() + ".ckpt";
  for (int attempt = 0; attempt < 2; ++attempt) {
    SCOPED_TRACE(attempt);
    const nsf::testing::CliResult r = train_tiny(small, model());
    EXPECT_EQ(r.exit_code, 1) << r.output;
    expect_contains(r.output, "a coefficient map needs more training rows");
    EXPECT_EQ(r.output.find("interrupted training run"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(ckpt));
    EXPECT_FALSE(fs::exists(model()));
  }
  // SIGTERM once the first checkpoint is there: it stays, for --resume.
  const std::string log = (dir_ / "killed.log").string();
  const pid_t pid = nsf::testing::spawn_cli({"train",
                                             data().string(),
                                             "--out",
                                             model().string(),
                                             "-r",
                                             "2",
                                             "--depth",
                                             "2",
                                             "--widths",
                                             "64,8,8",
                                             "--encoder-hidden",
                                             "8",
                                             "--steps",
                                             "100000,5,5",
                                             "--refine-latents",
                                             "0",
                                             "-j",
                                             "1",
                                             "-q",
                                             "--checkpoint-every",
                                             "1",
                                             "--frames-per-batch",
                                             "2",
                                             "--particles-per-frame",
                                             "16"},
                                            log);
  ASSERT_GT(pid, 0);
  for (int i = 0; i < 600 && !fs::exists(ckpt); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  ASSERT_TRUE(fs::exists(ckpt)) << nsf::testing::read_text(log);
  ::kill(pid, SIGTERM);
  const int status = nsf::testing::wait_child(pid);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM) << nsf::testing::read_text(log);
  EXPECT_TRUE(fs::exists(ckpt));
}

// Item 9: without --resume, a checkpoint left by a killed run is kept and the command refused
// (it used to start afresh and overwrite it); --fresh deletes it and starts over.
TEST_F(HostileTraining, AKilledRunsCheckpointIsKeptUnlessTold) {
  nsf::testing::CliResult r = train_tiny(data(), model(), "--stop-after 4 --checkpoint-every 2");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const fs::path ckpt = model().string() + ".ckpt";
  ASSERT_TRUE(fs::exists(ckpt));
  const std::string before = file_bytes(ckpt);

  r = train_tiny(data(), model());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  expect_contains(r.output, ckpt.string() + " holds the checkpoint of an interrupted");
  expect_contains(r.output, "--resume");
  expect_contains(r.output, "--fresh");
  EXPECT_EQ(file_bytes(ckpt), before);
  EXPECT_FALSE(fs::exists(model()));

  r = train_tiny(data(), model(), "--fresh --resume");
  EXPECT_NE(r.exit_code, 0) << r.output;
  EXPECT_EQ(file_bytes(ckpt), before);

  r = train_tiny(data(), model(), "--fresh");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(model()));
  EXPECT_FALSE(fs::exists(ckpt));
}

}  // namespace
