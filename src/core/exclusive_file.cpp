#include "core/exclusive_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <system_error>
#include <vector>

#include "core/error.h"

namespace nsf {

namespace fs = std::filesystem;

void check_replaceable(const std::string& path) {
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0) {
    if (errno == ENOENT) return;
    fail("cannot inspect the output path ", path, ": ", std::strerror(errno));
  }
  // A link is replaced by the rename, never written through; one that stands for a device or a
  // pipe (/dev/stdout) is refused like the device.
  if (S_ISLNK(st.st_mode) && (::stat(path.c_str(), &st) != 0 || S_ISREG(st.st_mode))) return;
  if (S_ISREG(st.st_mode)) return;
  fail(path,
       S_ISDIR(st.st_mode) ? " is a directory" : " is not a regular file (a device or a pipe)",
       ": nsf writes an output under a temporary name and renames it into place, which would "
       "replace it; give a file path");
}

void clear_stale_temp(const std::string& tmp, const std::string& dest) {
  check_replaceable(dest);
  struct stat st {};
  if (::lstat(tmp.c_str(), &st) != 0) {
    if (errno == ENOENT) return;
    fail("cannot inspect the temporary file ", tmp, ": ", std::strerror(errno));
  }
  if (S_ISLNK(st.st_mode))
    fail(tmp,
         " is a symbolic link: refusing to write through it (remove it, or choose another "
         "output path)");
  if (!S_ISREG(st.st_mode))
    fail(tmp,
         " exists and is not a regular file: refusing to replace it (remove it, or choose "
         "another output path)");
  // A temp file a killed run left behind: unlinking removes the name only.
  if (::unlink(tmp.c_str()) != 0 && errno != ENOENT)
    fail("cannot remove the stale temporary file ", tmp, ": ", std::strerror(errno));
}

int create_exclusive(const std::string& tmp, const std::string& dest) {
  clear_stale_temp(tmp, dest);
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
  if (fd < 0) {
    if (errno == EEXIST)  // something appeared there since clear_stale_temp: another writer
      fail(tmp, " appeared while nsf was creating it (another process writing the same output?)");
    fail("cannot create ", tmp, ": ", std::strerror(errno));
  }
  return fd;
}

PrivateDir::PrivateDir(const std::string& prefix) {
  std::error_code ec;
  fs::path base = fs::temp_directory_path(ec);
  if (ec || base.empty()) base = "/tmp";
  const std::string pattern = (fs::absolute(base, ec) / (prefix + "_XXXXXX")).string();
  std::vector<char> buf(pattern.begin(), pattern.end());
  buf.push_back('\0');
  if (!::mkdtemp(buf.data()))
    fail("cannot create a private directory in ", base.string(), ": ", std::strerror(errno));
  dir_ = buf.data();
}

PrivateDir::~PrivateDir() {
  std::error_code ec;
  fs::remove_all(dir_, ec);
}

std::string read_file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) fail("cannot read ", path);
  // One read into a buffer of the file's size (a character-wise copy took ~1 s per 400 MB).
  const std::streamoff size = in.tellg();
  if (size < 0) fail("cannot read ", path);
  std::string bytes(static_cast<size_t>(size), '\0');
  in.seekg(0);
  if (!in.read(bytes.data(), size)) fail("cannot read ", path);
  return bytes;
}

}  // namespace nsf
