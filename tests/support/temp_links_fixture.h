#pragma once
// A fresh directory per test holding a victim file, and links to it planted where nsf writes its
// temporary files: the fixture of TempLinks, whose tests are unit/io/test_temp_links.cpp's (the
// writers) and cli/test_temp_links_cli.cpp's (`nsf simulate` and `nsf train`).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "cli_runner.h"
#include "error_matchers.h"
#include "tiny_training.h"

namespace nsf::testing::temp_links {

namespace fs = std::filesystem;

inline constexpr const char* kVictimText = "the victim's own contents\n";

class TempLinks : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = nsf::testing::fresh_dir(std::string("temp_links_") +
                                   ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::ofstream(victim()) << kVictimText;
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path victim() const { return dir_ / "victim.txt"; }
  // A link at `tmp` to the victim, as an attacker with write access to the output folder (or a
  // shared /tmp) would plant it.
  void plant(const fs::path& tmp) const { fs::create_symlink(victim(), tmp); }
  void expect_victim_untouched() const { EXPECT_EQ(file_bytes(victim()), kVictimText); }
  // The refusal names the link; the final name was not made into a link to the victim.
  void expect_refused(const std::string& message, const fs::path& out) const {
    expect_contains(message, "symbolic link");
    expect_victim_untouched();
    EXPECT_FALSE(fs::is_symlink(out)) << out;
  }
  fs::path dir_;
};

}  // namespace nsf::testing::temp_links
