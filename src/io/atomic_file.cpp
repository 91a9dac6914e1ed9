#include "io/atomic_file.h"

#include <filesystem>
#include <system_error>

#include "core/error.h"

namespace nsf {

namespace fs = std::filesystem;

AtomicFile::AtomicFile(std::string path)
    : path_(std::move(path)), tmp_(path_ + ".tmp"), registration_(tmp_) {
  out_.open(tmp_, std::ios::binary | std::ios::trunc);
  if (!out_) fail(path_, ": cannot create ", tmp_);
}

AtomicFile::~AtomicFile() {
  if (committed_) return;
  out_.close();
  std::error_code ignored;
  fs::remove(tmp_, ignored);
}

void AtomicFile::commit() {
  out_.close();
  if (out_.fail()) fail(path_, ": write failed (disk full?)");
  std::error_code ec;
  fs::rename(tmp_, path_, ec);
  if (ec) fail(path_, ": cannot move ", tmp_, " into place: ", ec.message());
  registration_.release();
  committed_ = true;
}

void write_file_atomic(const std::string& path, const std::string& contents) {
  AtomicFile f(path);
  f.stream().write(contents.data(), static_cast<std::streamsize>(contents.size()));
  f.commit();
}

}  // namespace nsf
