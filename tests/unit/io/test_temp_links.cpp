// Issue #54, item 4: the temporary name every output is written under ("<out>.tmp") is created
// exclusively, never through a symbolic link planted there (the writers; the commands are
// cli/test_temp_links_cli.cpp's). Each case: a clear error naming the link, and the link's target
// untouched.
#include <gtest/gtest.h>

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

}  // namespace
