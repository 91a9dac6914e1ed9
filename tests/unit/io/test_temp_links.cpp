// Issue #54, item 4: the temporary name every output is written under ("<out>.tmp") is created
// exclusively, never through a symbolic link planted there (the writers; the commands are
// cli/test_temp_links_cli.cpp's). Each case: a clear error naming the link, and the link's target
// untouched.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include "core/error.h"
#include "core/exclusive_file.h"
#include "data/manifest.h"
#include "error_matchers.h"
#include "io/atomic_file.h"
#include "io/image.h"
#include "temp_links_fixture.h"
#include "tiny_training.h"

namespace {

namespace fs = std::filesystem;
using nsf::testing::expect_contains;
using nsf::testing::file_bytes;
using nsf::testing::temp_links::TempLinks;

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const nsf::Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "no error";
  return "";
}

TEST_F(TempLinks, AtomicFileRefusesALinkAtItsTempName) {
  const fs::path out = dir_ / "row.json";
  plant(dir_ / "row.json.tmp");
  expect_refused(error_of([&] { nsf::write_file_atomic(out.string(), "{}"); }), out);
  EXPECT_TRUE(fs::is_symlink(dir_ / "row.json.tmp")) << "the planted link is left alone";
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(TempLinks, AStaleTempFileIsReplacedNotWrittenThrough) {
  // A killed run's leftover is a regular file: removed, then the temp file is created afresh. A
  // hard link to the victim is such a file too, and unlinking it leaves the victim as it was.
  const fs::path out = dir_ / "row.json";
  fs::create_hard_link(victim(), dir_ / "row.json.tmp");
  nsf::write_file_atomic(out.string(), "{}\n");
  EXPECT_EQ(file_bytes(out), "{}\n");
  EXPECT_FALSE(fs::exists(dir_ / "row.json.tmp"));
  expect_victim_untouched();
}

TEST_F(TempLinks, ADirectoryAtTheTempNameIsRefused) {
  fs::create_directory(dir_ / "row.json.tmp");
  expect_contains(error_of([&] { nsf::write_file_atomic((dir_ / "row.json").string(), "{}"); }),
                  "not a regular file");
  EXPECT_TRUE(fs::is_directory(dir_ / "row.json.tmp"));
}

TEST_F(TempLinks, PngAndManifestWritersRefuseALink) {
  const fs::path png = dir_ / "a.png", manifest = dir_ / "manifest.json";
  plant(dir_ / "a.png.tmp");
  plant(dir_ / "manifest.json.tmp");
  expect_refused(error_of([&] { nsf::write_png(nsf::Image(4, 4, {1, 2, 3}), png.string()); }), png);
  expect_refused(
      error_of([&] { nsf::write_json_atomically(manifest.string(), nlohmann::json::object()); }),
      manifest);
}

// A device, a pipe or a directory at the output itself: the rename into place would replace it
// (as root, `-o /dev/null` replaced the device with a regular file). Refused before anything is
// written, naming the output, which is left as it was, with no temporary file beside it.
TEST_F(TempLinks, AnOutputThatIsNotARegularFileIsRefused) {
  const fs::path fifo = dir_ / "pipe.json", folder = dir_ / "folder.png";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  fs::create_directory(folder);
  const std::string e1 = error_of([&] { nsf::write_file_atomic(fifo.string(), "{}"); });
  expect_contains(e1, fifo.string());
  expect_contains(e1, "not a regular file");
  const std::string e2 = error_of([&] {
    nsf::write_png(nsf::Image(4, 4, {1, 2, 3}), folder.string());
  });
  expect_contains(e2, folder.string());
  expect_contains(e2, "is a directory");
  EXPECT_TRUE(fs::is_fifo(fifo));
  EXPECT_TRUE(fs::is_directory(folder));
  EXPECT_FALSE(fs::exists(dir_ / "pipe.json.tmp"));
  EXPECT_FALSE(fs::exists(dir_ / "folder.png.tmp"));
  // A link to the pipe stands for it; a link to a regular file is replaced by the rename, never
  // written through.
  const fs::path to_pipe = dir_ / "to_pipe.json";
  fs::create_symlink(fifo, to_pipe);
  expect_contains(error_of([&] { nsf::write_file_atomic(to_pipe.string(), "{}"); }),
                  "not a regular file");
  EXPECT_TRUE(fs::is_symlink(to_pipe));
  const fs::path link = dir_ / "linked.json";
  fs::create_symlink(victim(), link);
  nsf::write_file_atomic(link.string(), "{}\n");
  EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(link)));
  expect_victim_untouched();
}

}  // namespace
