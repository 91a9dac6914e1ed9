#include "io/atomic_file.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <streambuf>
#include <system_error>
#include <vector>

#include "core/error.h"
#include "core/exclusive_file.h"

namespace nsf {

namespace fs = std::filesystem;

// A buffered output stream over the descriptor create_exclusive() opened: std::ofstream can only
// open by name, which would follow a link swapped in after the exclusive create.
class AtomicFile::FdBuf : public std::streambuf {
 public:
  explicit FdBuf(int fd) : fd_(fd), buf_(size_t(1) << 16) {
    setp(buf_.data(), buf_.data() + buf_.size());
  }
  ~FdBuf() override { close(); }
  FdBuf(const FdBuf&) = delete;
  FdBuf& operator=(const FdBuf&) = delete;

  // Flushes and closes; false (errno kept in error()) if any write failed.
  bool close() {
    if (fd_ < 0) return error_ == 0;
    if (!flush()) error_ = error_ ? error_ : EIO;
    if (::close(fd_) != 0 && error_ == 0) error_ = errno;
    fd_ = -1;
    return error_ == 0;
  }
  int error() const { return error_; }

 protected:
  int_type overflow(int_type ch) override {
    if (!flush()) return traits_type::eof();
    if (!traits_type::eq_int_type(ch, traits_type::eof())) {
      *pptr() = traits_type::to_char_type(ch);
      pbump(1);
    }
    return traits_type::not_eof(ch);
  }
  int sync() override { return flush() ? 0 : -1; }

 private:
  bool flush() {
    const char* p = pbase();
    size_t left = size_t(pptr() - pbase());
    while (left > 0 && error_ == 0) {
      const ssize_t n = ::write(fd_, p, left);
      if (n < 0) {
        if (errno == EINTR) continue;
        error_ = errno;  // ENOSPC, EFBIG (a file-size limit), EIO
        break;
      }
      p += n;
      left -= size_t(n);
    }
    setp(buf_.data(), buf_.data() + buf_.size());
    return error_ == 0;
  }

  int fd_;
  std::vector<char> buf_;
  int error_ = 0;
};

AtomicFile::AtomicFile(std::string path)
    : path_(std::move(path)), tmp_(path_ + ".tmp"), out_(nullptr) {
  const int fd = create_exclusive(tmp_, path_);  // fails naming tmp_
  registration_ = TempFileRegistration(tmp_);
  buf_ = std::make_unique<FdBuf>(fd);
  out_.rdbuf(buf_.get());
}

AtomicFile::~AtomicFile() {
  if (committed_) return;
  buf_->close();
  std::error_code ignored;
  fs::remove(tmp_, ignored);
}

void AtomicFile::commit() {
  out_.flush();
  if (!buf_->close() || out_.fail())
    fail(path_, ": write failed (", std::strerror(buf_->error() ? buf_->error() : EIO),
         "; disk full or over a file-size limit?)");
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
