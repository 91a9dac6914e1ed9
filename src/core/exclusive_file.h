#pragma once
// Temporary files created safely. Every nsf output is written under a temporary name and renamed
// into place; that name is predictable ("<out>.tmp"), so it must never be opened if something
// already sits there: a symbolic link planted at it would make the write land in the link's target.
// create_exclusive() opens with O_CREAT | O_EXCL | O_NOFOLLOW, which refuses any existing name,
// links included. A regular file there is a temp file an earlier, killed run left behind: it is
// removed first (the name, never what it might point to). A symbolic link or anything other than a
// regular file is refused with an error naming it, and left alone.
#include <string>

namespace nsf {

// Fails naming `path` when something other than a regular file sits there (a device such as
// /dev/null, a directory, a pipe, or a symbolic link to one, such as /dev/stdout): the write's
// rename would replace it. A link to a regular file, or a dangling one, is replaced by the rename.
void check_replaceable(const std::string& path);

// check_replaceable(dest), the name `tmp` will be renamed to; then removes a stale regular file at
// `tmp`, and fails naming `tmp` if a symbolic link, a directory or another non-regular file is
// there. For writers whose library creates the file itself with O_EXCL (HDF5's H5F_ACC_EXCL).
void clear_stale_temp(const std::string& tmp, const std::string& dest);

// clear_stale_temp(), then creates `tmp` exclusively for writing (mode 0666 less the umask).
// Returns the file descriptor (close-on-exec); fails naming `tmp` when it cannot.
int create_exclusive(const std::string& tmp, const std::string& dest);

// A directory only this process uses (mkdtemp: a fresh name, mode 0700) in the system's temp
// directory, removed with everything in it on destruction. For programs nsf runs (ffmpeg,
// gnuplot) that write files by name: they write here, where no one else can put a link.
class PrivateDir {
 public:
  explicit PrivateDir(const std::string& prefix);  // fails naming the temp directory
  ~PrivateDir();
  PrivateDir(const PrivateDir&) = delete;
  PrivateDir& operator=(const PrivateDir&) = delete;
  std::string path(const std::string& name) const { return dir_ + "/" + name; }

 private:
  std::string dir_;
};

// The whole contents of a file (binary); fails naming it.
std::string read_file_bytes(const std::string& path);

}  // namespace nsf
