#pragma once
// A file that appears under its final name only when complete: writes go to "<path>.tmp", created
// exclusively (core/exclusive_file.h: never through a link planted at that name), which commit()
// renames into place. Destroyed without commit() (an error, an exception), it deletes the temp
// file, so a reader or a viewer polling the directory never sees half a file.
#include <memory>
#include <ostream>
#include <string>

#include "core/temp_files.h"

namespace nsf {

class AtomicFile {
 public:
  explicit AtomicFile(std::string path);  // binary; fails naming the path if not writable
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  std::ostream& stream() { return out_; }
  void commit();  // flushes, checks for write errors (disk full) and renames

 private:
  class FdBuf;
  std::string path_, tmp_;
  TempFileRegistration registration_;  // a fatal signal deletes tmp_ (core/temp_files.h)
  std::unique_ptr<FdBuf> buf_;
  std::ostream out_;
  bool committed_ = false;
};

// The whole file at once.
void write_file_atomic(const std::string& path, const std::string& contents);

}  // namespace nsf
